//! The cold joints a walk keeps for a correction of the same program: one
//! for each literal it moves to, each what the IK gives for its pose in
//! the move's tool and work object, and none where the frames asked for
//! differ from the move's, or the program is another.

use rapidtherm::rapid;
use rapidtherm::resolve::{target_pose, Frames};
use rapidtherm::robot::frames::{flange_of_target, ToolFrame, WobjFrames};
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{estimate_with_joints, EstimateOptions};

const PROGRAM: &str = "MODULE M
  PERS tooldata tPen := [TRUE,[[0,0,120],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];
  PERS wobjdata wTable := [FALSE,TRUE,\"\",[[300,-100,50],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pA := [[100,0,200],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB := [[150,50,200],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pC := [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pNever := [[500,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL pA, v100, fine, tPen\\WObj:=wTable;
    MoveL pB, v100, fine, tPen\\WObj:=wTable;
    MoveL Offs(pB,0,0,20), v100, fine, tPen\\WObj:=wTable;
    MoveJ pC, v100, fine, tool0;
    MoveL [[520,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;
  ENDPROC
ENDMODULE
";

#[test]
fn each_literal_moved_to_has_the_joints_the_ik_gives() {
    let program = rapid::parse("t.mod", PROGRAM.as_bytes()).unwrap_or_else(|e| panic!("{e}"));
    let robot = Robot::irb140();
    let (_, joints) = estimate_with_joints(&program, &robot, &EstimateOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(joints.fits(&program));
    let frames = Frames::of_program(&program).unwrap_or_else(|e| panic!("{e}"));
    let pen = frames.tool(Some("tPen")).cloned().expect("tPen");
    let table = frames.wobj(Some("wTable")).cloned().expect("wTable");
    let (tool0, wobj0) = (ToolFrame::tool0(), WobjFrames::wobj0());
    let targets = program.targets();
    let mut checked = 0;
    for i in 0..targets.len() {
        let t = targets.at(i);
        if t.value.is_none() {
            // The derived Offs(pB, ...): no literal, no joints kept.
            assert_eq!(joints.joints(i, &pen, &table), None, "{}", t.id);
            continue;
        }
        let name = t.name.clone().unwrap_or_default();
        let (tool, wobj) = match name.as_str() {
            "pA" | "pB" => (&pen, &table),
            "pNever" => {
                assert_eq!(joints.joints(i, &tool0, &wobj0), None, "never moved to");
                continue;
            }
            _ => (&tool0, &wobj0),
        };
        let (pose, conf) = target_pose(&program, &t)
            .unwrap_or_else(|e| panic!("{e}"))
            .expect("numbers");
        let flange = flange_of_target(&pose, tool, wobj).unwrap_or_else(|e| panic!("{e}"));
        let q = robot
            .ik_conf(&flange, &conf)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(joints.joints(i, tool, wobj), Some(q), "{}", t.id);
        // Asked in other frames, the walk's joints are not given.
        let other = if std::ptr::eq(tool, &pen) {
            &tool0
        } else {
            &pen
        };
        assert_eq!(joints.joints(i, other, wobj), None, "{}", t.id);
        checked += 1;
    }
    // pA, pB, pC and the inline target; the derived Offs(pB) keeps none.
    assert_eq!(checked, 4);
    assert_eq!(joints.found(), 4);
    // For another program (a copy, at another address) they do not fit.
    let copy = rapid::parse("t.mod", PROGRAM.as_bytes()).unwrap_or_else(|e| panic!("{e}"));
    assert!(!joints.fits(&copy));
}
