MODULE Declined
    PERS tooldata tGrip:=[TRUE,[[0,0,120],[1,0,0,0]],[1.2,[0,0,50],[1,0,0,0],0,0,0]];
    CONST robtarget p10:=[[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p20:=[[520,40,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PROC main()
        MoveJ p10, v1000, z10, tGrip;
        MoveL Offs(p10,0,0,50), v100, fine, tGrip;
        MoveL p20, v100\V:=200, fine, tGrip;
        MoveL Offs(p20,0,0,50), v100, fine, tGrip;
    ENDPROC
ENDMODULE
