MODULE MainModule
    ! The cell's positions are taught in the task's data module
    ! (CellData.mod), which this run does not read.
    PERS tooldata tGripper := [TRUE,[[0,0,145],[1,0,0,0]],[2.1,[0,0,60],[1,0,0,0],0,0,0]];
    CONST robtarget pApproach := [[520,-80,420],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        MoveJ pHome, v1000, z50, tGripper;
        MoveJ pApproach, v500, z10, tGripper;
        MoveL Point_Put1, v200, fine, tGripper;
        MoveJ home, v1000, z50, tGripper;
    ENDPROC
ENDMODULE
