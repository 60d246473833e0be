MODULE M
  CONST robtarget pA:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pA:=[[400,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB:=[[400,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    VAR num n;
    VAR num n;
    MoveL pA,v100,fine,tool0;
    MoveL pB,v100,fine,tool0;
  ENDPROC
ENDMODULE

MODULE Other
  CONST robtarget pB:=[[400,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  LOCAL CONST robtarget pA:=[[400,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
ENDMODULE
