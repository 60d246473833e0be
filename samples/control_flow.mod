MODULE PalletCell (SYSMODULE)
    ! Palletising cell: every control structure of RAPID a field program
    ! uses, targets derived with Offs/RelTool/CRobT and a FUNC, optional
    ! arguments with and without a comma, 9E9 placeholders in all spellings.
    ! The pallet frame wPallet was taught equal to the base frame.
    CONST num nRows := 3;
    CONST num nCols := 2;
    LOCAL VAR num nCount := 0;
    VAR num nRetries;
    VAR intnum iStop;
    PERS tooldata tGripper := [TRUE, [[0, 0, 210], [1, 0, 0, 0]], [4.5, [0, 0, 95], [1, 0, 0, 0], 0.02, 0.02, 0.01]];
    TASK PERS wobjdata wPallet := [FALSE, TRUE, "", [[0, 0, 0], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
    CONST robtarget pPick := [[520, -180, 260], [0, 0.0, 1.0, 0], [-1, 0, -1, 0], [9E9, 9e9, 9E+9, 9E+09, 9e+09, 9.0E+09]];
    CONST robtarget pPallet := [[380, 120, 150], [0, 0, 1, 0], [0, 0, 0, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    CONST robtarget pRot := RelTool(pPick, 0, 0, -30\Rz:=45);
    VAR robtarget pCurrent;
    VAR robtarget pAbove;
    CONST speeddata vFast := [1500, 500, 5000, 1000];
    CONST zonedata zPal := [FALSE, 15, 20, 20, 2, 20, 2];
    CONST num fPrec := 3.75943E-07;
    CONST num fNeg := -245E-2;
    CONST num fHalf := .5;
    CONST num fOne := 1.;
    CONST num fExp := 3E2;

    PROC main()
        VAR num nRow;
        VAR num nCol;
        CONNECT iStop WITH trStop;
        ISignalDI diStop, 1, iStop;
        nCount := 0;
        FOR nRow FROM 1 TO nRows DO
            FOR nCol FROM 1 TO nCols STEP 1 DO
                PickPart;
                PlacePart nRow, nCol;
                Incr nCount;
            ENDFOR
        ENDFOR
        WHILE nCount > 0 DO
            nCount := nCount - 1;
            IF nCount MOD 2 = 0 WaitTime 0.1;
        ENDWHILE
        TEST nCount
        CASE 0:
            TPWrite "pallet full";
        CASE 1, 2, 3:
            TPWrite "pallet partly full";
        DEFAULT:
            Stop;
        ENDTEST
        IF nRetries > 3 THEN
            GOTO lblDone;
        ELSEIF nRetries > 1 THEN
            TPWrite "retried " \Num:=nRetries;
        ELSE
            nRetries := 0;
        ENDIF
        lblDone:
        MoveJ Home(), vFast, fine, tGripper;
    ERROR
        IF ERRNO = ERR_PATH_STOP THEN
            StartMove;
            RETRY;
        ENDIF
        RAISE;
    ENDPROC

    PROC PickPart()
        MoveJ Offs(pPick, 0, 0, 100), vFast, zPal, tGripper;
        MoveL pPick, v200, fine, tGripper;
        SetDO doGrip, 1;
        WaitTime \InPos, 0.3;
        MoveL Offs(pPick, 0, 0, 100), v500, z20, tGripper;
    BACKWARD
        MoveL Offs(pPick, 0, 0, 100), v200, fine, tGripper;
    UNDO
        SetDO doGrip, 0;
    ENDPROC

    PROC PlacePart(num row, num col)
        pAbove := Offs(pPallet, (col - 1) * 120, (row - 1) * 80, 150);
        MoveJ pAbove, vFast, z50, tGripper\WObj:=wPallet;
        MoveL Offs(pAbove, 0, 0, -150), v200, fine, tGripper \WObj:=wPallet;
        SetDO doGrip, 0;
        pCurrent := CRobT(\Tool:=tGripper \WObj:=wPallet);
        MoveL RelTool(pCurrent, 0, 0, -100), v500, z20, tGripper\WObj:=wPallet;
        MoveL [[460,240,270],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v500, z20, tGripper, \WObj:=wPallet;
    ENDPROC

    FUNC robtarget Home()
        RETURN [[515, 0, 470], [0, 0, 1, 0], [0, 0, 0, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    ENDFUNC

    FUNC robtarget Lifted(robtarget p, \num dz | switch Std)
        VAR num h := 50;
        IF Present(dz) h := dz;
        RETURN Offs(p, 0, 0, h);
    ENDFUNC

    TRAP trStop
        StopMove;
        MoveL Lifted(CRobT(\Tool:=tGripper) \dz:=20), v100, fine, tGripper;
        StartMove;
    ENDTRAP
ENDMODULE
