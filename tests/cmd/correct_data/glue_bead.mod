MODULE GlueBead
  ! Glue bead around a housing lid, taught on the FlexPendant.
  PERS tooldata tGlue:=[TRUE,[[0,0,185],[1,0,0,0]],[1.2,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pHome:=[[515,0,600],[0.5,0,0.866025,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pApp:=[[480,-80,320],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p10:=[[480,-80,260],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p20:=[[480,80,260],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p30:=[[600,80,260],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p40:=[[600,-80,260],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

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
ENDMODULE
