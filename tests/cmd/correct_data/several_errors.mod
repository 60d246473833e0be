MODULE Cell
    ! Three targets refused for three reasons: a run names them all.
    PERS tooldata tGrip:=[TRUE,[[0,0,120],[1,0,0,0]],[1.2,[0,0,50],[1,0,0,0],0,0,0]];
    CONST robtarget p10:=[[100,150,380],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pFar:=[[1450,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pTable:=[[150,250,380],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST jointtarget jHalf:=[[0,0,0,9E9,9E9,9E9],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveJ p10, v1000, z10, tGripper;
        MoveL pFar, v100, fine, tGrip;
        MoveL pTable, v100, fine, tGrip\WObj:=wTabel;
        MoveAbsJ jHalf, v100, fine, tGrip;
    ENDPROC
ENDMODULE
