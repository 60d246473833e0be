MODULE m
  PROC main()
    IF reg1 > 0 THEN
      WaitTime 1;
  ENDPROC
ENDMODULE
