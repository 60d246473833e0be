MODULE m
  VAR string s := "open;
ENDMODULE
