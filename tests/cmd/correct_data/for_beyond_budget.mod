MODULE M
  CONST robtarget p1:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    FOR i FROM 1 TO 1000000000 DO
      MoveL p1,v100,fine,tool0;
    ENDFOR
  ENDPROC
ENDMODULE
