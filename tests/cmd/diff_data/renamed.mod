MODULE Service
    CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST jointtarget jPark:=[[-90,-30,20,0,60,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pCheck2:=[[400,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveAbsJ jHome, v1000, fine, tool0;
        MoveL pCheck2, v100, fine, tool0;
        MoveAbsJ jPark, v1000, fine, tool0;
    ENDPROC
ENDMODULE
