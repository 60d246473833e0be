MODULE NeverSilent
    ! Every way a program holds a target that a correction can get wrong
    ! without saying so.
    CONST num nX := 400;
    PERS tooldata tGrip := [TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,1],[1,0,0,0],0,0,0]];
    ! Named constant and expression: valid RAPID, not numbers to edit.
    CONST robtarget pNamed := [[nX,0,300],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pExpr := [[400,0,-300+600],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget p10 := [[450,50,350],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    ! A pallet base reached only through Offs.
    CONST robtarget pPallet := [[500,-100,300],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    ! A placeholder the routine fills at run time.
    VAR robtarget pUnloadA := [[0,0,0],[0,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pLage1A := [[420,30,320],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    ! Taught, then changed by component at run time.
    PERS robtarget pApproach := [[430,-20,380],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    ! Wrist singular (axis 5 at 0) and a positioner's jointtarget.
    CONST jointtarget jWrist := [[-60,40,-60,45,0,-70],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST jointtarget jNamed := [[0,nX/20,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST jointtarget jPos := [[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09],[0,45,9E+09,9E+09,9E+09,9E+09]];
    PROC main()
        MoveJ pNamed, v100, z10, tGrip;
        MoveJ pExpr, v100, z10, tGrip;
        MoveL p10, v100, fine, tGrip;
        MoveL Offs(pPallet,0,0,50), v100, fine, tGrip;
        MoveL Offs(pPallet,100,0,50), v100, fine, tGrip;
        pUnloadA := pLage1A;
        MoveL pUnloadA, v100, fine, tGrip;
        pApproach.trans.z := 400;
        MoveL pApproach, v100, fine, tGrip;
        MoveAbsJ jWrist, v100, fine, tGrip;
        MoveAbsJ jPos, v100, fine, tGrip;
        MoveAbsJ jNamed, v100, fine, tGrip;
    ENDPROC
ENDMODULE
