MODULE Palletizing
    PERS tooldata tVacuum := [TRUE,[[0,0,210],[1,0,0,0]],[3.5,[0,0,90],[1,0,0,0],0,0,0]];
    CONST robtarget pPickBase := [[450,-250,300],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST jointtarget jParkBase := [[0,-20,20,0,60,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC PickLayer(num nRow)
        VAR robtarget rt;
        VAR jointtarget j;
        j := jParkBase;
        j.robax.rax_1 := nRow * 10;
        MoveAbsJ j, v1000, z50, tVacuum;
        rt := Offs(pPickBase, nRow * 120, 0, 0);
        MoveL rt, v500, fine, tVacuum;
    ENDPROC

    PROC main()
        PickLayer 1;
        PickLayer 2;
    ENDPROC
ENDMODULE
