MODULE JointNotAngle
  CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST jointtarget jOdd:=[[1E30,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  PROC main()
    MoveAbsJ jHome, v100, fine, tool0;
    MoveAbsJ jOdd, v100, fine, tool0;
  ENDPROC
ENDMODULE
