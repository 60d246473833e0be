MODULE PalletCell
  ! The place path is taught with ConfL on; a service routine, run from
  ! the pendant only, switches monitoring off for jogging-like moves.
  PERS tooldata tVac:=[TRUE,[[0,0,185],[1,0,0,0]],[1.2,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pHome:=[[515,0,600],[0.5,0,0.866025,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pAbove:=[[480,-80,320],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPlace:=[[480,-80,260],[0,0,1,0],[-1,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ pHome, v1000, z50, tVac;
    MoveJ pAbove, v1000, z10, tVac;
    MoveL pPlace, v200, fine, tVac;
    MoveL pAbove, v200, z10, tVac;
  ENDPROC

  PROC rService()
    ConfL\Off;
    MoveL pHome, v100, fine, tVac;
    ConfL\On;
  ENDPROC
ENDMODULE
