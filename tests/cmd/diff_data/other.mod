MODULE Other
    CONST robtarget pPick:=[[450,100,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pPlace:=[[450,-100,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveL pPick, v100, fine, tool0;
        MoveL pPlace, v100, fine, tool0;
    ENDPROC
ENDMODULE
