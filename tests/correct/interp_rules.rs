//! The generated module under a controller's rules (issue 48): each case
//! the issue found, run in the project's interpreter (which follows the
//! controller there: tests/correct/interp_controller.rs) on a program
//! `correct --runtime` rewrote, against an expectation written apart from
//! the module: the static correction of the same numbers (`correct
//! --at`), or what the manual says the controller does.

use super::interp::touch;
use super::interp_targets::{camera, lit, TOOL, WOBJ};
use rapidtherm::correct::{correct, Correction, Options, When};
use rapidtherm::interp::{kin, Clock, Interp, Kinematics, MessageKind, Value};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::robot::Robot;

/// `program` (with `TOOL`, `WOBJ` and the camera's target `PA` filled in)
/// rewritten by `correct --runtime`, and the module it wrote: loaded,
/// the clock at `start`, and the run's report.
pub(super) fn rewritten(program: &str, start: Clock) -> (Interp, String, String, Vec<u8>) {
    let (trans, rot, conf) = camera();
    let text = program
        .replace("TOOL", TOOL)
        .replace("WOBJ", WOBJ)
        .replace("PA", &lit(trans, rot, conf));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cell.mod"), &text).unwrap();
    std::fs::create_dir(dir.path().join("warm")).unwrap();
    let out = super::rapidtherm(
        &["correct", "cell.mod", "--runtime", "-o", "warm/cell.mod"],
        dir.path(),
    );
    super::assert_exit(&out, 0);
    let rewritten = std::fs::read(dir.path().join("warm/cell.mod")).unwrap();
    let module = std::fs::read(dir.path().join("warm/RtWarm.sys")).unwrap();
    let mut i = Interp::load(
        &[("RtWarm.sys", &module), ("cell.mod", &rewritten)],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    i.set_clock(start);
    (
        i,
        String::from_utf8_lossy(&rewritten).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        module,
    )
}

/// `minutes` of running, a move a minute.
fn run_for(i: &mut Interp, minutes: usize) {
    for _ in 0..minutes {
        i.advance(1.0);
        touch(i);
    }
}

/// The static correction at minute `t` of the camera's target moved to
/// with the tool and the work object `wobj` (RAPID data text).
fn static_pose(t: f64, wobj: &str) -> nalgebra::Isometry3<f64> {
    let (trans, rot, conf) = camera();
    let fixed = format!(
        "MODULE Fixed\r\n  CONST robtarget pA := {};\r\n  PERS tooldata tGrip := {TOOL};\r\n  PERS wobjdata wConv := {wobj};\r\n  PROC main()\r\n    MoveL pA, v100, fine, tGrip\\WObj:=wConv;\r\n  ENDPROC\r\nENDMODULE\r\n",
        lit(trans, rot, conf)
    );
    statically(&fixed, t)[0].exact.unwrap()
}

/// What `correct --at t` makes of `program`'s targets.
pub(super) fn statically(program: &str, t: f64) -> Vec<Correction> {
    let program = rapidtherm::rapid::parse("fixed.mod", program.as_bytes()).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), t.max(1.0)).unwrap();
    correct(
        &program,
        &warm,
        &Options::new(When::At(Moment::Minute(t))),
        &mut |_, _| {},
    )
    .unwrap()
    .corrections
}

/// How far a moved target is from a pose (mm, degrees).
fn off(got: &Value, want: &nalgebra::Isometry3<f64>) -> (f64, f64) {
    let (pose, _, _) = kin::robtarget_parts(got).unwrap();
    (
        (pose.translation.vector - want.translation.vector).norm(),
        pose.rotation.angle_to(&want.rotation).to_degrees(),
    )
}

fn position(v: &Value) -> [f64; 3] {
    let n = v.numbers();
    [n[0], n[1], n[2]]
}

fn start() -> Clock {
    Clock::at(2026, 11, 27, 6, 0, 0)
}

const CELL: &str = "MODULE Cell\r
  PERS tooldata tGrip := TOOL;\r
  PERS wobjdata wConv := WOBJ;\r
  CONST robtarget pA := PA;\r
  PROC main()\r
    VAR robtarget p;\r
    MoveL pA, v100, fine, tGrip\\WObj:=wConv;\r
    p := CRobT(\\Tool:=tGrip \\WObj:=wConv);\r
    MoveL Offs(p, 0, 0, 20), v100, fine, tGrip\\WObj:=wConv;\r
  ENDPROC\r
ENDMODULE\r
";

