MODULE M
  ! r1's own pA shadows the module's within r1; r2's pB is the only one.
  CONST robtarget pA:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PERS tooldata tPen:=[TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];
  PROC r1()
    CONST robtarget pA:=[[400,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    MoveL pA,v100,fine,tPen;
  ENDPROC
  PROC r2()
    CONST robtarget pB:=[[450,-100,500],[0,0,1,0],[-1,-1,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    MoveL pB,v100,fine,tool0;
  ENDPROC
  PROC main()
    MoveL pA,v100,fine,tool0;
    r1;
    r2;
  ENDPROC
ENDMODULE
