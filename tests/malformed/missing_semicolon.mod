MODULE m
  PROC main()
    MoveL p10, v100, z10, tool0
    MoveL p20, v100, z10, tool0;
  ENDPROC
ENDMODULE
