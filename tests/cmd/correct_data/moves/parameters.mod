MODULE Gluing
    PERS tooldata tGlue := [TRUE,[[12.5,0,180],[0.9659258,0,0.258819,0]],[1.2,[0,0,50],[1,0,0,0],0,0,0]];
    CONST robtarget pStart1 := [[500,-120,310],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pStart2 := [[500,120,310],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    ! Every call passes a declared target: its moves reach those.
    PROC EG1ML(robtarget ToPoint, speeddata Speed)
        MoveL ToPoint, Speed, fine, tGlue;
    ENDPROC

    ! The caller's target comes from a function: only the run knows it.
    PROC MoveTo(robtarget pTo)
        MoveJ pTo, v500, z10, tGlue;
    ENDPROC

    PROC main()
        EG1ML pStart1, v100;
        EG1ML pStart2, v100;
        MoveTo CRobT(\Tool:=tGlue);
    ENDPROC
ENDMODULE
