PROC main()
  WaitTime 1;
ENDPROC
