MODULE ServicePos
  ! Maintenance position copied from an IRB 1600 program: axis 3 is
  ! beyond the IRB 140's travel.
  PERS tooldata tGripper:=[TRUE,[[0,0,150],[1,0,0,0]],[1.5,[0,0,60],[1,0,0,0],0,0,0]];
  CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jMaint:=[[0,10,54.5,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveAbsJ jHome\NoEOffs, v1000, fine, tGripper;
    MoveAbsJ jMaint\NoEOffs, v200, fine, tGripper;
  ENDPROC
ENDMODULE
