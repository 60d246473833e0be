MODULE m
  MoveL p10, v100, z10, tool0;
ENDMODULE
