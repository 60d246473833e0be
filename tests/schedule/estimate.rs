//! Schedule estimation on small programs whose timing is computed by hand,
//! on every sample, and round trips through the schedule file format.

use approx::assert_abs_diff_eq;
use rapidtherm::error::ErrorKind;
use rapidtherm::rapid;
use rapidtherm::robot::{Joints, Robot};
use rapidtherm::schedule::{estimate, Estimate, EstimateOptions, Schedule};
use std::path::Path;

const EAX: &str = "[9E9,9E9,9E9,9E9,9E9,9E9]";

/// A robtarget pointing down (tool0 z along -z) at x, y, z.
fn down(x: f64, y: f64, z: f64) -> String {
    format!("[[{x},{y},{z}],[0,0,1,0],[0,0,0,0],{EAX}]")
}

fn run(src: &str, opts: &EstimateOptions) -> Estimate {
    let program = rapid::parse("t.mod", src.as_bytes()).unwrap_or_else(|e| panic!("{e}"));
    estimate(&program, &Robot::irb140(), opts).unwrap_or_else(|e| panic!("{e}"))
}

fn main_opts() -> EstimateOptions {
    EstimateOptions::default()
}

/// Seconds between two minute values.
fn secs(a: f64, b: f64) -> f64 {
    (b - a) * 60.0
}

const TWO_POINTS: &str = "
    CONST robtarget pA := [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pB := [[500,100,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];";

#[test]
fn two_moves_a_wait_and_a_loop() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    PROC main()
        VAR num i;
        MoveL pA, v100, fine, tool0;
        MoveL pB, v100, fine, tool0;
        WaitTime 2;
        FOR i FROM 1 TO 3 DO
            MoveL pA, v100, fine, tool0;
            MoveL pB, v100, fine, tool0;
        ENDFOR
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    let a = est.schedule.times("pA").unwrap();
    let b = est.schedule.times("PB").unwrap();
    assert_eq!(a.len(), 4, "pA: once before the loop, 3 times in it");
    assert_eq!(b.len(), 4);
    // First move: from the calibration pose (flange 515, 0, 712, spec
    // check pose) to pA: 312.36 mm at 100 mm/s (the 90° reorientation at
    // 500°/s is quicker).
    let first = (15f64.powi(2) + 312f64.powi(2)).sqrt() / 100.0;
    assert_abs_diff_eq!(a[0] * 60.0, first, epsilon = 1e-6);
    // 100 mm at v100 = 1 s; WaitTime 2; then 1 s per move.
    let expect_b = [1.0, 5.0, 7.0, 9.0];
    let expect_a = [0.0, 4.0, 6.0, 8.0];
    for k in 0..4 {
        assert_abs_diff_eq!(secs(a[0], a[k]), expect_a[k], epsilon = 1e-6);
        assert_abs_diff_eq!(secs(a[0], b[k]), expect_b[k], epsilon = 1e-6);
    }
    assert_abs_diff_eq!(est.duration_min * 60.0, first + 9.0, epsilon = 1e-6);
    assert!(est.notes.is_empty(), "{:?}", est.notes);
}

#[test]
fn start_time_shifts_every_visit() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    PROC main()
        MoveL pA, v100, fine, tool0;
        MoveL pB, v100, fine, tool0;
    ENDPROC
ENDMODULE"
    );
    let at0 = run(&src, &main_opts());
    let at40 = run(
        &src,
        &EstimateOptions {
            start_min: 40.0,
            ..main_opts()
        },
    );
    for id in ["pA", "pB"] {
        assert_abs_diff_eq!(
            at40.schedule.times(id).unwrap()[0] - at0.schedule.times(id).unwrap()[0],
            40.0,
            epsilon = 1e-9
        );
    }
    assert_abs_diff_eq!(at40.duration_min, at0.duration_min, epsilon = 1e-9);
}

#[test]
fn procedure_calls_arguments_and_cycles() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    CONST num nTimes := 2;
    PROC main()
        Go pA;
        Go pB;
    ENDPROC
    PROC Go(robtarget p)
        VAR num k;
        FOR k FROM nTimes TO 1 DO
            MoveL p, v100, fine, tool0;
            WaitTime 1;
        ENDFOR
    ENDPROC
