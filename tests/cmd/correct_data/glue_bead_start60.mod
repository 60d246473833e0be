MODULE GlueBead
  ! rapidtherm 0.1.0 corrected: basis=estimate v1 sha256:aa07722648bfb83e; model=embedded default model, embedded IRB 140 arm; cold=sha256:fe225bd71c0c8b40
  ! Glue bead around a housing lid, taught on the FlexPendant.
  PERS tooldata tGlue:=[TRUE,[[0,0,185],[1,0,0,0]],[1.2,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pHome:=[[514.957,0,599.952],[0.5,0,0.866025,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pApp:=[[479.953,-79.992,319.974],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p10:=[[479.954,-79.992,259.98],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p20:=[[479.954,79.992,259.98],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p30:=[[599.945,79.993,259.978],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p40:=[[599.945,-79.993,259.978],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ pHome, v1000, z50, tGlue;
    FOR n FROM 1 TO 3 DO
      rBead;
    ENDFOR
    MoveJ pHome, v1000, fine, tGlue;
  ENDPROC

  PROC rBead()
    MoveJ pApp, v1000, z10, tGlue;
    MoveL p10, v200, fine, tGlue;
    MoveL p20, v100, z1, tGlue;
    MoveL p30, v100, z1, tGlue;
    MoveL p40, v100, z1, tGlue;
    MoveL p10, v100, fine, tGlue;
    MoveL pApp, v500, z10, tGlue;
  ENDPROC
    ! rapidtherm numbers v2 sha256:711e9387ad464f88
ENDMODULE
