//! The interpreter follows a real ABB controller where the generated
//! module depends on it: error handlers, CalcJointT's configuration rule,
//! program displacement, stopwatches, the robot's commanded position,
//! operator messages, restarts, the expressions and the single precision.
//! Each expectation is worked by hand or taken from ABB's "RAPID
//! Instructions, Functions and Data types" technical reference (cited as
//! "the reference", by entry) or its "RAPID Reference Manual, Basic
//! Characteristics" (error recovery, RAISE).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rapidtherm::error::ErrorKind;
use rapidtherm::interp::{kin, CallArg, Clock, Interp, Kinematics, MessageKind, Precision, Value};
use rapidtherm::robot::frames::{pose_from_rapid, pose_to_rapid};
use rapidtherm::robot::Robot;

fn load(text: &str) -> Interp {
    Interp::load(
        &[("m.mod", text.as_bytes())],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap()
}

fn func(i: &mut Interp, name: &str, args: &[CallArg]) -> Value {
    i.call_func(name, args)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"))
        .0
}

fn num(i: &mut Interp, name: &str) -> f64 {
    func(i, name, &[]).num().unwrap()
}

fn joints(q: [f64; 6]) -> Value {
    kin::jointtarget(q, [9e9; 6])
}

/// A configuration the IRB 140 reaches flange pose (`trans`, `rot`) in
/// (tool0, wobj0), and its joints (degrees): the project's IK's first
/// solution.
fn conf_for(trans: [f64; 3], rot: [f64; 4]) -> ([f64; 4], [f64; 6]) {
    let robot = Robot::irb140();
    let f = pose_from_rapid(trans, rot).unwrap();
    let sols = robot.ik(&f).unwrap();
    let s = sols.iter().next().expect("a solution");
    let c = s.conf;
    (
        [c.cf1, c.cf4, c.cf6, c.cfx].map(f64::from),
        s.q.map(f64::to_degrees),
    )
}

/// A robtarget at (`trans`, down) in a configuration the flange pose has.
fn down_at(trans: [f64; 3]) -> Value {
    let down = [0.0, 0.0, 1.0, 0.0];
    kin::robtarget(trans, down, conf_for(trans, down).0, [9e9; 6])
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

const ERRORS: &str = r#"MODULE M
  VAR num log := 0;
  VAR num d := 0;
  VAR num low := 3;
  FUNC num safeDiv(num a, num b)
    RETURN a / b;
  ERROR
    IF ERRNO = ERR_DIVZERO RETURN -1;
  ENDFUNC
  PROC skipOn()
    VAR num x;
    log := 0;
    x := 1 / 0;
    log := log + 1;
  ERROR
    IF ERRNO = ERR_DIVZERO THEN
      log := log + 10;
      TRYNEXT;
    ENDIF
  ENDPROC
  PROC again()
    VAR num x;
    d := 0;
    x := 1 / d;
    log := x;
  ERROR
    d := 4;
    RETRY;
  ENDPROC
  PROC retryForever()
    VAR num x;
    x := 1 / 0;
  ERROR
    log := log + 1;
    RETRY;
  ENDPROC
  FUNC jointtarget inner(robtarget p)
    RETURN CalcJointT(p, tool0);
  ERROR
    RAISE;
  ENDFUNC
  FUNC jointtarget noHandler(robtarget p)
    RETURN CalcJointT(p, tool0);
  ENDFUNC
  FUNC num outer(robtarget p)
    VAR jointtarget j;
    j := inner(p);
    j := noHandler(p);
    RETURN 1;
  ERROR
    IF ERRNO = ERR_OUTSIDE_REACH RETURN 2;
    IF ERRNO = ERR_ROBLIMIT RETURN 3;
    RETURN 4;
  ENDFUNC
  FUNC num user()
    IF log = 0 RAISE 7;
    RETURN 0;
  ERROR
    RETURN ERRNO;
  ENDFUNC
  FUNC num onlyDivZero()
    VAR num a{2};
    VAR num at := 3;
    RETURN a{at};
  ERROR (ERR_DIVZERO)
    RETURN -1;
  ENDFUNC
  FUNC num takesOutOfBnd()
    VAR num a{2};
    RETURN a{low};
  ERROR (ERR_OUTOFBND)
    RETURN -2;
  ENDFUNC
  FUNC num unknown()
    RETURN Foo(1);
  ERROR
    RETURN -9;
  ENDFUNC
  FUNC num badHandler()
    RETURN 1 / 0;
  ERROR
    RETURN 1 / 0;
  ENDFUNC
  FUNC num callsBad()
    RETURN badHandler();
  ERROR
    RETURN -5;
  ENDFUNC
ENDMODULE
"#;

/// The RAPID Reference Manual, Basic Characteristics, Error Recovery and
/// RAISE: a handler ends with RETURN (a FUNC's value), RETRY (the failed
/// statement again), TRYNEXT (the statement after it) or RAISE (to the
/// caller's handler); an error of a routine without handler is raised
/// again where it was called; an error inside a handler is the system's.
#[test]
fn error_handlers_return_retry_trynext_and_raise_as_the_manual_says() {
    let mut i = load(ERRORS);
    let n = |v: f64| CallArg::Value(Value::Num(v));
    assert_eq!(func(&mut i, "safeDiv", &[n(6.0), n(3.0)]), Value::Num(2.0));
    assert_eq!(func(&mut i, "safeDiv", &[n(1.0), n(0.0)]), Value::Num(-1.0));
    assert_eq!(i.global("ERRNO"), i.global("ERR_DIVZERO"));

    // TRYNEXT: the handler's +10, then the statement after the division.
    i.call_proc("skipOn", &[]).unwrap();
    assert_eq!(i.global("log"), Some(&Value::Num(11.0)));
    // RETRY: the division again with d = 4.
    i.call_proc("again", &[]).unwrap();
    assert_eq!(i.global("log"), Some(&Value::Num(0.25)));
    // A RETRY that never succeeds: the controller gives up (ERR_EXCRTYMAX
    // after its 4 retries, "No Of Retry"), an error of the call.
    i.set_global("log", Value::Num(0.0)).unwrap();
    assert!(i.call_proc("retryForever", &[]).is_err());
    assert_eq!(
        i.global("log"),
        Some(&Value::Num(5.0)),
        "first try + 4 retries"
    );

    // CalcJointT out of reach of the IRB 140 (810 mm): ERR_OUTSIDE_REACH,
    // passed on by inner's RAISE to outer's handler.
    let far = kin::robtarget(
        [3000.0, 0.0, 500.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0; 4],
        [9e9; 6],
    );
    assert_eq!(
        func(&mut i, "outer", &[CallArg::Value(far.clone())]),
        Value::Num(2.0)
    );
    // Unhandled, it is an error at its place, as before.
    let e = i
        .call_func("noHandler", &[CallArg::Value(far)])
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert_eq!(e.location.as_ref().unwrap().line, 43, "{e:?}");
    // What the interpreter does not run is no RAPID error: no handler
    // takes it (that call's unhandled error left behind neither).
    let e = i.call_func("unknown", &[]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported, "{e:?}");

    // RAISE 7 in the body: the routine's own handler, ERRNO 7.
    i.set_global("log", Value::Num(0.0)).unwrap();
    assert_eq!(num(&mut i, "user"), 7.0);
    // A handler for ERR_DIVZERO only does not take an index out of bounds.
    assert!(i.call_func("onlyDivZero", &[]).is_err());
    assert_eq!(num(&mut i, "takesOutOfBnd"), -2.0);
    i.set_global("low", Value::Num(0.0)).unwrap();
    assert_eq!(num(&mut i, "takesOutOfBnd"), -2.0, "index 0 too");
    // An error inside a handler is the system's: the caller's handler
    // does not take it.
    assert!(i.call_func("callsBad", &[]).is_err());
}

const KIN: &str = r#"MODULE M
  PERS tooldata tSt := [FALSE,[[600,100,400],[0.6,0,0.8,0]],[1,[0,0,1],[1,0,0,0],0,0,0]];
  PERS wobjdata wHeld := [TRUE,TRUE,"",[[0,0,120],[1,0,0,0]],[[10,-20,5],[1,0,0,0]]];
  FUNC robtarget rob(jointtarget j)
    RETURN CalcRobT(j, tool0);
  ENDFUNC
  FUNC jointtarget joint(robtarget p)
    RETURN CalcJointT(p, tool0);
  ENDFUNC
  FUNC num tryJoint(robtarget p)
    VAR jointtarget j;
    j := CalcJointT(p, tool0);
    RETURN 0;
  ERROR
    IF ERRNO = ERR_ROBLIMIT RETURN 1;
    IF ERRNO = ERR_OUTSIDE_REACH RETURN 2;
  ENDFUNC
  FUNC robtarget robSt(jointtarget j)
    RETURN CalcRobT(j, tSt \WObj:=wHeld);
  ENDFUNC
  FUNC jointtarget jointSt(robtarget p)
    RETURN CalcJointT(p, tSt \WObj:=wHeld);
  ENDFUNC
ENDMODULE
"#;

fn with_conf(p: &Value, conf: [f64; 4]) -> Value {
    let n = p.numbers();
    kin::robtarget([n[0], n[1], n[2]], [n[3], n[4], n[5], n[6]], conf, [9e9; 6])
}

/// The reference, CalcJointT: the configuration written in the robtarget
/// is used; no solution there is ERR_ROBLIMIT, a pose out of reach
/// ERR_OUTSIDE_REACH. Axis quadrants by hand: cf = floor(angle / 90°).
#[test]
fn calc_joint_t_takes_the_written_configuration_exactly() {
    let mut i = load(KIN);
    let arg = |v: &Value| [CallArg::Value(v.clone())];
    // Axis 1 at 15°, 4 at 10°, 6 at 20°: quadrants 0, 0, 0.
    let q = [15.0, 10.0, 20.0, 10.0, 50.0, 20.0];
    let p = func(&mut i, "rob", &arg(&joints(q)));
    let c = p.numbers();
    assert_eq!(&c[7..10], &[0.0, 0.0, 0.0]);
    let back = func(&mut i, "joint", &arg(&p)).numbers();
    assert!(close(&back[..6], &q, 1e-6), "{back:?}");
    // cf1 = 1 (axis 1 in 90..180°): the IRB 140 has no such solution.
    let p1 = with_conf(&p, [1.0, c[8], c[9], c[10]]);
    assert_eq!(func(&mut i, "tryJoint", &arg(&p1)), Value::Num(1.0));

    // Axis 4 at -0.2°: quadrant -1. Written cf4 = 0 (0..90°), a solution
    // 0.2° outside it: the controller refuses it (ERR_ROBLIMIT).
    let q = [15.0, 10.0, 20.0, -0.2, 50.0, 20.0];
    let p = func(&mut i, "rob", &arg(&joints(q)));
    let c = p.numbers();
    assert_eq!(c[8], -1.0);
    let back = func(&mut i, "joint", &arg(&p)).numbers();
    assert!(close(&back[..6], &q, 1e-6), "{back:?}");
    let p0 = with_conf(&p, [c[7], 0.0, c[9], c[10]]);
    assert_eq!(func(&mut i, "tryJoint", &arg(&p0)), Value::Num(1.0));
    // The static path's half a degree, asked for: taken.
    let mut lenient = Kinematics::new(Robot::irb140());
    lenient.quadrant_edge = 0.5f64.to_radians();
    let mut l = Interp::load(&[("m.mod", KIN.as_bytes())], lenient).unwrap();
    assert_eq!(func(&mut l, "tryJoint", &arg(&p0)), Value::Num(0.0));

    let far = kin::robtarget(
        [3000.0, 0.0, 500.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0; 4],
        [9e9; 6],
    );
    assert_eq!(func(&mut i, "tryJoint", &arg(&far)), Value::Num(2.0));
}

/// A stationary tool (tooldata robhold FALSE, its tframe the TCP in the
/// world) with the work object held by the robot (uframe in the flange):
/// TCP = flange · uframe · oframe · target, so target = (flange · uframe ·
/// oframe)⁻¹ · tframe, worked here with nalgebra from the flange pose.
#[test]
fn calc_rob_t_and_calc_joint_t_hold_a_stationary_tool() {
    let mut i = load(KIN);
    let q = [20.0, 15.0, 10.0, 30.0, 40.0, -60.0];
    let got = func(&mut i, "robSt", &[CallArg::Value(joints(q))]);
    let flange = Robot::irb140().fk(&q.map(f64::to_radians));
    let uframe = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 120.0),
        UnitQuaternion::identity(),
    );
    let oframe = Isometry3::from_parts(
        Translation3::new(10.0, -20.0, 5.0),
        UnitQuaternion::identity(),
    );
    let tframe = pose_from_rapid([600.0, 100.0, 400.0], [0.6, 0.0, 0.8, 0.0]).unwrap();
    let want = (flange * uframe * oframe).inverse() * tframe;
    let (t, r) = pose_to_rapid(&want);
    let n = got.numbers();
    assert!(close(&n[..3], &t, 1e-6), "{n:?} {t:?}");
    assert!(close(&n[3..7], &r, 1e-9), "{n:?} {r:?}");
    let back = func(&mut i, "jointSt", &[CallArg::Value(got)]).numbers();
    assert!(close(&back[..6], &q, 1e-6), "{back:?}");
}

