MODULE m
  PROC main()
    TEST reg1
      WaitTime 1;
    CASE 1:
    ENDTEST
  ENDPROC
ENDMODULE
