MODULE ServicePos
  !***********************************************************
  ! Module:  ServicePos
  ! Description:
  !   Home and service positions taught in joint coordinates on
  !   the FlexPendant (Jogging > Axis 1-3 / 4-6, ModPos).
  !***********************************************************
  PERS tooldata tGripper:=[TRUE,[[0,0,150],[1,0,0,0]],[1.5,[0,0,60],[1,0,0,0],0,0,0]];
  ! Calibration-style home: wrist bent down, axis 5 at 0.
  CONST jointtarget jHome:=[[0,0,0,-90,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jHome2:=[[0,0,0,-91,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  ! Arm stretched out for the tool change, wrist singular.
  CONST jointtarget jToolChange:=[[40,90,-90,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  ! Gripper turned for the inspection camera.
  CONST jointtarget jInspect:=[[0,0,0,45,0,88.8],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jPark:=[[-30,-20,30,0,50,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveAbsJ jHome\NoEOffs, v1000, z50, tGripper;
    MoveAbsJ jHome2\NoEOffs, v1000, z50, tGripper;
    MoveAbsJ jToolChange\NoEOffs, v500, fine, tGripper;
    MoveAbsJ jInspect\NoEOffs, v500, fine, tGripper;
    MoveAbsJ jPark\NoEOffs, v1000, fine, tGripper;
  ENDPROC
ENDMODULE
