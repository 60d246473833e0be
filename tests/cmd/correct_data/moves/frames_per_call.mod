MODULE GlueCell
  !***********************************************************
  ! Two glue guns on one IRB 140, two fixtures. GlueSeam is
  ! called once per seam with the gun and fixture of that seam.
  !***********************************************************
  PERS tooldata tGunA:=[TRUE,[[0,0,180],[1,0,0,0]],[1.2,[0,0,60],[1,0,0,0],0,0,0]];
  PERS tooldata tGunB:=[TRUE,[[40,0,150],[0.9659258,0,0.258819,0]],[1.1,[0,0,50],[1,0,0,0],0,0,0]];
  TASK PERS wobjdata wFixL:=[FALSE,TRUE,"",[[420,-180,120],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  TASK PERS wobjdata wFixR:=[FALSE,TRUE,"",[[420,180,120],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pSeamL1:=[[20,30,80],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pSeamL2:=[[120,30,80],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pSeamR1:=[[20,-30,80],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pSeamR2:=[[120,-30,80],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pClear:=[[450,0,520],[0,0,1,0],[0,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    GlueSeam pSeamL1, pSeamL2, tGunA \Fix:=wFixL;
    GlueSeam pSeamR1, pSeamR2, tGunB \Fix:=wFixR;
  ENDPROC

  PROC GlueSeam(robtarget pFrom, robtarget pTo, PERS tooldata tGun, \PERS wobjdata Fix)
    ! the clearance point is taken with whichever gun is mounted
    MoveJ pClear, v1000, z50, tGun;
    MoveJ Offs(pFrom,0,0,40), v500, z10, tGun \WObj?Fix;
    MoveL pFrom, v100, fine, tGun \WObj?Fix;
    MoveL pTo, v50, fine, tGun \WObj?Fix;
    MoveL Offs(pTo,0,0,40), v200, z10, tGun \WObj?Fix;
  ENDPROC
ENDMODULE
