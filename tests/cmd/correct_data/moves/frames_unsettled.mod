MODULE PickCell
  !***********************************************************
  ! The gripper is picked from a tool changer at run time: the
  ! tool each pick moves with is read from the rack.
  !***********************************************************
  PERS tooldata tGripA:=[TRUE,[[0,0,160],[1,0,0,0]],[0.8,[0,0,50],[1,0,0,0],0,0,0]];
  PERS tooldata tRack{2}:=[[TRUE,[[0,0,160],[1,0,0,0]],[0.8,[0,0,50],[1,0,0,0],0,0,0]],[TRUE,[[0,0,210],[1,0,0,0]],[1.0,[0,0,70],[1,0,0,0],0,0,0]]];
  VAR num nSlot:=1;
  CONST robtarget pPick:=[[520,-80,260],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPlace:=[[520,120,260],[0,0,1,0],[0,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pHome:=[[450,0,550],[0,0,1,0],[0,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ pHome, v1000, z50, tGripA;
    PickPlace pPick, tGripA;
    PickPlace pPlace, tRack{nSlot};
  ENDPROC

  PROC PickPlace(robtarget pAt, PERS tooldata tGrip)
    MoveJ Offs(pAt,0,0,60), v500, z10, tGrip;
    MoveL pAt, v100, fine, tGrip;
    MoveL Offs(pAt,0,0,60), v500, z10, tGrip;
  ENDPROC
ENDMODULE