const DISP: &str = r#"MODULE M
  PERS wobjdata wTurn := [FALSE,TRUE,"",[[0,0,0],[0.70710678,0,0,0.70710678]],[[0,0,0],[1,0,0,0]]];
  PROC shift(pose f)
    PDispSet f;
  ENDPROC
  PROC off()
    PDispOff;
  ENDPROC
  FUNC jointtarget joint(robtarget p)
    RETURN CalcJointT(p, tool0);
  ENDFUNC
  FUNC jointtarget jointTurn(robtarget p)
    RETURN CalcJointT(p, tool0 \WObj:=wTurn);
  ENDFUNC
  FUNC robtarget rob(jointtarget j)
    RETURN CalcRobT(j, tool0);
  ENDFUNC
  FUNC num dispX()
    RETURN C_PROGDISP.pdisp.trans.x;
  ENDFUNC
ENDMODULE
"#;

/// The reference, PDispSet/progdisp: world = uframe · oframe · pdisp ·
/// target; CalcJointT and CalcRobT compute with the active displacement;
/// PDispOff, and a program started from the beginning, switch it off.
/// Worked by hand: uframe turned 90° about z, pdisp 100 mm along x,
/// target (400, 50, 500): in the object frame (500, 50, 500), in the
/// world (−50, 500, 500), the tool's rotation turned by 90° about z too.
#[test]
fn program_displacement_moves_the_robot_functions_frames() {
    let mut i = load(DISP);
    let down = [0.0, 0.0, 1.0, 0.0];
    let turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 90f64.to_radians());
    let rot = turn * pose_from_rapid([0.0; 3], down).unwrap().rotation;
    let q = rot.quaternion();
    let world_rot = [q.w, q.i, q.j, q.k];
    let (conf, want) = conf_for([-50.0, 500.0, 500.0], world_rot);
    let p = kin::robtarget([400.0, 50.0, 500.0], down, conf, [9e9; 6]);
    let shift = kin::pose([100.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    i.call_proc("shift", &[CallArg::Value(shift)]).unwrap();
    assert_eq!(num(&mut i, "dispX"), 100.0);
    let displaced = func(&mut i, "jointTurn", &[CallArg::Value(p.clone())]).numbers();
    assert!(
        close(&displaced[..6], &want, 1e-6),
        "{displaced:?} {want:?}"
    );
    // Off: the same target is another pose.
    i.call_proc("off", &[]).unwrap();
    assert_eq!(num(&mut i, "dispX"), 0.0);
    let world = kin::robtarget([-50.0, 500.0, 500.0], world_rot, conf, [9e9; 6]);
    let plain = func(&mut i, "joint", &[CallArg::Value(world)]).numbers();
    assert!(close(&plain[..6], &want, 1e-6), "{plain:?} {want:?}");

    // CalcRobT in the displaced frame: x less the displacement.
    let j = joints([10.0, 20.0, 10.0, 0.5, 40.0, 5.0]);
    let before = func(&mut i, "rob", &[CallArg::Value(j.clone())]).numbers();
    let shift = kin::pose([100.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    i.call_proc("shift", &[CallArg::Value(shift)]).unwrap();
    let after = func(&mut i, "rob", &[CallArg::Value(j)]).numbers();
    assert!((before[0] - 100.0 - after[0]).abs() < 1e-9);
    assert!(close(&before[1..7], &after[1..7], 1e-9));
    // A program restart switches it off.
    i.restart().unwrap();
    assert_eq!(num(&mut i, "dispX"), 0.0);
}

const CLOCKS: &str = r#"MODULE M
  VAR clock c;
  PROC start()
    ClkStart c;
  ENDPROC
  PROC stop()
    ClkStop c;
  ENDPROC
  PROC reset()
    ClkReset c;
  ENDPROC
  FUNC num read()
    RETURN ClkRead(c);
  ENDFUNC
  FUNC num readSafe()
    RETURN ClkRead(c);
  ERROR
    IF ERRNO = ERR_OVERFLOW RETURN -1;
  ENDFUNC
  FUNC string date()
    RETURN CDate();
  ENDFUNC
  FUNC string time()
    RETURN CTime();
  ENDFUNC
  FUNC num wday()
    RETURN GetTime(\WDay);
  ENDFUNC
ENDMODULE
"#;

/// The reference, clock/ClkStart/ClkStop/ClkReset/ClkRead: seconds
/// counted while started, kept when stopped, zero after a reset, to
/// 0.001 s; ERR_OVERFLOW past 4 294 967 s. The controller's time moves
/// with `advance`; the wall clock an operator sets does not move it.
#[test]
fn clocks_count_the_controllers_time_not_the_wall_clock() {
    let mut i = load(CLOCKS);
    i.set_clock(Clock::at(2026, 11, 27, 10, 0, 0));
    i.call_proc("start", &[]).unwrap();
    i.advance(1.5);
    assert_eq!(num(&mut i, "read"), 90.0);
    // The operator sets the wall clock an hour back: the clock counts on.
    i.set_clock(Clock::at(2026, 11, 27, 9, 1, 30));
    assert_eq!(num(&mut i, "read"), 90.0);
    i.call_proc("stop", &[]).unwrap();
    i.advance(1.0);
    assert_eq!(num(&mut i, "read"), 90.0, "stopped");
    i.call_proc("start", &[]).unwrap();
    i.advance(0.5);
    assert_eq!(num(&mut i, "read"), 120.0);
    // To the millisecond: 0.0123456 min = 0.740736 s.
    i.advance(0.0123456);
    assert_eq!(num(&mut i, "read"), 120.741);
    i.call_proc("reset", &[]).unwrap();
    i.advance(1.0);
    assert_eq!(num(&mut i, "read"), 0.0, "reset stops it");
    // A restart resets the VAR clock.
    i.call_proc("start", &[]).unwrap();
    i.advance(1.0);
    i.restart().unwrap();
    assert_eq!(num(&mut i, "read"), 0.0);
    // Past what a clock holds.
    i.call_proc("start", &[]).unwrap();
    i.advance((4_294_967.0 + 60.0) / 60.0);
    assert_eq!(num(&mut i, "readSafe"), -1.0);
}

/// CDate "yyyy-mm-dd", CTime "hh:mm:ss" (the reference) across the turn
/// of 1999 to 2000; GetTime(\WDay) 1..7 for Monday..Sunday: 1970-01-01
/// was a Thursday (4), 1999-12-31 a Friday (5), 2000-01-01 a Saturday (6).
#[test]
fn dates_before_2000_read_as_the_controller_writes_them() {
    let mut i = load(CLOCKS);
    i.set_clock(Clock::at(1999, 12, 31, 23, 59, 59));
    let s = |i: &mut Interp, f: &str| func(i, f, &[]).string().unwrap().to_string();
    assert_eq!(s(&mut i, "date"), "1999-12-31");
    assert_eq!(s(&mut i, "time"), "23:59:59");
    assert_eq!(num(&mut i, "wday"), 5.0);
    i.advance(1.0 / 60.0);
    assert_eq!(s(&mut i, "date"), "2000-01-01");
    assert_eq!(s(&mut i, "time"), "00:00:00");
    assert_eq!(num(&mut i, "wday"), 6.0);
    i.set_clock(Clock::at(1970, 1, 1, 12, 0, 0));
    assert_eq!(s(&mut i, "date"), "1970-01-01");
    assert_eq!(num(&mut i, "wday"), 4.0);
}

const MOVES: &str = r#"MODULE M
  PERS tooldata tGrip := [TRUE,[[0,0,150],[1,0,0,0]],[1.5,[0,0,60],[1,0,0,0],0,0,0]];
  PERS wobjdata wConv := [FALSE,TRUE,"",[[300,100,200],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  VAR robtarget p1 := [[200,0,100],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget p2 := [[150,50,100],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget found;
  VAR jointtarget home := [[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC go()
    MoveJ p1, v100, fine, tGrip \WObj:=wConv;
  ENDPROC
  PROC search()
    SearchL \Stop, di1, found, p2, v100, tGrip \WObj:=wConv;
  ENDPROC
  PROC goHome()
    MoveAbsJ home, v100, fine, tool0;
  ENDPROC
  PROC shift()
    PDispSet [[100,0,0],[1,0,0,0]];
  ENDPROC
  FUNC robtarget here()
    RETURN CRobT(\Tool:=tGrip \WObj:=wConv);
  ENDFUNC
  FUNC robtarget hereAsMoved()
    RETURN CRobT();
  ENDFUNC
  FUNC robtarget flange()
    RETURN CRobT(\Tool:=tool0 \WObj:=wobj0);
  ENDFUNC
  FUNC jointtarget hereJ()
    RETURN CJointT();
  ENDFUNC
ENDMODULE
"#;

/// CRobT returns where the robot was sent, in the tool and work object
/// asked (the last move's where not given: the reference, CRobT) and the
/// displacement active now; CJointT its joints. By hand: p1 (200, 0, 100)
/// in wConv (uframe at (300, 100, 200)) is the TCP at (500, 100, 300) in
/// the world; the tool (150 mm along z) points down (180° about y), so
/// the flange is at (500, 100, 450).
#[test]
fn the_robot_is_where_the_last_move_sent_it() {
    let mut i = load(MOVES);
    // p1 in a configuration its flange pose has.
    let (conf, want) = conf_for([500.0, 100.0, 450.0], [0.0, 0.0, 1.0, 0.0]);
    let p1 = kin::robtarget([200.0, 0.0, 100.0], [0.0, 0.0, 1.0, 0.0], conf, [9e9; 6]);
    i.set_global("p1", p1).unwrap();
    let e = i.call_func("here", &[]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported, "no move yet: {e:?}");
    i.call_proc("go", &[]).unwrap();
    let here = func(&mut i, "here", &[]).numbers();
    assert!(close(&here[..3], &[200.0, 0.0, 100.0], 1e-9), "{here:?}");
    let asmoved = func(&mut i, "hereAsMoved", &[]).numbers();
    assert!(close(&asmoved[..7], &here[..7], 1e-12));
    let flange = func(&mut i, "flange", &[]).numbers();
    assert!(
        close(&flange[..3], &[500.0, 100.0, 450.0], 1e-9),
        "{flange:?}"
    );
    assert!(close(&flange[3..7], &[0.0, 0.0, 1.0, 0.0], 1e-12));
    assert_eq!(&here[7..11], &conf);
    // CJointT: the joints of that flange pose in p1's configuration.
    let j = func(&mut i, "hereJ", &[]).numbers();
    assert!(close(&j[..6], &want, 1e-6), "{j:?} {want:?}");
    // A displacement of 100 mm along x set after the move: the robot
    // stands where it stood, read 100 mm less along x.
    i.call_proc("shift", &[]).unwrap();
    let here = func(&mut i, "here", &[]).numbers();
    assert!(close(&here[..3], &[100.0, 0.0, 100.0], 1e-9), "{here:?}");
    i.restart().unwrap();

    // A search's found point: the commanded end point (no sensor).
    i.call_proc("search", &[]).unwrap();
    assert_eq!(i.global("found"), i.global("p2"));
    // MoveAbsJ: CJointT gives its joints back.
    i.call_proc("goHome", &[]).unwrap();
    assert_eq!(
        func(&mut i, "hereJ", &[]).numbers()[..6],
        [0.0, 0.0, 0.0, 0.0, 30.0, 0.0]
    );
}

const TELL: &str = r#"MODULE M
  PROC tell()
    ErrWrite \I, "RtWarm: state kept", "warm arm, 12 min stopped" \RL2:="second line";
    TPWrite "drift mm " \Num:=2.5;
    ErrWrite \W, "clock jump", "the wall clock moved";
    ErrWrite "failed", "why";
  ENDPROC
ENDMODULE
"#;

/// The reference, ErrWrite (\W warning, \I information, else an error;
/// header, reason, \RL2..\RL4) and TPWrite (the string, then \Num).
#[test]
fn operator_messages_are_kept_in_order() {
    let mut i = load(TELL);
    assert!(i.messages().is_empty());
    i.call_proc("tell", &[]).unwrap();
    let m = i.messages();
    assert_eq!(m.len(), 4);
    assert_eq!(m[0].kind, MessageKind::Info);
    assert_eq!(m[0].header, "RtWarm: state kept");
    assert_eq!(m[0].reasons, ["warm arm, 12 min stopped", "second line"]);
    assert_eq!(m[1].kind, MessageKind::Pendant);
    assert_eq!(m[1].header, "drift mm 2.5");
    assert_eq!(m[2].kind, MessageKind::Warning);
    assert_eq!(m[3].kind, MessageKind::Error);
    assert_eq!(m[3].reasons, ["why"]);
}

const KEPT: &str = r#"MODULE M
  PERS num count := 0;
  VAR num seen := 0;
  VAR clock c;
  PROC tick()
    count := count + 1;
    seen := seen + 1;
  ENDPROC
  PROC start()
    ClkStart c;
  ENDPROC
  FUNC num read()
    RETURN ClkRead(c);
  ENDFUNC
ENDMODULE
"#;

const OTHER: &str =
    "MODULE Other\n  VAR num n := 1;\n  PROC bump()\n    n := n + 1;\n  ENDPROC\nENDMODULE\n";

/// A power failure keeps every datum (VAR too) and the program
/// displacement; the time off is not counted by a running clock (the
/// interpreter's choice, the manual being silent). A module loaded again
/// takes its file's values, PERS ones too; the other modules keep theirs.
#[test]
fn power_failure_keeps_everything_and_a_reload_takes_the_files_values() {
    let mut i = Interp::load(
        &[("m.mod", KEPT.as_bytes()), ("other.mod", OTHER.as_bytes())],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    i.set_clock(Clock::at(2026, 11, 27, 10, 0, 0));
    i.call_proc("tick", &[]).unwrap();
    i.call_proc("bump", &[]).unwrap();
    i.call_proc("start", &[]).unwrap();
    i.advance(1.0);
    i.power_fail(10.0);
    assert_eq!(i.clock(), Clock::at(2026, 11, 27, 10, 11, 0));
    assert_eq!(i.global("seen"), Some(&Value::Num(1.0)));
    assert_eq!(i.global("count"), Some(&Value::Num(1.0)));
    assert_eq!(num(&mut i, "read"), 60.0);
    i.advance(1.0);
    assert_eq!(num(&mut i, "read"), 120.0);

    let edited = KEPT
        .replace("count := 0", "count := 5")
        .replace("seen := 0", "seen := 7");
    i.reload_module("M", edited.as_bytes()).unwrap();
    assert_eq!(i.global("count"), Some(&Value::Num(5.0)));
    assert_eq!(i.global("seen"), Some(&Value::Num(7.0)));
    assert_eq!(num(&mut i, "read"), 0.0, "its VAR clock reset");
    assert_eq!(
        i.global("n"),
        Some(&Value::Num(2.0)),
        "the other module's kept"
    );
    i.call_proc("tick", &[]).unwrap();
    assert_eq!(i.global("count"), Some(&Value::Num(6.0)));
    assert!(i
        .reload_module("Nope", b"MODULE Nope\nENDMODULE\n")
        .is_err());
}

const EXPR: &str = r#"MODULE A
  LOCAL VAR num k := 1;
  CONST pos rtD{3,4} := [[[1,2,3],[4,5,6],[7,8,9],[10,11,12]],
    [[13,14,15],[16,17,18],[19,20,21],[22,23,24]],
    [[25,26,27],[28,29,30],[31,32,33],[34,35,36]]];
  CONST num cube{2,2,2} := [[[1,2],[3,4]],[[5,6],[7,8]]];
  VAR pos store{2};
  LOCAL FUNC num f()
    RETURN 10;
  ENDFUNC
  FUNC num getA()
    RETURN k + f();
  ENDFUNC
  FUNC pos mix(num e1, num e2)
    RETURN e1 * rtD{2,1} + rtD{3,4} * e2 - rtD{1,1} - rtD{1,2};
  ENDFUNC
  FUNC pos neg()
    RETURN -rtD{1,2};
  ENDFUNC
  FUNC num corner()
    RETURN cube{2,1,2} + cube{1,2,1};
  ENDFUNC
  FUNC bool has(\wobjdata W)
    RETURN Present(W);
  ENDFUNC
  FUNC bool passOn(\wobjdata W)
    RETURN has(\W?W);
  ENDFUNC
  FUNC jointtarget cj(robtarget p \wobjdata W)
    RETURN CalcJointT(p, tool0 \WObj?W);
  ENDFUNC
  PROC keep(num x)
    store{2}.y := x;
  ENDPROC
ENDMODULE
"#;

const EXPR_B: &str = "MODULE B\n  VAR num k := 100;\n  FUNC num f()\n    RETURN 1000;\n  ENDFUNC\n  FUNC num getB()\n    RETURN k + f();\n  ENDFUNC\nENDMODULE\n";

/// What the module's arithmetic needs, worked by hand: 2·(13,14,15) +
/// (34,35,36)·3 − (1,2,3) − (4,5,6) = (26+102−1−4, 28+105−2−5,
/// 30+108−3−6) = (123, 126, 129); cube{2,1,2} + cube{1,2,1} = 6 + 3; a
/// LOCAL datum and routine hide the global ones of another module in
/// their own; `\W?W` passes an argument on only where the caller got one.
#[test]
fn the_modules_expressions_locals_and_conditional_arguments() {
    let mut i = Interp::load(
        &[("a.mod", EXPR.as_bytes()), ("b.mod", EXPR_B.as_bytes())],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    let n = |v: f64| CallArg::Value(Value::Num(v));
    let p = func(&mut i, "mix", &[n(2.0), n(3.0)]);
    assert_eq!(p, kin::pos([123.0, 126.0, 129.0]));
    assert_eq!(func(&mut i, "neg", &[]), kin::pos([-4.0, -5.0, -6.0]));
    assert_eq!(num(&mut i, "corner"), 9.0);
    assert_eq!(num(&mut i, "getA"), 11.0);
    assert_eq!(num(&mut i, "getB"), 1100.0);
    // From outside, the global datum (B's), not A's LOCAL one.
    assert_eq!(i.global("k"), Some(&Value::Num(100.0)));
    assert!(i
        .call_func("f", &[])
        .is_ok_and(|(v, _)| v == Value::Num(1000.0)));

    assert_eq!(func(&mut i, "passOn", &[]), Value::Bool(false));
    let w = i.global("wobj0").unwrap().clone();
    let given = [CallArg::Named("W".into(), w.clone())];
    assert_eq!(func(&mut i, "passOn", &given), Value::Bool(true));
    let p = down_at([400.0, 50.0, 500.0]);
    let without = func(&mut i, "cj", &[CallArg::Value(p.clone())]);
    let with = func(
        &mut i,
        "cj",
        &[CallArg::Value(p), CallArg::Named("W".into(), w)],
    );
    assert_eq!(without, with);
}

/// Single precision applies to every value stored: a component of a
/// record in an array, a clock's read, a robot function's result; and
/// each built-in call, expression node and statement is counted (by
/// hand: `RETURN ClkRead(c)` is one statement, two expression nodes, the
/// call and its argument, and one built-in call).
#[test]
fn single_precision_reaches_records_and_clock_reads_and_ops_are_counted() {
    let mut i = Interp::load(
        &[
            ("a.mod", EXPR.as_bytes()),
            ("m.mod", KEPT.replace("MODULE M", "MODULE K").as_bytes()),
        ],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    i.set_precision(Precision::Single).unwrap();
    i.call_proc("keep", &[CallArg::Value(Value::Num(1.0 / 3.0))])
        .unwrap();
    let y = i.global("store").unwrap().numbers()[4];
    assert_eq!(y, f64::from((1.0f64 / 3.0) as f32));
    i.call_proc("start", &[]).unwrap();
    i.advance(0.0123456);
    let (v, ops) = i.call_func("read", &[]).unwrap();
    assert_eq!(v, Value::Num(f64::from(0.741f32)));
    assert_eq!((ops.statements, ops.expressions, ops.builtins), (1, 2, 1));
    let p = down_at([400.0, 50.0, 500.0]);
    let j = func(&mut i, "cj", &[CallArg::Value(p)]);
    for x in j.numbers() {
        assert_eq!(x, f64::from(x as f32));
    }
}
