MODULE UR5Move
    ! A UR5 (no spherical wrist: numeric IK) moving between two targets.
    CONST robtarget pA := [[-483.9548,-292.3002,357.2888],[0,0.766044,0.642788,0],[0,-2,0,1],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pB := [[-110.6358,-276.1856,752.0865],[0.29442993,-0.24872584,-0.86327921,-0.32587647],[-1,-1,-2,5],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    PROC main()
        MoveL pA, v100, fine, tool0;
        MoveJ pB, v100, fine, tool0;
    ENDPROC
ENDMODULE
