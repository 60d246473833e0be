MODULE Fixtures
    ! Fixture data of a two-station gluing cell: robtarget arrays sized by
    ! constants, a RECORD holding robtargets, tool and work object data.
    CONST num nStations := 2;
    CONST num nPoints := 4;

    RECORD gluepath
        robtarget start;
        robtarget finish;
        num speed;
        string label;
    ENDRECORD

    RECORD station
        gluepath path;
        jointtarget home;
        bool active;
    ENDRECORD

    PERS tooldata tGlue := [TRUE, [[0, 0, 145.2], [0.92388, 0, 0, 0.382683]], [1.8, [0, 0, 70], [1, 0, 0, 0], 0, 0, 0]];
    TASK PERS wobjdata wTable := [FALSE, TRUE, "", [[0, 0, 20], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
    LOCAL PERS wobjdata wFixture := [FALSE, TRUE, "", [[0, 0, 25], [1, 0, 0, 0]], [[10, 5, 0], [1, 0, 0, 0]]];
    CONST speeddata vGlue := [80, 200, 5000, 1000];
    CONST zonedata zGlue := [FALSE, 0.5, 1, 1, 0.1, 1, 0.1];
    ! Not a valid zonedata (six fields), harmless: never read as a target.
    CONST zonedata zOdd := [FALSE, 2, 3, 3, 0.3, 3];

    CONST robtarget pHome := [[515, 0, 610], [0.707107, 0, 0.707107, 0], [0, -2, 1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    PERS robtarget pCorner{nPoints} := [
        [[400, 50, 130], [0, 0, 1, 0], [0, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]],
        [[550, 50, 130], [0, 0, 1, 0], [0, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]],
        [[550, 150, 130], [0, 0, 1, 0], [0, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]],
        [[400, 150, 130], [0, 0, 1, 0], [0, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]]];
    VAR robtarget pGrid{nStations, 2} := [
        [[[420, 70, 105], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]],
         [[420, 130, 105], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]]],
        [[[520, 70, 105], [0, 0, 1, 0], [0, 0, -1, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]],
         [[520, 130, 105], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]]]];
    PERS gluepath gBead := [[[405, 60, 102], [0, 0, 1, 0], [0, -1, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]],
                            [[545, 60, 102], [0, 0, 1, 0], [0, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]], 60, "bead A"];
    PERS station sCell{2} := [
        [[[[410, 60, 102], [0, 0, 1, 0], [0, 0, -1, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]],
          [[540, 60, 102], [0, 0, 1, 0], [0, -1, -1, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], 50, "left"],
         [[0, 10, 20, 0, 60, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], TRUE],
        [[[[410, 140, 102], [0, 0, 1, 0], [0, -1, -1, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]],
          [[540, 140, 102], [0, 0, 1, 0], [0, 0, -1, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], 50, "right"],
         [[20, 10, 20, 0, 60, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], FALSE]];

    PROC main()
        VAR num i;
        MoveJ pHome, v1000, z50, tGlue;
        FOR i FROM 1 TO nPoints DO
            MoveL pCorner{i}, vGlue, zGlue, tGlue\WObj:=wTable;
        ENDFOR
        FOR i FROM 1 TO nStations DO
            IF sCell{i}.active THEN
                MoveL sCell{i}.path.start, v200, z5, tGlue\WObj:=wFixture;
                MoveL sCell{i}.path.finish, vGlue, fine, tGlue\WObj:=wFixture;
            ENDIF
        ENDFOR
        MoveL gBead.start, v200, z5, tGlue\WObj:=wTable;
        MoveL gBead.finish, vGlue, fine, tGlue\WObj:=wTable;
        MoveL pGrid{2, 1}, v200, z5, tGlue\WObj:=wTable;
        MoveJ pHome, v1000, fine, tGlue;
    ENDPROC
ENDMODULE
