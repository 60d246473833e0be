MODULE PickHidden
  !***********************************************************
  ! A procedure's parameter, and a routine's own variable, named
  ! as a module target: inside their routine they hide it.
  !***********************************************************
  PERS tooldata tSuction:=[TRUE,[[0,0,120],[1,0,0,0]],[0.6,[0,0,40],[1,0,0,0],0,0,0]];
  CONST robtarget pA:=[[500,0,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pB:=[[520,50,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    Pick pB;
    Pick CRobT(\Tool:=tSuction);
    Place;
  ENDPROC

  PROC Pick(robtarget pA)
    MoveL pA, v100, fine, tSuction;
  ENDPROC

  PROC Place()
    VAR robtarget pA;
    pA := Offs(CRobT(\Tool:=tSuction), 0, 0, 50);
    MoveL pA, v100, fine, tSuction;
  ENDPROC
ENDMODULE
