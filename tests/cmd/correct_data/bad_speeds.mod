MODULE M
  CONST speeddata vZero := [0,500,5000,1000];
  CONST speeddata vNeg := [-100,500,5000,1000];
  CONST robtarget p1:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p2:=[[500,100,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL p1,v100,fine,tool0;
    MoveL p2,vZero,fine,tool0;
    MoveL p1,vNeg,fine,tool0;
  ENDPROC
ENDMODULE
