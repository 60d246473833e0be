//! Run-time targets: a cell program whose moves go to a camera's target
//! and `Offs` of it, rewritten by `correct --runtime`, run by the
//! project's interpreter with the module the tool wrote; its corrected
//! targets are the static path's for the same numbers. And what the
//! interpreter refuses, and keeps across a restart.

use nalgebra::Isometry3;
use rapidtherm::interp::{kin, Clock, Interp, Kinematics, Value};
use rapidtherm::robot::frames::{pose_to_rapid, target_of_flange};
use rapidtherm::robot::{Robot, ToolFrame, WobjFrames};

pub(super) const TOOL: &str = "[TRUE,[[0,0,150],[1,0,0,0]],[1.5,[0,0,60],[1,0,0,0],0,0,0]]";
/// A conveyor's frame turned 30° about z: the drift is turned into it.
pub(super) const WOBJ: &str =
    "[FALSE,TRUE,\"\",[[300,100,200],[0.965926,0,0,0.258819]],[[0,0,0],[1,0,0,0]]]";

pub(super) fn lit(trans: [f64; 3], rot: [f64; 4], conf: [f64; 4]) -> String {
    format!(
        "[[{},{},{}],[{},{},{},{}],[{},{},{},{}],[9E9,9E9,9E9,9E9,9E9,9E9]]",
        trans[0],
        trans[1],
        trans[2],
        rot[0],
        rot[1],
        rot[2],
        rot[3],
        conf[0],
        conf[1],
        conf[2],
        conf[3]
    )
}

/// Where the camera sees the part: a target the arm reaches with margin
/// on every quadrant, in the conveyor's frame.
pub(super) fn camera() -> ([f64; 3], [f64; 4], [f64; 4]) {
    let robot = Robot::irb140();
    let q = [15.0f64, 10.0, 20.0, 10.0, 50.0, 20.0].map(f64::to_radians);
    let tool = ToolFrame::new(true, [0.0, 0.0, 150.0], [1.0, 0.0, 0.0, 0.0]).unwrap();
    let wobj = WobjFrames::new(
        false,
        true,
        "",
        ([300.0, 100.0, 200.0], [0.965926, 0.0, 0.0, 0.258819]),
        ([0.0; 3], [1.0, 0.0, 0.0, 0.0]),
    )
    .unwrap();
    let t: Isometry3<f64> = target_of_flange(&robot.fk(&q), &tool, &wobj).unwrap();
    let (trans, rot) = pose_to_rapid(&t);
    let c = robot.conf_of(&q);
    (trans, rot, [c.cf1, c.cf4, c.cf6, c.cfx].map(f64::from))
}

