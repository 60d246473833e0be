MODULE StationaryGlue
  ! A glue nozzle stands in the cell; the robot holds the part and moves it
  ! past the nozzle: a stationary tool (tooldata robhold FALSE, its TCP in
  ! the world), the work object held by the robot (wobjdata robhold TRUE,
  ! its user frame in the wrist frame). The service positions lie on axis
  ! boundaries: axis 4 at 90 degrees, axis 5 at 0 (the wrist singularity),
  ! axis 6 at -90.
  PERS tooldata tNozzle := [FALSE,[[522.2169,0,285.2893],[0,0,1,0]],[0.1,[0,0,1],[1,0,0,0],0,0,0]];
  PERS wobjdata wPart := [TRUE,TRUE,"",[[0,0,150],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pStart := [[0,0,0],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pEdge1 := [[-40,0,0],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pEdge2 := [[-40,0,30],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pEdge3 := [[35,0,30],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jHome := [[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jWrist90 := [[10,20,15,90,45,-90],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jWrist0 := [[5,10,20,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jTurned := [[-30,15,10,180,30,90],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveAbsJ jHome\NoEOffs, v1000, fine, tool0;
    MoveJ pStart, v500, z20, tNozzle\WObj:=wPart;
    MoveL pEdge1, v100, z1, tNozzle\WObj:=wPart;
    MoveL pEdge2, v100, z1, tNozzle\WObj:=wPart;
    MoveL pEdge3, v100, z1, tNozzle\WObj:=wPart;
    MoveL [[35,0,0],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]], v100, fine, tNozzle\WObj:=wPart;
    MoveAbsJ jWrist90\NoEOffs, v1000, fine, tool0;
    MoveAbsJ jWrist0\NoEOffs, v1000, fine, tool0;
    MoveAbsJ jTurned\NoEOffs, v1000, fine, tool0;
    MoveAbsJ jHome\NoEOffs, v1000, fine, tool0;
  ENDPROC
ENDMODULE
