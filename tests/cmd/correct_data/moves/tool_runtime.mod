MODULE Boxing
    PERS tooldata BoxUp := [TRUE,[[0,0,160],[1,0,0,0]],[4,[0,0,70],[1,0,0,0],0,0,0]];
    PERS tooldata BoxDown := [TRUE,[[0,0,185],[1,0,0,0]],[4,[0,0,70],[1,0,0,0],0,0,0]];
    PERS tooldata ToolActual;
    PERS wobjdata wobjConveyor := [FALSE,TRUE,"",[[600,-300,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    PERS wobjdata wobjWeldLine2;
    CONST robtarget pPick := [[50,100,200],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pPlace := [[420,200,260],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        ToolActual := BoxUp;
        wobjWeldLine2 := wobjConveyor;
        MoveL pPick, v300, fine, ToolActual\WObj:=wobjWeldLine2;
        MoveL pPlace, v300, fine, ToolActual;
        Turn;
    ENDPROC

    ! The box is turned over: the same places with the other tool.
    PROC Turn()
        ToolActual := BoxDown;
        MoveL pPlace, v300, fine, ToolActual;
    ENDPROC
ENDMODULE
