MODULE Probe
    ! DatumZ is measured by the probe cycle; the literals read it.
    VAR num DatumZ := 250;
    VAR robtarget pDatumCenter;
    PERS tooldata tProbe := [TRUE,[[0,0,120],[1,0,0,0]],[0.8,[0,0,40],[1,0,0,0],0,0,0]];

    PROC main()
        MoveL [[400,0,DatumZ],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]], v100, fine, tProbe;
        pDatumCenter := [[0,0,DatumZ],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
        MoveL pDatumCenter, v100, fine, tProbe;
    ENDPROC
ENDMODULE