ENDMODULE"
    );
    let once = run(&src, &main_opts());
    // FOR 2 TO 1 counts down (RAPID's default step is -1 there): 2 turns.
    assert_eq!(once.schedule.times("pA").unwrap().len(), 2);
    let a = once.schedule.times("pA").unwrap();
    let b = once.schedule.times("pB").unwrap();
    // pA (wait 1) pA again (0 mm, wait 1) pB (100 mm: 1 s).
    assert_abs_diff_eq!(secs(a[0], a[1]), 1.0, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(a[0], b[0]), 3.0, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(a[0], b[1]), 4.0, epsilon = 1e-6);

    let three = run(
        &src,
        &EstimateOptions {
            cycles: 3,
            ..main_opts()
        },
    );
    let a3 = three.schedule.times("pA").unwrap();
    assert_eq!(a3.len(), 6);
    // The second cycle starts at the end of the first (after its last
    // WaitTime 1) and moves 100 mm back to pA: 1 s.
    assert_abs_diff_eq!(secs(b[1], a3[2]), 2.0, epsilon = 1e-6);
    assert_eq!(three.schedule.times("pB").unwrap().len(), 6);
}

#[test]
fn program_speeddata_and_v_t_overrides() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    CONST speeddata vSlow := [50, 500, 5000, 1000];
    PROC main()
        MoveL pA, v100, fine, tool0;
        MoveL pB, vSlow, fine, tool0;
        MoveL pA, v100 \\V:=200, fine, tool0;
        MoveL pB, v100 \\T:=4, fine, tool0;
        MoveL pA, [25, 500, 5000, 1000], fine, tool0;
        VelSet 50, 800;
        MoveL pB, v100, fine, tool0;
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    let a = est.schedule.times("pA").unwrap();
    let b = est.schedule.times("pB").unwrap();
    assert_abs_diff_eq!(secs(a[0], b[0]), 2.0, epsilon = 1e-6); // 100 mm at 50
    assert_abs_diff_eq!(secs(b[0], a[1]), 0.5, epsilon = 1e-6); // \V:=200
    assert_abs_diff_eq!(secs(a[1], b[1]), 4.0, epsilon = 1e-6); // \T:=4
    assert_abs_diff_eq!(secs(b[1], a[2]), 4.0, epsilon = 1e-6); // literal 25 mm/s
    assert_abs_diff_eq!(secs(a[2], b[2]), 2.0, epsilon = 1e-6); // VelSet 50 %
}

#[test]
fn reorientation_limited_by_v_ori() {
    // Same point, turned 90° about z: v_ori 30°/s -> 3 s.
    let src = format!(
        "MODULE T
    CONST speeddata vTurn := [100, 30, 5000, 1000];
    PROC main()
        MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],{EAX}], v100, fine, tool0;
        MoveL [[500,0,400],[0,0.7071068,0.7071068,0],[0,0,0,0],{EAX}], vTurn, fine, tool0;
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    let t1 = est.schedule.times("main#1").unwrap()[0];
    let t2 = est.schedule.times("main#2").unwrap()[0];
    assert_abs_diff_eq!(secs(t1, t2), 3.0, epsilon = 1e-5);
}

fn jt(q: [f64; 6]) -> String {
    format!(
        "[[{},{},{},{},{},{}],{EAX}]",
        q[0], q[1], q[2], q[3], q[4], q[5]
    )
}