// Before: the move to `Offs(p, 0, 0, 20)` was wrapped, but CRobT returns
// where the corrected robot stands: corrected twice, one drift off.
#[test]
fn a_target_read_back_from_the_robot_is_not_corrected_twice() {
    let (mut i, text, report, _) = rewritten(CELL, start());
    assert!(text.contains("MoveL Offs(p, 0, 0, 20), v100"), "{text}");
    assert!(
        text.contains("MoveL RtWarmT(pA, 1, tGrip \\WObj:=wConv)"),
        "{text}"
    );
    assert!(
        report.contains("cell.mod:9:5: left as written: a reading of the robot"),
        "{report}"
    );
    touch(&mut i);
    run_for(&mut i, 120);
    i.call_proc("main", &[]).unwrap();
    let moved = i.moves();
    // The first move: the static correction of pA at minute 120.
    let (d, a) = off(&moved[0].targets[0], &static_pose(120.0, WOBJ));
    assert!(d < 1e-3 && a < 1e-3, "{d} mm, {a} deg");
    // The second: 20 mm above where the robot was sent, as the manual's
    // CRobT and Offs make it (the work object's z, here turned only about
    // z: the world's).
    let (p0, p1) = (
        position(&moved[0].targets[0]),
        position(&moved[1].targets[0]),
    );
    let rise = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
    for (k, want) in [0.0, 0.0, 20.0].iter().enumerate() {
        assert!((rise[k] - want).abs() < 1e-9, "{rise:?}");
    }
}

const PASSED_ON: &str = "MODULE Cell\r
  PERS tooldata tGrip := TOOL;\r
  PERS wobjdata wConv := WOBJ;\r
  CONST robtarget pA := PA;\r
  PROC glue(robtarget p, PERS tooldata t \\PERS wobjdata W)\r
    MoveL p, v100, fine, t \\WObj?W;\r
  ENDPROC\r
  PROC main()\r
    glue pA, tGrip \\W:=wConv;\r
  ENDPROC\r
ENDMODULE\r
";

// Before: `\WObj?W` was dropped (`RtWarm(p, t)`): the drift computed in
// wobj0, the wrong frame under a work object turned 30° about z.
#[test]
fn a_work_object_passed_on_is_the_frame_of_the_correction() {
    let (mut i, text, _, _) = rewritten(PASSED_ON, start());
    assert!(text.contains("MoveL RtWarm(p, t \\WObj?W), v100"), "{text}");
    touch(&mut i);
    run_for(&mut i, 60);
    i.call_proc("main", &[]).unwrap();
    let (d, a) = off(&i.moves()[0].targets[0], &static_pose(60.0, WOBJ));
    assert!(d < 1e-3 && a < 1e-3, "{d} mm, {a} deg {:?}", i.messages());
}

// Before: a date before 2000 made the day number negative, the module's
// "never updated" mark: the state never advanced.
#[test]
fn a_controller_date_before_2000_corrects_as_any_other() {
    let (mut i, _, _, _) = rewritten(CELL, Clock::at(1999, 12, 31, 22, 0, 0));
    touch(&mut i);
    run_for(&mut i, 120);
    i.call_proc("main", &[]).unwrap();
    let (d, a) = off(&i.moves()[0].targets[0], &static_pose(120.0, WOBJ));
    assert!(d < 1e-3 && a < 1e-3, "{d} mm, {a} deg");
}

const DISPLACED: &str = "MODULE Cell\r
  PERS tooldata tGrip := TOOL;\r
  PERS wobjdata wConv := WOBJ;\r
  CONST robtarget pA := PA;\r
  PROC main()\r
    PDispSet [[10,5,0],[0.9848078,0,0,0.1736482]];\r
    MoveL pA, v100, fine, tGrip\\WObj:=wConv;\r
    PDispOff;\r
  ENDPROC\r
ENDMODULE\r
";

// Before: the drift was turned into the work object's frame without the
// program displacement's rotation. The displaced target is the target in
// a work object whose object frame is the displacement (BCR, PDispSet:
// "all programmed positions will also be displaced"): the static
// correction of that work object is the expectation.
#[test]
fn the_program_displacement_turns_the_correction() {
    let (mut i, _, _, _) = rewritten(DISPLACED, start());
    touch(&mut i);
    run_for(&mut i, 120);
    i.call_proc("main", &[]).unwrap();
    let displaced = WOBJ.replace(
        "[[0,0,0],[1,0,0,0]]]",
        "[[10,5,0],[0.9848078,0,0,0.1736482]]]",
    );
    assert_ne!(displaced, WOBJ);
    let (d, a) = off(&i.moves()[0].targets[0], &static_pose(120.0, &displaced));
    assert!(d < 1e-3 && a < 1e-3, "{d} mm, {a} deg");
    // The correction the target would get undisplaced is another: the
    // drift turned by 20° and taken at other joints (the old module's
    // miss was of this kind).
    let (undisplaced, _) = off(&i.moves()[0].targets[0], &static_pose(120.0, WOBJ));
    assert!(undisplaced > 5e-3, "{undisplaced} mm");
}

