MODULE Cell
    ! rapidtherm 0.1.0 corrected: basis=minute 60; model=embedded default model, embedded IRB 140 arm; cold=sha256:fa547465159907c0
    PERS tooldata tGrip:=[TRUE,[[0,0,120],[1,0,0,0]],[1.2,[0,0,50],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[400,-200,100],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    CONST robtarget p10:=[[99.951,150.005,379.964],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p20:=[[149.947,249.995,379.963],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveJ p10, v1000, z10, tGrip\WObj:=wTable;
        MoveL p20, v100, fine, tGrip\WObj:=wTable;
        MoveL [[449.955,99.99,499.975],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;
    ENDPROC
    ! rapidtherm numbers v2 sha256:8262e207ab5d8df7
ENDMODULE