#[test]
fn joint_moves_from_joint_distance_and_max_speeds() {
    let robot = Robot::irb140();
    let q1 = [0.0, 10.0, 10.0, 0.0, 40.0, 0.0];
    // Axis 1 by 60° (200°/s: 0.3 s), axis 6 by 90° (450°/s: 0.2 s).
    let q2 = [60.0, 10.0, 10.0, 0.0, 40.0, 90.0];
    let rad: Joints = q2.map(f64::to_radians);
    let flange = robot.fk(&rad);
    let conf = robot.conf_of(&rad);
    let (t, r) = rapidtherm::robot::frames::pose_to_rapid(&flange);
    let p2 = format!(
        "[[{},{},{}],[{},{},{},{}],[{},{},{},{}],{EAX}]",
        t[0], t[1], t[2], r[0], r[1], r[2], r[3], conf.cf1, conf.cf4, conf.cf6, conf.cfx
    );
    let src = format!(
        "MODULE T
    PROC main()
        MoveAbsJ {}, v5000, fine, tool0;
        MoveJ {p2}, v5000, fine, tool0;
        MoveAbsJ {}, v5000, fine, tool0;
        MoveAbsJ {}, v5, fine, tool0;
    ENDPROC
ENDMODULE",
        jt(q1),
        jt(q1),
        jt(q2),
    );
    let est = run(&src, &main_opts());
    // Jointtargets: their own name space (main#1..3); robtarget main#1.
    let j = est.joint_schedule.times("main#1").unwrap()[0];
    // From the calibration pose: axis 5 by 40° at 360°/s is the slowest
    // axis (0.111 s) unless the TCP at v5000 is slower: it is not.
    assert_abs_diff_eq!(j * 60.0, 40.0 / 360.0, epsilon = 1e-6);
    let p = est.schedule.times("main#1").unwrap()[0];
    assert_abs_diff_eq!(secs(j, p), 0.3, epsilon = 1e-6);
    let back = est.joint_schedule.times("main#2").unwrap()[0];
    assert_abs_diff_eq!(secs(p, back), 0.3, epsilon = 1e-6);
    // At v5 the TCP (moving about 1 m on the chord... here the straight
    // line between the flange poses) limits the move.
    let last = est.joint_schedule.times("main#3").unwrap()[0];
    let chord =
        (robot.fk(&q1.map(f64::to_radians)).translation.vector - flange.translation.vector).norm();
    assert_abs_diff_eq!(secs(back, last), chord / 5.0, epsilon = 1e-6);
}

#[test]
fn circular_move_by_arc_length() {
    // Half circle of radius 50 mm at v100: 157.08 mm = 1.5708 s; the
    // CirPoint is reached half way.
    let src = format!(
        "MODULE T
    PROC main()
        MoveL {}, v100, fine, tool0;
        MoveC {}, {}, v100, fine, tool0;
    ENDPROC
ENDMODULE",
        down(500.0, 0.0, 400.0),
        down(550.0, 50.0, 400.0),
        down(600.0, 0.0, 400.0)
    );
    let est = run(&src, &main_opts());
    let t0 = est.schedule.times("main#1").unwrap()[0];
    let cir = est.schedule.times("main#2").unwrap()[0];
    let end = est.schedule.times("main#3").unwrap()[0];
    let half = std::f64::consts::PI * 50.0;
    assert_abs_diff_eq!(secs(t0, end), half / 100.0, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(t0, cir), half / 200.0, epsilon = 1e-6);
}

