MODULE m
  CONST robtarget p10 := [[500, 0, 400], [0, 0, 1, 0], [0, 0, 0, 0]];
ENDMODULE
