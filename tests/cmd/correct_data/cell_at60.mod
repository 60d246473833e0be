MODULE Cell
    ! rapidtherm 0.1.0 corrected: basis=minute 60; model=embedded default model, embedded IRB 140 arm; cold=sha256:fa547465159907c0
    PERS tooldata tGrip:=[TRUE,[[0,0,120],[1,0,0,0]],[1.2,[0,0,50],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[400,-200,100],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    CONST robtarget p10:=[[99.853,150.015,379.892],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p20:=[[149.843,249.986,379.891],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveJ p10, v1000, z10, tGrip\WObj:=wTable;
        MoveL p20, v100, fine, tGrip\WObj:=wTable;
        MoveL [[449.867,99.971,499.925],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;
    ENDPROC
ENDMODULE