#[test]
fn derived_targets_and_tool_frames() {
    // tool 100 mm along z; Offs in the work object frame; RelTool along
    // the tool's z (pointing down: -z in the base).
    let src = format!(
        "MODULE T{TWO_POINTS}
    PERS tooldata tLong := [TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];
    PERS wobjdata wUp := [FALSE,TRUE,\"\",[[0,0,50],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    VAR robtarget pUp;
    PROC main()
        MoveL pA, v100, fine, tLong\\WObj:=wUp;
        MoveL Offs(pA, 0, 0, 100), v100, fine, tLong\\WObj:=wUp;
        pUp := RelTool(pA, 0, 0, -50);
        MoveL pUp, v100, fine, tLong\\WObj:=wUp;
        MoveL pUp, v100, fine, tLong\\WObj:=wUp;
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    let a = est.schedule.times("pA").unwrap();
    let offs = est.schedule.times("main@1").unwrap();
    let rel = est.schedule.times("main@2").unwrap();
    assert_eq!(a.len(), 1, "pA reached directly: no visits through Offs");
    assert_abs_diff_eq!(secs(a[0], offs[0]), 1.0, epsilon = 1e-6);
    // RelTool -50 along a tool z pointing down: 50 mm up, 100 - 50 = 50 mm
    // from the Offs pose.
    assert_abs_diff_eq!(secs(offs[0], rel[0]), 0.5, epsilon = 1e-6);
    assert_eq!(rel.len(), 2);
    assert_abs_diff_eq!(secs(rel[0], rel[1]), 0.0, epsilon = 1e-9);
    assert!(est.schedule.times("pB").is_none());
    assert!(
        est.notes.iter().any(|n| n.contains("pB")),
        "{:?}",
        est.notes
    );
}

#[test]
fn base_reached_only_through_offs_gets_those_visits() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    PROC main()
        MoveL Offs(pB, 0, 0, 10), v100, fine, tool0;
        MoveL Offs(pB, 0, 0, 20), v100, fine, tool0;
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    let b = est.schedule.times("pB").unwrap();
    assert_eq!(b.len(), 2);
    assert_eq!(b[0], est.schedule.times("main@1").unwrap()[0]);
    assert_eq!(b[1], est.schedule.times("main@2").unwrap()[0]);
}

#[test]
fn control_flow_choices_are_documented() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    CONST bool bDry := FALSE;
    CONST num nMode := 2;
    VAR num nRun;
    PROC main()
        IF bDry THEN
            MoveL pB, v100, fine, tool0;
        ELSE
            MoveL pA, v100, fine, tool0;
        ENDIF
        TEST nMode
        CASE 1:
            WaitTime 100;
        CASE 2, 3:
            WaitTime 1;
        DEFAULT:
            WaitTime 50;
        ENDTEST
        IF nRun > 3 THEN
            WaitTime 2;
        ELSE
            WaitTime 200;
        ENDIF
        WHILE nRun < 10 DO
            WaitTime 3;
        ENDWHILE
        GOTO skip;
        WaitTime 500;
        skip:
        WaitDI diReady, 1;
        SomeVendorProc;
        MoveL pB, v100, fine, tool0;
        again:
        IF nRun > 0 GOTO again;
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    let a = est.schedule.times("pA").unwrap();
    let b = est.schedule.times("pB").unwrap();
    assert_eq!(a.len(), 1, "constant FALSE IF: the ELSE branch");
    // TEST 2 -> 1 s; unknown IF -> first branch 2 s; WHILE once 3 s;
    // forward GOTO skips 500 s; WaitDI 0 s; pB 1 s.
    assert_abs_diff_eq!(secs(a[0], b[0]), 1.0 + 2.0 + 3.0 + 1.0, epsilon = 1e-6);
    let notes = est.notes.join("\n");
    for needle in [
        "t.mod:21 (main): IF",
        "t.mod:26 (main): WHILE",
        "WaitDI",
        "SomeVendorProc",
        "GOTO again jumps back",
    ] {
        assert!(notes.contains(needle), "missing {needle:?} in\n{notes}");
    }
    assert!(
        !notes.contains("TEST"),
        "constant TEST needs no note:\n{notes}"
    );
}

#[test]
fn conc_lets_the_program_run_on() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    PROC main()
        MoveL pA, v100, fine, tool0;
        MoveL pB, v100, fine, tool0 \\Conc;
        WaitTime 0.25;
        MoveL pA, v100, fine, tool0;
        WaitTime \\InPos, 1;
        MoveL pB, v100, fine, tool0;
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    let a = est.schedule.times("pA").unwrap();
    let b = est.schedule.times("pB").unwrap();
    // The WaitTime runs during the concurrent move: pA is back 2 s after.
    assert_abs_diff_eq!(secs(a[0], b[0]), 1.0, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(a[0], a[1]), 2.0, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(a[1], b[1]), 2.0, epsilon = 1e-6);
}

#[test]
fn recursion_is_not_followed_forever() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    PROC main()
        Loop;
    ENDPROC
    PROC Loop()
        MoveL pA, v100, fine, tool0;
        Loop;
    ENDPROC
ENDMODULE"
    );
    let est = run(&src, &main_opts());
    assert_eq!(est.schedule.times("pA").unwrap().len(), 1);
    assert!(est
        .notes
        .iter()
        .any(|n| n.contains("recursive call of Loop")));
}

