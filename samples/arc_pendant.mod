%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

module ArcWeld
  ! Written on the pendant: lowercase keywords, a %%% header (RobotWare 5
  ! style), circular moves and arc welding instructions with inline targets,
  ! and a <SMT> placeholder the operator never filled in.
  pers tooldata tWeldGun:=[TRUE,[[0,0,195.5],[0.976296,0,0.21644,0]],[2.1,[0,0,90],[1,0,0,0],0,0,0]];
  task pers wobjdata wJig:=[FALSE,TRUE,"",[[0,0,30],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  pers seamdata seam1:=[0.5,0.5,[5,0,24,120,0,0,0,0,0],0.5,0,0,0,0,[5,0,24,120,0,0,0,0,0],0,1,[5,0,24,120,0,0,0,0,0],0,0,[5,0,24,120,0,0,0,0,0],0.5];
  pers welddata weld1:=[10,0,[5,0,24,120,0,0,0,0,0],[0,0,0,0,0,0,0,0,0]];
  pers weavedata weave1:=[1,0,3,4,0,0,0,0,0,0,0,0,0,0,0];
  const robtarget pApproach:=[[450,100,210],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  proc rWeldCircle()
    movej pApproach,v500,z20,tWeldGun\wobj:=wJig;
    movel [[500,100,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v100,fine,tWeldGun\wobj:=wJig;
    movec [[550,150,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],[[500,200,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v50,z1,tWeldGun\wobj:=wJig;
    ArcLStart [[500,200,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v100,seam1,weld1,fine,tWeldGun\WObj:=wJig;
    arcl\On,[[600,200,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v20,seam1,weld1,weave1,z1,tWeldGun\wobj:=wJig;
    arcc [[650,250,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],[[600,300,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v20,seam1,weld1,weave1,z1,tWeldGun\wobj:=wJig;
    ArcLEnd [[550,300,152],[0,0,1,0],[0,-1,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v20,seam1,weld1,fine,tWeldGun\WObj:=wJig;
    <SMT>
    movel offs(pApproach,0,0,40),v500,z20,tWeldGun\wobj:=wJig;
  endproc

  proc main()
    rWeldCircle;
    waittime 0.2;
  endproc
endmodule
