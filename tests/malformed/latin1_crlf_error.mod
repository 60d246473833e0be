MODULE m
  ! Überprüfung
  PROC main()
    MoveL pÜber, v100, z10 tool0;
  ENDPROC
ENDMODULE
