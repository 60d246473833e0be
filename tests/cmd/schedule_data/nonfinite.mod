MODULE Cell
    ! Offsets that overflow: the targets they make are not finite.
    CONST robtarget pHome:=[[400,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST num big:=1E300;
    PROC main()
        MoveJ pHome, v1000, fine, tool0;
        MoveL Offs(pHome, big*big, 0, 0), v100, fine, tool0;
        MoveL Offs(pHome, 0, 0, -big*big), v100, fine, tool0;
        MoveL pHome, v100, fine, tool0;
    ENDPROC
ENDMODULE
