MODULE PalletCell
  ! Pallet cell: pick from the conveyor, place on the pallet.
  ! The place targets were taught with loose configurations, so the
  ! place path runs with ConfL\Off; the approach is a joint move.
  PERS tooldata tVac:=[TRUE,[[0,0,185],[1,0,0,0]],[1.2,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pHome:=[[515,0,600],[0.5,0,0.866025,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pAbove:=[[480,-80,320],[0,0,1,0],[-1,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPlace:=[[480,-80,260],[0,0,1,0],[-1,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ pHome, v1000, z50, tVac;
    rPlace;
    MoveJ pHome, v1000, fine, tVac;
  ENDPROC

  PROC rPlace()
    MoveJ pAbove, v1000, z10, tVac;
    ConfL\Off;
    MoveL pPlace, v200, fine, tVac;
    ConfL\On;
  ENDPROC

  PROC rService()
    ! Run from the pendant only: never called by the program.
    ConfJ\Off;
    MoveJ pHome, v500, fine, tVac;
  ENDPROC
ENDMODULE
