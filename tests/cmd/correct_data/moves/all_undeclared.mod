MODULE Grinding
    ! Target, tool and work object all live in the task's other modules.
    CONST robtarget pSafe := [[480,0,560],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC Grind_Top()
        MoveJ pSafe, v500, z20, tool0;
        MoveL TopPlateHome, v100, fine, grinder_assembly\WObj:=wobj_samplePlate;
        MoveJ pSafe, v500, z20, tool0;
    ENDPROC
ENDMODULE
