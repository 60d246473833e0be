%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

module ArcWeld
  ! Written on the pendant: lowercase keywords, a %%% header (RobotWare 5
  ! style), circular moves and arc welding instructions with inline targets,
  ! and a <SMT> placeholder the operator never filled in.
  pers tooldata tWeldGun:=[TRUE,[[0,0,195.5],[0.976296,0,0.21644,0]],[2.1,[0,0,90],[1,0,0,0],0,0,0]];
  task pers wobjdata wJig:=[FALSE,TRUE,"",[[480,120,180],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  pers seamdata seam1:=[0.5,0.5,[5,0,24,120,0,0,0,0,0],0.5,0,0,0,0,[5,0,24,120,0,0,0,0,0],0,1,[5,0,24,120,0,0,0,0,0],0,0,[5,0,24,120,0,0,0,0,0],0.5];
  pers welddata weld1:=[10,0,[5,0,24,120,0,0,0,0,0],[0,0,0,0,0,0,0,0,0]];
  pers weavedata weave1:=[1,0,3,4,0,0,0,0,0,0,0,0,0,0,0];
  const robtarget pApproach:=[[0,0,60],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  proc rWeldCircle()
    movej pApproach,v500,z20,tWeldGun\wobj:=wJig;
    movel [[50,0,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v100,fine,tWeldGun\wobj:=wJig;
    movec [[100,50,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],[[50,100,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v50,z1,tWeldGun\wobj:=wJig;
    ArcLStart [[50,100,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v100,seam1,weld1,fine,tWeldGun\WObj:=wJig;
    arcl\On,[[150,100,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v20,seam1,weld1,weave1,z1,tWeldGun\wobj:=wJig;
    arcc [[200,150,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],[[150,200,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v20,seam1,weld1,weave1,z1,tWeldGun\wobj:=wJig;
    ArcLEnd [[100,200,2],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]],v20,seam1,weld1,fine,tWeldGun\WObj:=wJig;
    <SMT>
    movel offs(pApproach,0,0,40),v500,z20,tWeldGun\wobj:=wJig;
  endproc

  proc main()
    rWeldCircle;
    waittime 0.2;
  endproc
endmodule