fn said(i: &Interp, kind: MessageKind, header: &str) -> bool {
    i.messages()
        .iter()
        .any(|m| m.kind == kind && m.header == header)
}

// Before: a clock set forward counted as a stop (the arm cooled), and the
// operator was told nothing.
#[test]
fn a_clock_set_forward_is_no_time_and_is_said() {
    let (mut i, _, _, _) = rewritten(CELL, start());
    touch(&mut i);
    assert!(
        said(&i, MessageKind::Info, "RtWarm: cold start"),
        "{:?}",
        i.messages()
    );
    run_for(&mut i, 60);
    // Summer time: the controller's clock an hour on, none of it passed.
    i.set_clock(i.clock().plus(60.0));
    run_for(&mut i, 1);
    assert!(
        said(&i, MessageKind::Warning, "RtWarm: clock jumped"),
        "{:?}",
        i.messages()
    );
    i.call_proc("main", &[]).unwrap();
    let (d, a) = off(&i.moves()[0].targets[0], &static_pose(61.0, WOBJ));
    assert!(d < 1e-3 && a < 1e-3, "{d} mm, {a} deg");
}

// A P-start keeps the state (PERS) and the time since the last update
// counts from the controller's clock; a module loaded again starts from
// its file: a cold arm. Both said.
#[test]
fn a_p_start_keeps_the_state_and_a_reload_starts_cold_both_said() {
    let (mut i, _, _, module) = rewritten(CELL, start());
    touch(&mut i);
    run_for(&mut i, 60);
    i.restart().unwrap();
    i.advance(2.0);
    touch(&mut i);
    assert!(
        said(&i, MessageKind::Info, "RtWarm: started"),
        "{:?}",
        i.messages()
    );
    i.call_proc("main", &[]).unwrap();
    let (d, _) = off(&i.moves()[0].targets[0], &static_pose(62.0, WOBJ));
    assert!(d < 1e-3, "{d} mm");
    // A long stop: cooled, and said.
    i.advance(30.0);
    touch(&mut i);
    assert!(
        said(&i, MessageKind::Info, "RtWarm: robot stood"),
        "{:?}",
        i.messages()
    );
    i.reload_module("RtWarm", &module).unwrap();
    let before = i.messages().len();
    touch(&mut i);
    let m = &i.messages()[before..];
    assert!(
        m.iter()
            .any(|m| m.kind == MessageKind::Info && m.header == "RtWarm: cold start"),
        "{m:?}"
    );
}

const AT_THE_EDGE: &str = "MODULE Cell\r
  PERS tooldata tGrip := TOOL;\r
  PERS wobjdata wConv := WOBJ;\r
  CONST robtarget pA := PA;\r
  PROC main()\r
    VAR jointtarget j;\r
    j := [[10,20,15,90,45,-90],[9E9,9E9,9E9,9E9,9E9,9E9]];\r
    MoveAbsJ j, v1000, fine, tool0;\r
  ENDPROC\r
ENDMODULE\r
";

// Before: a run-time jointtarget went through CalcJointT in its written
// joints' configuration; the warm solution across the quadrant (axis 4
// at 89.99° for a written 90°) has none there: a program stop. Now the
// joints go as written, and the operator is told.
#[test]
fn a_run_time_jointtarget_across_a_quadrant_goes_as_written_and_is_said() {
    let (mut i, text, _, _) = rewritten(AT_THE_EDGE, start());
    assert!(text.contains("MoveAbsJ RtWarmJ(j), v1000"), "{text}");
    touch(&mut i);
    run_for(&mut i, 120);
    i.call_proc("main", &[]).unwrap();
    let got = i.moves()[0].targets[0].numbers();
    let written = [10.0, 20.0, 15.0, 90.0, 45.0, -90.0];
    let moved: f64 = (0..6)
        .map(|k| (got[k] - written[k]).abs())
        .fold(0.0, f64::max);
    if moved == 0.0 {
        assert!(
            said(&i, MessageKind::Error, "RtWarm: joints as written"),
            "{:?}",
            i.messages()
        );
    } else {
        // Where the controller does find joints in the configuration,
        // they are the warm ones, within the degree the module allows.
        assert!(moved < 1.0, "{got:?}");
    }
}

