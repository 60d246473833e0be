MODULE 1_T_ROB2
  ! T_ROB2: picks parts from the fixture and hands them over. A module
  ! name that starts with a digit, as MultiMove station generators write.
  CONST robtarget pPick := [[480.00,-60.00,260.00],[-0.066452,0.37687,0.909844,0.16043],[-1,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPlace := [[540.00,90.00,300.00],[-0.066452,0.37687,0.909844,0.16043],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jHome := [[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR num nStatus := 0;

  PROC main()
    MoveAbsJ jHome, v1000, fine, tGripper;
    rPick \Timeout:=5;
    MoveL pPlace, v500, fine, tGripper\WObj:=wobjFixture;
  ENDPROC

  PROC rPick(\num Timeout)
    MoveJ Offs(pPick,0,0,50), v1000, z10, tGripper\WObj:=wobjFixture;
    MoveL pPick, v200, fine, tGripper\WObj:=wobjFixture;
    ! Waits as long as the caller allows, or forever when it says nothing.
    rWaitGrip \MaxTime?Timeout;
    IF nStatus = 1THEN
      MoveL Offs(pPick,0,0,50), v200, z10, tGripper\WObj:=wobjFixture;
    ENDIF
  ENDPROC

  PROC rWaitGrip(\num MaxTime)
    WaitTime\InPos, 0.2;
    nStatus := 1;
  ENDPROC
ENDMODULE
