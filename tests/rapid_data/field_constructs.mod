%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE 1_T_ROB2
  ! A task module as a controller backup names it, with the constructs of
  ! ABB's system modules and of vendor add-ins that controllers load.
  PERS tooldata tGun := [TRUE,[[0,0,180],[1,0,0,0]],[2,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pWeld := [[480,-60,420],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR num status := 0;

  PROC GunMove(robtarget ToPoint, \num ID, \wobjdata WObj, \switch InPos)
    ! Conditional arguments pass the caller's optional parameters on.
    MoveL ToPoint, v200, fine, tGun \WObj?WObj;
    GunReady \ID?ID, \InPos?InPos;
    status := TcControlEquip(1\TimeOut?ID);
    IF status = 1THEN
      Stop;
    ENDIF
    FOR i FROM 1 TO 3DO
      WaitTime 0.1;
    ENDFOR
  ENDPROC

  PROC main()
    MoveL pWeld, v200, fine, tGun;
    GunMove pWeld \ID:=2;
  ENDPROC
ENDMODULE
