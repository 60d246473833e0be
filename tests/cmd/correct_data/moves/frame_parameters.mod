MODULE SeamWeld
  ! A welding cell's seams, each welded by one procedure that is given
  ! the torch and the fixture's work object by its caller.
  PERS tooldata tTorch := [TRUE,[[0,0,180],[1,0,0,0]],[3,[0,0,100],[1,0,0,0],0,0,0]];
  PERS wobjdata wFixA := [FALSE,TRUE,"",[[400,-100,300],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pHome := [[480,-60,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pSeam1 := [[80,40,120],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pSeam2 := [[60,20,120],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC WeldTo(robtarget ToPoint, PERS tooldata Torch, \PERS wobjdata Fixture)
    MoveL ToPoint, v100, fine, Torch \WObj?Fixture;
  ENDPROC

  PROC main()
    MoveJ pHome, v1000, z50, tTorch;
    WeldTo pSeam1, tTorch \Fixture:=wFixA;
    WeldTo pSeam2, tTorch \Fixture:=wFixA;
  ENDPROC
ENDMODULE