#[test]
fn errors_name_what_is_wrong() {
    let program = rapid::parse(
        "t.mod",
        format!(
            "MODULE T\n PROC rMain()\n  MoveJ {}, v100, fine, tool0;\n ENDPROC\nENDMODULE\n",
            down(2000.0, 0.0, 400.0)
        )
        .as_bytes(),
    )
    .unwrap();
    let robot = Robot::irb140();
    let e = estimate(&program, &robot, &main_opts()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    assert!(e.message.contains("`main`"), "{e}");
    assert!(e.notes.iter().any(|n| n.contains("rMain")), "{e}");
    let opts = EstimateOptions {
        entry: "RMAIN".into(),
        ..main_opts()
    };
    let e = estimate(&program, &robot, &opts).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert!(e.message.contains("rMain#1"), "{e}");
    assert_eq!(e.location.unwrap().line, 3);
    let bad = EstimateOptions {
        start_min: f64::NAN,
        ..opts
    };
    assert!(estimate(&program, &robot, &bad).is_err());
}

#[test]
fn huge_loops_are_refused_not_run_for_hours() {
    let src = format!(
        "MODULE T{TWO_POINTS}
    PROC main()
        VAR num i;
        FOR i FROM 1 TO 1E12 DO
            WaitTime 1;
        ENDFOR
    ENDPROC
ENDMODULE"
    );
    let program = rapid::parse("t.mod", src.as_bytes()).unwrap();
    // Bounded by a step budget: an error, not a hang. (Debug builds run the
    // 50 M statements in a few seconds.)
    let e = estimate(&program, &Robot::irb140(), &main_opts()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported);
}

// ------------------------------------------------------------------ samples

fn sample(name: &str) -> rapid::Program {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("samples")
        .join(name);
    let bytes = std::fs::read(&path).unwrap();
    rapid::parse(name, &bytes).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_sample_schedules() {
    let robot = Robot::irb140();
    for (name, entry) in [
        ("arc_pendant.mod", "main"),
        ("cam_contour.mod", "main"),
        ("control_flow.mod", "main"),
        ("deburr_mixed_eol.modx", "main"),
        ("fixtures.mod", "main"),
        ("inspection_bom.prg", "main"),
        ("process_lib.sys", "rBead"),
        ("service_positions.mod", "rCalibrate"),
        ("two_modules.mod", "main"),
        ("weld_cell_latin1.mod", "Naht1"),
    ] {
        let program = sample(name);
        let opts = EstimateOptions {
            entry: entry.into(),
            start_min: 40.0,
            cycles: 2,
            ..main_opts()
        };
        let est = estimate(&program, &robot, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!est.schedule.is_empty(), "{name}");
        assert!(est.duration_min > 0.0, "{name}");
        // Every identifier is one of the program's, every time in range.
        for id in est.schedule.targets() {
            assert!(program.target(id).is_some(), "{name}: {id}");
            for &t in est.schedule.times(id).unwrap() {
                assert!(
                    (40.0..=40.0 + est.duration_min + 1e-9).contains(&t),
                    "{name}: {id} {t}"
                );
            }
        }
        for id in est.joint_schedule.targets() {
            assert!(
                program
                    .jointtargets()
                    .iter()
                    .any(|j| j.id.eq_ignore_ascii_case(id)),
                "{name}: {id}"
            );
        }
        // Round trip through the file format, each name space its own
        // (a file that says rows' kinds keeps the jointtargets apart).
        let read = Schedule::read_file("s.csv", est.to_csv().as_bytes(), None).unwrap();
        let joints_back = read.joints.as_ref().unwrap_or(&read.schedule);
        for (kept, back) in [
            (&est.schedule, &read.schedule),
            (&est.joint_schedule, joints_back),
        ] {
            for id in kept.targets() {
                let (x, y) = (kept.times(id).unwrap(), back.times(id).unwrap());
                assert_eq!(x.len(), y.len(), "{name}: {id}");
                for (x, y) in x.iter().zip(y) {
                    assert_abs_diff_eq!(x, y, epsilon = 1e-4);
                }
            }
        }
    }
}

#[test]
fn two_modules_follow_the_late_bound_call_into_the_local_main() {
    let est = estimate(&sample("two_modules.mod"), &Robot::irb140(), &main_opts()).unwrap();
    let order: Vec<&str> = est.schedule.targets().collect();
    assert_eq!(
        order,
        [
            "MainModule:p10",
            "p20",
            "MainModule:main#1",
            "Station2:p10",
            "pPlace",
            "Station2:main#1"
        ]
    );
}

#[test]
fn control_flow_sample_runs_the_pallet_loops() {
    let est = estimate(&sample("control_flow.mod"), &Robot::irb140(), &main_opts()).unwrap();
    // nRows × nCols = 3 × 2 picks and places.
    assert_eq!(est.schedule.times("pPick").unwrap().len(), 6);
    assert_eq!(est.schedule.times("PlacePart#1").unwrap().len(), 6);
    // Home() returns the literal of FUNC Home: that literal is reached.
    assert_eq!(est.schedule.times("Home#1").unwrap().len(), 1);
    // pPallet only through Offs: it gets those visits.
    assert_eq!(est.schedule.times("pPallet").unwrap().len(), 12);
}

#[test]
fn service_positions_loop_over_dim() {
    let opts = EstimateOptions {
        entry: "rCalibrate".into(),
        ..main_opts()
    };
    let est = estimate(&sample("service_positions.mod"), &Robot::irb140(), &opts).unwrap();
    let j = &est.joint_schedule;
    for k in 1..=3 {
        assert_eq!(j.times(&format!("jCalib{{{k}}}")).unwrap().len(), 1);
    }
    // jCalib{1} -> {2} after WaitTime \InPos 2: axis 1 turns 75° at
    // 200°/s (0.375 s, the slowest axis), but the TCP (tool0) travels
    // further than 0.375 s at v200 allows: the straight line between the
    // flange poses at 200 mm/s sets the time.
    let robot = Robot::irb140();
    let q1 = [30.0, 20.0, -40.0, 50.0, 60.0, 70.0].map(f64::to_radians);
    let q2 = [-45.0, 10.0, -10.0, -60.0, 45.0, -90.0].map(f64::to_radians);
    let chord = (robot.fk(&q1).translation.vector - robot.fk(&q2).translation.vector).norm();
    assert!(chord / 200.0 > 0.375);
    let t1 = j.times("jCalib{1}").unwrap()[0];
    let t2 = j.times("jCalib{2}").unwrap()[0];
    assert_abs_diff_eq!(secs(t1, t2), 2.0 + chord / 200.0, epsilon = 1e-6);
}

/// Independent of the RAPID reader: the path length of the CAM sample's
/// v100 moves, read straight from the text.
#[test]
fn cam_duration_is_path_length_over_speed() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("samples/cam_contour.mod"),
    )
    .unwrap();
    let points: Vec<[f64; 3]> = text
        .lines()
        .filter(|l| l.starts_with("MoveL [[") && l.contains(",v100,"))
        .map(|l| {
            let inner = &l["MoveL [[".len()..];
            let xyz: Vec<f64> = inner
                .split(']')
                .next()
                .unwrap()
                .split(',')
                .map(|v| v.parse().unwrap())
                .collect();
            [xyz[0], xyz[1], xyz[2]]
        })
        .collect();
    assert!(points.len() >= 5000);
    let path: f64 = points
        .windows(2)
        .map(|w| {
            ((w[1][0] - w[0][0]).powi(2)
                + (w[1][1] - w[0][1]).powi(2)
                + (w[1][2] - w[0][2]).powi(2))
            .sqrt()
        })
        .sum();
    let est = estimate(&sample("cam_contour.mod"), &Robot::irb140(), &main_opts()).unwrap();
    let first = est.schedule.times("main#1").unwrap()[0];
    let last_v100 = est
        .schedule
        .times(&format!("main#{}", points.len()))
        .unwrap()[0];
    // Reorientations are tiny here: the TCP path sets the time.
    assert_abs_diff_eq!(
        secs(first, last_v100),
        path / 100.0,
        epsilon = 1e-3 * path / 100.0
    );
    // The rest (MoveAbsJ, approach, retract) takes seconds, not minutes.
    let rest = est.duration_min * 60.0 - path / 100.0;
    assert!(rest > 0.0 && rest < 20.0, "rest {rest} s");
}

