MODULE Remote
    ! Positions sent by the cell PC over a socket.
    VAR robtarget cartesianTarget;
    VAR num params{7};
    PERS tooldata tPen := [TRUE,[[0,0,95],[1,0,0,0]],[0.4,[0,0,30],[1,0,0,0],0,0,0]];

    PROC main()
        WHILE TRUE DO
            cartesianTarget := [[params{1},params{2},params{3}],[params{4},params{5},params{6},params{7}],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
            MoveL cartesianTarget, v200, fine, tPen;
        ENDWHILE
    ENDPROC
ENDMODULE
