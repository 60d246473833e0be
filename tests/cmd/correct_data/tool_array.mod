MODULE ToolArray
  ! Two grippers in a tool array; the move picks one by index at run time.
  PERS tooldata tools{2} := [[TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]],
                             [TRUE,[[0,0,150],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]]];
  CONST robtarget p10 := [[450,100,300],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR num nGripper := 2;
  PROC main()
    MoveL p10, v100, fine, tools{nGripper};
  ENDPROC
ENDMODULE
