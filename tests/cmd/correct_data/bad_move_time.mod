MODULE M
  CONST robtarget p1:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p2:=[[500,100,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL p1,v100,fine,tool0;
    MoveL p1,v100\T:=-2,fine,tool0;
  ENDPROC
ENDMODULE
