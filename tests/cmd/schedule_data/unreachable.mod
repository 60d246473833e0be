MODULE Cell
    ! Four targets the IRB 140 cannot reach, between three it can.
    CONST robtarget pHome:=[[400,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pHuge:=[[1E200,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pFar:=[[5000,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pPick:=[[450,100,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pBehind:=[[-2000,0,500],[0,0,1,0],[1,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST jointtarget jBent:=[[0,150,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveJ pHome, v1000, fine, tool0;
        FOR i FROM 1 TO 3 DO
            MoveL pHuge, v100, fine, tool0;
            MoveL pFar, v100, fine, tool0;
            MoveL pPick, v100, fine, tool0;
        ENDFOR
        MoveJ pBehind, v1000, fine, tool0;
        MoveAbsJ jBent, v1000, fine, tool0;
        MoveJ pHome, v1000, fine, tool0;
    ENDPROC
ENDMODULE
