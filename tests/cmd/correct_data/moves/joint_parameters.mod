MODULE ServiceMoves
  !***********************************************************
  ! Park and service positions taught in joints, reached by one
  ! routine that is given the position to go to.
  !***********************************************************
  CONST jointtarget jPark:=[[0,-20,40,0,70,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jService:=[[90,10,10,0,-60,45],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR jointtarget jNow;

  PROC main()
    GoJoints jPark;
    GoJoints jService;
    jNow := CJointT();
    GoJoints jNow;
    Leave jPark;
  ENDPROC

  PROC GoJoints(jointtarget jTo)
    MoveAbsJ jTo\NoEOffs, v500, fine, tool0;
  ENDPROC

  PROC Leave(jointtarget jTo)
    MoveAbsJ jTo\NoEOffs, v200, fine, tool0;
  ENDPROC
ENDMODULE
