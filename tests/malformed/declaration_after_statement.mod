MODULE m
  PROC main()
    WaitTime 1;
    VAR num n := 2;
  ENDPROC
ENDMODULE
