MODULE m
  PROC main()
    IF reg1 > 0
      WaitTime 1;
    ENDIF
  ENDPROC
ENDMODULE
