MODULE Service
    ! Service positions taught as joints.
    CONST jointtarget jHome := [[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST jointtarget jService := [[-60,40,-60,45,20,-70],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST jointtarget jCalib := [[30,10,-20,10,45,10],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        MoveAbsJ jHome, v1000, z50, tool0;
        MoveAbsJ jService, v500, fine, tool0;
        MoveAbsJ jCalib, v500, fine, tool0;
    ENDPROC
ENDMODULE
