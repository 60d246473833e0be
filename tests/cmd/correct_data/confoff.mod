MODULE Cell
    PERS tooldata tGrip:=[TRUE,[[0,0,120],[1,0,0,0]],[1.2,[0,0,50],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[400,-200,100],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    CONST robtarget p10:=[[100,150,380],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p20:=[[150,250,380],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        ConfL \Off;
        ConfJ \Off;
        MoveJ p10, v1000, z10, tGrip\WObj:=wTable;
        MoveL p20, v100, fine, tGrip\WObj:=wTable;
        MoveL [[450,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;
    ENDPROC
ENDMODULE