const CELL: &str = "MODULE Cell\r
  ! The camera fills pCam and the offsets at run time.\r
  VAR robtarget pCam := [[0,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\r
  VAR num camX := 0;\r
  VAR num camY := 0;\r
  PERS tooldata tGrip := TOOL;\r
  PERS wobjdata wConv := WOBJ;\r
  PROC main()\r
    VAR robtarget p;\r
    p := Offs(pCam, camX, camY, 0);\r
    MoveL p, v100, fine, tGrip\\WObj:=wConv;\r
    MoveJ Offs(pCam, 0, 0, 40), v1000, z50, tGrip\\WObj:=wConv;\r
  ENDPROC\r
ENDMODULE\r
";

#[test]
fn run_time_targets_are_corrected_as_the_static_path_corrects_their_numbers() {
    let (mut i, text, _, _) =
        super::interp_rules::rewritten(CELL, Clock::at(2026, 11, 27, 6, 0, 0));
    assert!(
        text.contains("MoveL RtWarm(p, tGrip \\WObj:=wConv)"),
        "{text}"
    );
    assert!(text.contains("MoveJ RtWarm(Offs(pCam, 0, 0, 40), tGrip \\WObj:=wConv)"));

    // What the camera saw, and the offsets it measured.
    let (trans, rot, conf) = camera();
    let (dx, dy) = (12.5, -7.25);
    // A move a minute for an hour: each call brings the state to now.
    super::interp::touch(&mut i);
    for _ in 0..60 {
        i.advance(1.0);
        super::interp::touch(&mut i);
    }
    i.set_global("pCam", kin::robtarget(trans, rot, conf, [9e9; 6]))
        .unwrap();
    i.set_global("camX", Value::Num(dx)).unwrap();
    i.set_global("camY", Value::Num(dy)).unwrap();
    i.call_proc("main", &[]).unwrap();
    let moved = i.moves();
    assert_eq!(moved.len(), 2);

    // The static path: the same numbers written as CONSTs.
    let a = [trans[0] + dx, trans[1] + dy, trans[2]];
    let b = [trans[0], trans[1], trans[2] + 40.0];
    let fixed = format!(
        "MODULE Fixed\r\n  CONST robtarget pA := {};\r\n  CONST robtarget pB := {};\r\n  PERS tooldata tGrip := {TOOL};\r\n  PERS wobjdata wConv := {WOBJ};\r\n  PROC main()\r\n    MoveL pA, v100, fine, tGrip\\WObj:=wConv;\r\n    MoveJ pB, v1000, z50, tGrip\\WObj:=wConv;\r\n  ENDPROC\r\nENDMODULE\r\n",
        lit(a, rot, conf),
        lit(b, rot, conf)
    );
    let want = super::interp_rules::statically(&fixed, 60.0);
    for (id, got) in [("pA", &moved[0].targets[0]), ("pB", &moved[1].targets[0])] {
        let c = want.iter().find(|c| c.id == id).unwrap();
        let exact = c.exact.unwrap();
        let (pose, _, _) = kin::robtarget_parts(got).unwrap();
        let d = (pose.translation.vector - exact.translation.vector).norm();
        let a = pose.rotation.angle_to(&exact.rotation).to_degrees();
        eprintln!(
            "{id}: corrected by {:.4} mm; the interpreter's misses by {d:.2e} mm",
            c.correction_norm_mm
        );
        assert!(c.correction_norm_mm > 0.02, "{id}: a warm arm's correction");
        assert!(d < 1e-3 && a < 1e-3, "{id}: {d} mm, {a} deg");
    }
}

#[test]
fn pers_data_outlive_a_restart_and_var_data_do_not() {
    let text = "MODULE M\n  PERS num count := 0;\n  VAR num seen := 0;\n  PROC tick()\n    count := count + 1;\n    seen := seen + 1;\n  ENDPROC\nENDMODULE\n";
    let mut i = Interp::load(
        &[("m.mod", text.as_bytes())],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    i.call_proc("tick", &[]).unwrap();
    i.call_proc("tick", &[]).unwrap();
    i.restart().unwrap();
    assert_eq!(i.global("count"), Some(&Value::Num(2.0)));
    assert_eq!(i.global("seen"), Some(&Value::Num(0.0)));
}

#[test]
fn what_the_interpreter_does_not_run_is_an_error_at_its_place() {
    let text = "MODULE M\n  PROC main()\n    VAR num x;\n    x := 1;\n    SetDO do1, 1;\n  ENDPROC\n  FUNC num f()\n    RETURN Foo(1);\n  ENDFUNC\n  PROC g()\n    x := 1 DIV 0.5;\n  ENDPROC\nENDMODULE\n";
    let mut i = Interp::load(
        &[("m.mod", text.as_bytes())],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    for (routine, line, col, words) in [
        ("main", 5, 5, "SetDO"),
        ("f", 8, 5, "Foo"),
        ("g", 11, 5, "DIV"),
    ] {
        let e = match routine {
            "f" => i.call_func(routine, &[]).map(|_| ()).unwrap_err(),
            _ => i.call_proc(routine, &[]).map(|_| ()).unwrap_err(),
        };
        let at = e.location.as_ref().expect("a place");
        assert_eq!(
            (at.file.as_str(), at.line, at.col),
            ("m.mod", line, col),
            "{e:?}"
        );
        assert!(e.message.contains(words), "{}", e.message);
    }
}

#[test]
fn a_loop_that_never_ends_is_an_error_at_its_place_not_a_hang() {
    let text = "MODULE M\n  PROC main()\n    VAR num x;\n    WHILE TRUE DO\n      x := x + 1;\n    ENDWHILE\n  ENDPROC\nENDMODULE\n";
    let mut i = Interp::load(
        &[("m.mod", text.as_bytes())],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    i.set_step_budget(1_000);
    let e = i.call_proc("main", &[]).unwrap_err();
    let at = e.location.as_ref().expect("a place");
    assert_eq!((at.file.as_str(), at.line), ("m.mod", 5), "{e:?}");
    assert!(e.message.contains("without ending"), "{}", e.message);
    // The budget is a call's: the next call starts afresh and fails the
    // same way, not at once.
    let again = i.call_proc("main", &[]).unwrap_err();
    assert!(
        again.message.contains("1000 statements"),
        "{}",
        again.message
    );
}
