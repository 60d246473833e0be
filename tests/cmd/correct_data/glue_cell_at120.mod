MODULE GlueCell
    ! rapidtherm 0.1.0 corrected: basis=minute 120; model=embedded default model, embedded IRB 140 arm; cold=sha256:a5ff475be17f713c
    ! Gripper and glue gun on one IRB 140: parts are picked from two
    ! identical fixtures, a bead is laid in each, and the robot parks.
    PERS tooldata tGripper:=[TRUE,[[0,0,145],[1,0,0,0]],[1.8,[0,0,60],[1,0,0,0],0,0,0]];
    PERS tooldata tGlueGun:=[TRUE,[[62.5,0,210],[0.965926,0,0.258819,0]],[2.4,[20,0,90],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wFixtureA:=[FALSE,TRUE,"",[[420,-260,80],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    TASK PERS wobjdata wFixtureB:=[FALSE,TRUE,"",[[540,-100,80],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    ! Both tools park here.
    CONST robtarget pHome:=[[514.946,0,711.929],[0.5,0,0.866025,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    ! The same pick point in either fixture.
    CONST robtarget pPick:=[[59.948,40.024,24.998],[0,0,1,0],[-1,-1,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pBead{2}:=[[[39.953,20.027,29.991],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[119.944,20.027,29.989],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]]];
    CONST robtarget pApproach:=[[559.934,-79.991,419.958],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    PERS robtarget pService:=[[599.931,0,299.973],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pPurge:=[[449.95,299.963,349.959],[0,0,1,0],[0,-1,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    VAR robtarget pWipe;

    PROC main()
        MoveJ pHome, v1000, z50, tGripper;
        Pick wFixtureA;
        Pick wFixtureB;
        MoveJ pApproach, v1000, z20, tGripper;
        Glue wFixtureA;
        Glue wFixtureB;
        MoveL Offs(pApproach,0,0,50), v500, z20, tGlueGun;
        MoveJ pHome, v1000, z50, tGlueGun;
    ENDPROC

    PROC Pick(PERS wobjdata wFixture)
        MoveL pPick, v200, fine, tGripper\WObj:=wFixtureA;
        MoveL pPick, v200, fine, tGripper\WObj:=wFixtureB;
    ENDPROC

    PROC Glue(PERS wobjdata wFixture)
        MoveL pBead{1}, v100, z1, tGlueGun\WObj:=wFixtureA;
        MoveL pBead{2}, v100, fine, tGlueGun\WObj:=wFixtureA;
        MoveL pBead{1}, v100, z1, tGlueGun\WObj:=wFixtureB;
        MoveL pBead{2}, v100, fine, tGlueGun\WObj:=wFixtureB;
    ENDPROC

    PROC Service()
        MoveJ pService, v500, fine, tGripper;
        MoveJ pService, v500, fine, tGlueGun;
        pWipe := pService;
        MoveL pWipe, v50, fine, tGlueGun;
        MoveL pPurge, v200, fine, tGlueGun;
        MoveL pPurge, v200, fine, tGripper;
        Purge pPurge;
    ENDPROC

    PROC Purge(robtarget pAt)
        MoveL Offs(pAt,0,0,20), v50, fine, tGlueGun;
    ENDPROC
    ! rapidtherm numbers v2 sha256:f97ad0dfee525b96
ENDMODULE
