MODULE ServicePositions
    ! Axis positions for service and calibration: MoveAbsJ with declared,
    ! array and inline jointtargets, MoveExtJ-free single robot.
    CONST jointtarget jHome := [[0, 0, 0, 0, 30, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    CONST jointtarget jService := [[-90, -20, 15, 0, 45, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    CONST jointtarget jCalib{3} := [
        [[30, 20, -40, 50, 60, 70], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]],
        [[-45, 10, -10, -60, 45, -90], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]],
        [[60, -15, 5, 90, -30, 180], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]]];
    CONST robtarget pCheck := [[600, 0, 500], [0.707107, 0, 0.707107, 0], [0, -2, -2, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];

    PROC rCalibrate()
        VAR num k;
        MoveAbsJ jHome\NoEOffs, v1000, fine, tool0;
        FOR k FROM 1 TO Dim(jCalib, 1) DO
            MoveAbsJ jCalib{k}, v200, fine, tool0;
            WaitTime \InPos, 2;
        ENDFOR
        MoveAbsJ [[0, 25, 10, 0, 55, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]]\NoEOffs, v500, z50, tool0;
        MoveJ pCheck, v500, fine, tool0;
        MoveAbsJ jService, v500, fine, tool0\WObj:=wobj0;
    ENDPROC
ENDMODULE