/// 64 routines each calling the next from inside 60 nested IFs, the last
/// one moving to an expression 45 brackets deep: the walk must not
/// overflow a test thread's stack (2 MB).
#[test]
fn deep_nesting_does_not_overflow_the_stack() {
    let mut src = String::from("MODULE Deep\n  CONST robtarget pA := ");
    src.push_str(&down(500.0, 0.0, 400.0));
    src.push_str(";\n  PROC main()\n    r0;\n  ENDPROC\n");
    for r in 0..64 {
        src.push_str(&format!("  PROC r{r}()\n"));
        src.push_str(&"IF TRUE THEN\n".repeat(60));
        if r < 63 {
            src.push_str(&format!("r{};\n", r + 1));
        } else {
            src.push_str(&format!(
                "MoveL Offs(pA,0,0,{}10{}), v100, fine, tool0;\n",
                "(".repeat(45),
                ")".repeat(45)
            ));
        }
        src.push_str(&"ENDIF\n".repeat(60));
        src.push_str("  ENDPROC\n");
    }
    src.push_str("ENDMODULE\n");
    let est = run(&src, &main_opts());
    assert_eq!(est.schedule.times("r63@1").unwrap().len(), 1);
    assert_eq!(est.schedule.times("pA").unwrap().len(), 1);
}