const ARRAYS: &str = "MODULE Cell\r
  PERS tooldata tGrip := TOOL;\r
  PERS wobjdata wConv := WOBJ;\r
  CONST robtarget pA := PA;\r
  CONST jointtarget jEdge{3} := [[[10,20,15,90,45,-90],[9E9,9E9,9E9,9E9,9E9,9E9]],[[5,10,20,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[-30,15,10,180,30,90],[9E9,9E9,9E9,9E9,9E9,9E9]]];\r
  PROC main()\r
    FOR k FROM 1 TO 3 DO\r
      MoveAbsJ jEdge{k}, v1000, fine, tool0;\r
    ENDFOR\r
  ENDPROC\r
ENDMODULE\r
";

// Before: jointtargets went through CalcJointT in their written joints'
// configuration, and the warm solution of one on a quadrant boundary
// (axis 4 at 90°, axis 5 at 0, axis 6 at -90°) lies just across it: a
// program stop. An array's elements indexed at run time now find their
// rows in the table: the static path's warm joints, nearest the written
// ones, no configuration involved.
#[test]
fn jointtargets_on_quadrant_boundaries_get_the_static_paths_warm_joints() {
    let (mut i, text, _, _) = rewritten(ARRAYS, start());
    assert!(
        text.contains("MoveAbsJ RtWarmJT(jEdge{k}, k), v1000"),
        "{text}"
    );
    touch(&mut i);
    run_for(&mut i, 120);
    i.call_proc("main", &[]).unwrap();
    let (trans, rot, conf) = camera();
    let program = ARRAYS
        .replace("TOOL", TOOL)
        .replace("WOBJ", WOBJ)
        .replace("PA", &lit(trans, rot, conf));
    let want = statically(&program, 120.0);
    let moved = i.moves();
    assert_eq!(moved.len(), 3);
    for (k, m) in moved.iter().enumerate() {
        let id = format!("jEdge{{{}}}", k + 1);
        let c = want
            .iter()
            .find(|c| c.id == id)
            .unwrap_or_else(|| panic!("{id}"));
        let got = m.targets[0].numbers();
        let worst = (0..6)
            .map(|a| (got[a] - c.corrected[a]).abs())
            .fold(0.0, f64::max);
        assert!(c.dangle_deg > 1e-3, "{id}: a warm arm's correction");
        assert!(worst < 1e-3, "{id}: {worst}°");
    }
}

// Before: hour and minute were separate GetTime reads, so a call across
// hh:00 read an hour early and the next counted a 60-minute stop. The
// manual's CTime gives "HH:MM:SS" in one reading, and a date read before
// and after it tells a midnight between: one moment's day and time.
#[test]
fn the_clock_is_read_once_per_update() {
    let (_, _, _, module) = rewritten(CELL, start());
    let text = String::from_utf8(module).unwrap();
    let now = &text[text.find("LOCAL PROC rtNow").unwrap()..];
    let now = &now[..now.find("ENDPROC").unwrap()];
    assert!(!text.contains("GetTime"), "no reading in parts");
    // The time once, the date before and after it; both again only where
    // midnight came between.
    let body: Vec<&str> = now.lines().map(str::trim).collect();
    let at = |s: &str| body.iter().position(|l| *l == s).unwrap_or(usize::MAX);
    let (d1, t1, check) = (
        at("date := CDate();"),
        at("time := CTime();"),
        at("IF CDate() <> date THEN"),
    );
    assert!(d1 < t1 && t1 < check && check != usize::MAX, "{now}");
    assert_eq!(now.matches("CTime()").count(), 2, "{now}");
}

// A power failure keeps VAR and PERS data (RAPID overview, Initiating
// data); whether a running clock counts the time off the manual does not
// say. The module takes the running clock's time and says so: the
// operator resets a warm arm after a long power failure.
#[test]
fn a_power_failure_keeps_the_state_and_is_said() {
    let (mut i, _, _, _) = rewritten(CELL, start());
    touch(&mut i);
    run_for(&mut i, 60);
    i.power_fail(30.0);
    run_for(&mut i, 1);
    let jumped = i
        .messages()
        .iter()
        .find(|m| m.kind == MessageKind::Warning && m.header == "RtWarm: clock jumped")
        .unwrap_or_else(|| panic!("{:?}", i.messages()));
    assert!(
        jumped.reasons.iter().any(|r| r.contains("power failure")),
        "{jumped:?}"
    );
    i.call_proc("main", &[]).unwrap();
    let (d, _) = off(&i.moves()[0].targets[0], &static_pose(61.0, WOBJ));
    assert!(d < 1e-3, "{d} mm");
}
