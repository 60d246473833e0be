MODULE WeldSeams
  !***********************************************************
  ! Arc welding with SmarTac searches and a weld-guide option.
  ! Search_1D finds the seam; ArcCalcL welds a computed path;
  ! Search_Groove belongs to an option this tool does not know.
  !***********************************************************
  PERS tooldata tWeldGun:=[TRUE,[[12.5,0,250],[1,0,0,0]],[3.2,[-60,0,180],[1,0,0,0],0,0,0]];
  PERS tooldata tLaser:=[TRUE,[[80,0,300],[1,0,0,0]],[2.5,[0,0,120],[1,0,0,0],0,0,0]];
  TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[350,-120,300],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  PERS pose peSeam1:=[[0,0,0],[1,0,0,0]];
  VAR robtarget robtStop;
  VAR robtarget robtNext;
  CONST robtarget pSearchStart:=[[60,100,80],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pSearchEnd:=[[60,100,20],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pSeamStart:=[[60,100,30],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pGroove:=[[160,100,30],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jTrackPark:=[[0,0,0,0,30,0],[500,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    Search_1D peSeam1\SearchStop:=robtStop, pSearchStart, pSearchEnd, v100, tLaser\WObj:=wTable;
    MoveL robtStop, v100, fine, tLaser\WObj:=wTable;
    Search_Groove peSeam1, pGroove, v50, tLaser\WObj:=wTable;
    ArcLStart pSeamStart, v100, seam1, weld1, fine, tWeldGun\WObj:=wTable;
    robtNext := Offs(pSeamStart, 100, 0, 0);
    ArcCalcL robtNext, v10, seam1, weld1, fine, tWeldGun\WObj:=wTable;
    ArcMoveExtJ jTrackPark, v1000, fine;
  ENDPROC
ENDMODULE
