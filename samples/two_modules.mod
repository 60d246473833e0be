MODULE MainModule
    ! Two modules in one file: both declare p10 and a routine `main` (the
    ! second ones LOCAL: RAPID refuses one global name declared twice), so
    ! their identifiers are qualified with the module (MainModule:p10).
    CONST robtarget p10 := [[450, 100, 300], [0, 0, 1, 0], [0, 0, 0, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    CONST robtarget p20 := [[450, 200, 300], [0, 0, 1, 0], [0, 0, 0, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];

    PROC main()
        MoveJ p10, v500, z10, tool0;
        MoveL p20, v200, fine, tool0;
        MoveL [[500, 150, 350], [0, 0, 1, 0], [0, 0, 0, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]], v200, fine, tool0;
        %"place_part"%;
    ENDPROC
ENDMODULE

MODULE Station2
    LOCAL CONST robtarget p10 := [[400, -150, 250], [0, 0, 1, 0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    CONST robtarget pPlace := [[380, -250, 200], [0, 0, 1, 0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];

    LOCAL PROC main()
        MoveJ p10, v500, z10, tool0;
        MoveL pPlace, v100, fine, tool0;
        MoveL [[380, -250, 300], [0, 0, 1, 0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]], v100, fine, tool0;
    ENDPROC

    PROC place_part()
        main;
    ENDPROC
ENDMODULE
