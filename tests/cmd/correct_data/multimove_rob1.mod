MODULE MainModule
  !***********************************************************
  ! T_ROB1 of a two-robot MultiMove station (RobotStudio).
  ! The operator confirms each cycle on the FlexPendant; without an
  ! answer within 30 s the cycle is stopped by S_Alarm1.
  !***********************************************************
  PERS tasks task_list{2}:=[["T_ROB1"],["T_ROB2"]];
  VAR syncident sync1;
  VAR syncident sync2;
  VAR syncident sync3;
  VAR errnum errvar;
  VAR num reg1;
  PERS tooldata tWeld:=[TRUE,[[0,0,200],[1,0,0,0]],[2,[0,0,100],[1,0,0,0],0,0,0]];
  CONST robtarget p10:=[[500,0,500],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p20:=[[550,100,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p30:=[[550,-100,400],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ p10, v1000, z50, tWeld;
    TPReadFK reg1, "Start cycle?", "Yes", stEmpty, stEmpty, stEmpty, "No"\MaxTime:=30\BreakFlag:=errvar;
    IF errvar=ERR_TP_MAXTIME S_Alarm1;
    WaitSyncTask sync1, task_list;
    SyncMoveOn sync2, task_list;
    MoveL p20\ID:=10, v500, fine, tWeld;
    MoveL p30\ID:=20, v500, fine, tWeld;
    SyncMoveOff sync3;
    MoveJ p10, v1000, fine, tWeld;
  ENDPROC

  PROC S_Alarm1()
    TPWrite "No answer within 30 s: cycle stopped";
    Stop;
    EXIT;
  ENDPROC
ENDMODULE
