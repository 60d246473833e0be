MODULE MainModule
  ! T_ROB1: draws the scan path on the table, then parks.
  ! tPen and wobjTable are declared in user.sys (SYSMOD).
  CONST robtarget pHome := [[515.00,0.00,592.00],[0.5,0,0.866025,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pApproach := [[500.00,141.00,300.00],[-0.066452,0.37687,0.909844,0.16043],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  ! Filled in at run time from the camera; the zeros are a placeholder.
  VAR robtarget pCamera := [[0,0,0],[0,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jPark := [[0,-20,30,0,50,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  PERS num nScanCount := 20000;
  VAR syncident sync1;
  PERS tasks tlAll{2} := [["T_ROB1"],["T_ROB2"]];

  PROC main()
    MoveJ pHome, v1000, z50, tPen;
    MoveJ pApproach, v1000, z10, tPen\WObj:=wobjTable;
    rScan;
    rCamera;
    MoveAbsJ jPark\NoEOffs, v1000, fine, tPen;
  ENDPROC

  PROC rScan(\num Count)
    VAR num n;
    n := nScanCount;
    IF Present(Count) n := Count;
    FOR i FROM 1 TO n DO
      MoveL pScan{i}, v200, z1, tPen\WObj:=wobjTable;
    ENDFOR
  ENDPROC

  PROC rCamera()
    pCamera := CRobT(\Tool:=tPen\WObj:=wobjTable);
    pCamera.trans.z := pCamera.trans.z + 20;
    MoveL pCamera, v100, fine, tPen\WObj:=wobjTable;
  ENDPROC
ENDMODULE