/// Every target the robot cannot reach is listed, each once at its place,
/// up to 20 with the rest counted; a reachable target between them does
/// not stop the walk. (Before: MoveL to an unreachable target was timed
/// as NaN and the estimate returned `Ok`.)
#[test]
fn every_unreachable_target_is_listed_once() {
    let mut decls = String::new();
    let mut moves = String::new();
    for k in 0..25 {
        decls.push_str(&format!(
            " CONST robtarget pFar{k} := {};\n",
            down(3000.0 + f64::from(k), 0.0, 400.0)
        ));
        moves.push_str(&format!("  MoveL pFar{k}, v100, fine, tool0;\n"));
        moves.push_str(&format!(
            "  MoveL {}, v100, fine, tool0;\n",
            down(500.0, 0.0, 400.0)
        ));
    }
    let src = format!(
        "MODULE T\n{decls} PROC main()\n  FOR i FROM 1 TO 2 DO\n{moves}  ENDFOR\n ENDPROC\nENDMODULE\n"
    );
    let program = rapid::parse("t.mod", src.as_bytes()).unwrap_or_else(|e| panic!("{e}"));
    let e = estimate(&program, &Robot::irb140(), &main_opts()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert!(e.message.starts_with("25 targets"), "{e}");
    assert!(e.notes.iter().any(|n| n.contains("5 more")), "{e}");
    let related = e.related();
    assert_eq!(related.len(), 20);
    for (k, r) in related.iter().enumerate() {
        assert!(r.message.contains(&format!("pFar{k} ")), "{r}");
        assert_eq!(r.location.as_ref().map(|l| l.line), Some(k + 2));
    }
}

/// A target out of reach is found wherever its move falls among the
/// poses the walk leaves to another core: in the first chunk of
/// thousands (answered by that core while the walk goes on) or the last
/// (answered when the walk ends). Were either answer lost, the estimate
/// would time the move as if reached and return `Ok`.
#[test]
fn a_target_out_of_reach_is_found_in_any_chunk_of_poses() {
    let near = down(500.0, 0.0, 400.0);
    let far = down(3000.0, 0.0, 400.0);
    for far_first in [true, false] {
        let far_move = "  MoveL pFar, v100, fine, tool0;\n";
        let src = format!(
            "MODULE T\n CONST robtarget pFar := {far};\n CONST robtarget pNear := {near};\n PROC main()\n{}  FOR i FROM 1 TO 10000 DO\n   MoveL pNear, v100, fine, tool0;\n  ENDFOR\n{} ENDPROC\nENDMODULE\n",
            if far_first { far_move } else { "" },
            if far_first { "" } else { far_move },
        );
        let program = rapid::parse("t.mod", src.as_bytes()).unwrap_or_else(|e| panic!("{e}"));
        let e = estimate(&program, &Robot::irb140(), &main_opts()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Unreachable, "{e}");
        assert!(e.message.contains("pFar "), "{e}");
    }
}

/// An element `pA{i}` is the element of the array the name finds where a
/// plain name would be found: the routine's own array before the
/// module's, and a module's LOCAL array in that module only.
#[test]
fn array_elements_are_found_where_their_name_is() {
    let (a1, a2, b1, b2) = (
        down(500.0, 0.0, 400.0),
        down(500.0, 300.0, 400.0),
        down(500.0, 0.0, 300.0),
        down(500.0, 10.0, 300.0),
    );
    let src = format!(
        "MODULE T
    CONST robtarget pA{{2}} := [{a1},{a2}];
    PROC main()
        CONST robtarget pA{{2}} := [{b1},{b2}];
        VAR num i;
        FOR i FROM 1 TO 2 DO
            MoveL pA{{i}}, v100, fine, tool0;
        ENDFOR
        Other;
    ENDPROC
    PROC Other()
        MoveL pA{{2}}, v100, fine, tool0;
    ENDPROC
ENDMODULE"
    );
    let e = run(&src, &main_opts());
    let ids: Vec<&str> = e.schedule.targets().collect();
    // main's own pA{1}, pA{2} (10 mm apart), then the module's pA{2}.
    assert_eq!(ids.len(), 3, "{ids:?}");
    let own1 = e.schedule.times(ids[0]).unwrap()[0];
    let own2 = e.schedule.times(ids[1]).unwrap()[0];
    let module2 = e.schedule.times(ids[2]).unwrap()[0];
    assert!(ids[0].to_ascii_lowercase().contains("main"), "{ids:?}");
    assert!(!ids[2].to_ascii_lowercase().contains("main"), "{ids:?}");
    // 10 mm at 100 mm/s; then from main's pA{2} to the module's, 290 mm
    // in y and 100 mm in z.
    assert_abs_diff_eq!(secs(own1, own2), 0.1, epsilon = 1e-9);
    let d = (290.0f64.powi(2) + 100.0f64.powi(2)).sqrt();
    assert_abs_diff_eq!(secs(own2, module2), d / 100.0, epsilon = 1e-9);
}

/// An inline robtarget and an inline jointtarget get the same identifier
/// (`main#1`, two name spaces): the estimate says so, once, and its CSV
/// says each row's kind, so that reading it back keeps them apart.
#[test]
fn an_identifier_of_both_kinds_is_noted() {
    let src = format!(
        "MODULE T
    PROC main()
        MoveL {}, v100, fine, tool0;
        MoveAbsJ [[0,0,0,0,30,0],{EAX}], v100, fine, tool0;
    ENDPROC
ENDMODULE",
        down(500.0, 0.0, 400.0)
    );
    let e = run(&src, &main_opts());
    let clash: Vec<&String> = e
        .notes
        .iter()
        .filter(|n| n.contains("two name spaces"))
        .collect();
    assert_eq!(clash.len(), 1, "{:?}", e.notes);
    assert!(clash[0].contains("jointtarget main#1"), "{}", clash[0]);
    let csv = e.to_csv();
    let rows: Vec<&str> = csv.lines().filter(|l| l.starts_with("main#1")).collect();
    assert_eq!(csv.lines().next(), Some("target,time_min,kind"), "{csv}");
    assert_eq!(rows.len(), 2, "{csv}");
    assert!(rows[0].ends_with(",robtarget"), "{csv}");
    assert!(rows[1].ends_with(",jointtarget"), "{csv}");
    let read = rapidtherm::schedule::Schedule::read_file("s.csv", csv.as_bytes(), None).unwrap();
    let joints = read.joints.expect("the jointtargets' visits kept apart");
    assert_eq!(read.schedule.times("main#1").unwrap().len(), 1);
    assert_eq!(joints.times("main#1").unwrap().len(), 1);
    assert_ne!(read.schedule.times("main#1"), joints.times("main#1"));
}
