MODULE Comm
  ! T_COM: a static background task that talks to the cell PLC. It moves
  ! nothing; the robtarget is a message buffer the robot tasks read.
  PERS robtarget pFromPlc := [[0,0,0],[1,0,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR socketdev sock;

  PROC main()
    WHILE TRUE DO
      WaitTime 1;
    ENDWHILE
  ENDPROC
ENDMODULE
