MODULE m
  PROC main()
    WaitTime 1;
  ENDPROC
