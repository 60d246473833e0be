MODULE m
  VAR num if := 1;
ENDMODULE
