//! The rule of the main job: every target a program holds is corrected, or
//! reported with the reason it was not, and every use of a target with
//! another tool or work object than it is corrected for is reported; at
//! minute 0 no byte changes. Each case below was silently wrong before
//! (named in its test).

use rapidtherm::correct::{correct, Options, Outcome, Reason, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid::{self, Program, TargetKind};
use rapidtherm::resolve::{usages, uses_by_frames};
use rapidtherm::robot::Robot;
use std::path::PathBuf;

fn run(name: &str, bytes: &[u8], minute: f64) -> (Program, Outcome) {
    run_split(name, bytes, minute, false)
}

fn run_split(name: &str, bytes: &[u8], minute: f64, split: bool) -> (Program, Outcome) {
    let program = rapid::parse(name, bytes).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), minute).unwrap();
    let options = Options {
        split_shared: split,
        ..Options::new(When::At(Moment::Minute(minute)))
    };
    let outcome = correct(&program, &warm, &options, &mut |_, _| {})
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (program, outcome)
}

/// Every RAPID program of the samples and of the CLI tests that corrects
/// without error.
fn programs() -> Vec<(String, Vec<u8>)> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in ["samples", "tests/cmd/correct_data"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = entry.unwrap().path();
            let rapid = matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("mod" | "modx" | "prg" | "sys")
            );
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            // The error cases of the CLI tests, a corrected output, and
            // programs of other arms than the IRB 140 these run on.
            let refused = [
                "ur5_",
                "unreachable",
                "unknown",
                "conf_wrong",
                "several_errors",
                "bad_speeds",
                "declared_twice",
                "not_an_angle",
                "_at60",
                "_at120",
                "_start60",
                "beyond_limit",
                "confl_joint_move",
                "confl_uncalled",
                "confl_unsettled",
            ]
            .iter()
            .any(|k| name.contains(k));
            if rapid && !refused {
                out.push((name, std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    assert!(out.len() >= 12);
    out
}

#[test]
fn at_minute_zero_no_byte_changes_and_every_target_is_accounted_for() {
    for ((name, bytes), split) in programs()
        .into_iter()
        .flat_map(|p| [(p.clone(), false), (p, true)])
    {
        let (program, outcome) = run_split(&name, &bytes, 0.0, split);
        assert_eq!(outcome.outputs[0], bytes, "{name}: --at 0 changed bytes");
        // Every use with another tool or work object than its target's
        // first use has its line (a split needs numbers that differ, so
        // at minute 0 none is made).
        assert!(outcome.splits.is_empty(), "{name}: split at minute 0");
        for (&i, uses) in &usages(&program) {
            let t = program.targets().at(i);
            if !outcome.corrections.iter().any(|c| c.id == t.id) {
                continue;
            }
            for u in uses_by_frames(uses).iter().skip(1).flatten() {
                assert!(
                    outcome
                        .shared
                        .iter()
                        .any(|s| s.id == t.id && s.other.line == u.line),
                    "{name}: use of {} at line {} not reported",
                    t.id,
                    u.line
                );
            }
        }
        let reported = |id: &str| {
            outcome.corrections.iter().any(|c| c.id == id)
                || outcome.left_alone.iter().any(|l| l.id == id)
        };
        for t in program.targets().iter() {
            if t.kind == TargetKind::Derived && !t.written_with_expressions() {
                assert!(
                    outcome.derived.iter().any(|d| d.id == t.id),
                    "{name}: derived {} not reported",
                    t.id
                );
            } else {
                assert!(reported(&t.id), "{name}: robtarget {} not reported", t.id);
            }
        }
        for j in program.jointtargets() {
            assert!(reported(&j.id), "{name}: jointtarget {} not reported", j.id);
        }
    }
}

fn never_silent() -> Vec<u8> {
    std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/cmd/correct_data/never_silent.mod"),
    )
    .unwrap()
}

fn reason_of(outcome: &Outcome, id: &str) -> Option<Reason> {
    outcome
        .left_alone
        .iter()
        .find(|l| l.id == id)
        .map(|l| l.reason)
}

/// Before: `[[nX,0,300],...]` and `[[400,0,-300+600],...]` stayed cold
/// and nothing said so; a placeholder VAR stopped the run ("quaternion is
/// zero"); a positioner jointtarget was refused.
#[test]
fn targets_left_alone_say_why() {
    let (_, outcome) = run("n.mod", &never_silent(), 120.0);
    assert_eq!(reason_of(&outcome, "pNamed"), Some(Reason::Expression));
    assert_eq!(reason_of(&outcome, "pExpr"), Some(Reason::Expression));
    assert_eq!(reason_of(&outcome, "pUnloadA"), Some(Reason::Runtime));
    assert_eq!(reason_of(&outcome, "pApproach"), Some(Reason::Runtime));
    assert_eq!(reason_of(&outcome, "jPos"), Some(Reason::NoRobotAxes));
    assert_eq!(reason_of(&outcome, "jNamed"), Some(Reason::Expression));
    // What the placeholder is assigned from is corrected, in the frames of
    // the move through the placeholder.
    assert!(outcome.corrections.iter().any(|c| c.id == "pLage1A"));
}

/// Before: a base reached only through Offs was skipped and its derived
/// uses said it moved 0.0000 mm. Now it is corrected for the mean of its
/// uses, and each use's residual is small against the drift.
#[test]
fn a_base_reached_only_through_offs_lands_on_average() {
    let (_, outcome) = run("n.mod", &never_silent(), 120.0);
    let base = outcome
        .corrections
        .iter()
        .find(|c| c.id == "pPallet")
        .expect("pPallet corrected");
    assert!(base.drift_norm_mm > 0.03);
    let uses: Vec<f64> = outcome
        .derived
        .iter()
        .filter(|d| d.bases == ["pPallet"])
        .map(|d| d.residual_mm.expect("literal offsets: residual known"))
        .collect();
    assert_eq!(uses.len(), 2);
    for r in uses {
        assert!(r < 0.03, "residual {r} mm of a derived use");
    }
}

/// Before: `[[-60,40,-60,45,0,-70],...]` became `[[-60,40,-60,0,0,-25],...]`
/// even at minute 0. Now axis 4 keeps its value at the wrist singularity
/// and axis 6 stays near its own.
#[test]
fn a_wrist_singular_jointtarget_keeps_axis_4() {
    let (_, outcome) = run("n.mod", &never_silent(), 120.0);
    let j = outcome
        .corrections
        .iter()
        .find(|c| c.id == "jWrist")
        .unwrap();
    assert_eq!(j.corrected[3], 45.0);
    assert!((j.corrected[5] - -70.0).abs() < 0.1, "{:?}", j.corrected);
    assert!(j.dangle_deg < 0.5, "{:?}", j.corrected);
    let r = outcome.residuals.iter().find(|r| r.id == "jWrist").unwrap();
    assert!(r.position_mm < 1e-4, "the flange position is reached");
}

/// Asked to, a literal with expressions is written as numbers and
/// corrected like any other.
#[test]
fn expressions_are_written_as_numbers_only_when_asked() {
    let bytes = never_silent();
    let program = rapid::parse("n.mod", &bytes).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).unwrap();
    let options = Options {
        expand_expressions: true,
        ..Options::new(When::At(Moment::Minute(120.0)))
    };
    let outcome = correct(&program, &warm, &options, &mut |_, _| {}).unwrap();
    let named = outcome
        .corrections
        .iter()
        .find(|c| c.id == "pNamed")
        .unwrap();
    let expr = outcome
        .corrections
        .iter()
        .find(|c| c.id == "pExpr")
        .unwrap();
    // Both mean [400,0,300] in the same frames: the same correction.
    assert!((named.corrected[0] - expr.corrected[0]).abs() < 1e-12);
    assert!(named.correction_norm_mm > 0.03);
    let text = String::from_utf8_lossy(&outcome.outputs[0]);
    assert!(!text.contains("[[nX,0,300]"));
    assert!(
        text.contains("CONST num nX := 400;"),
        "the constant itself stays"
    );
}

/// A target in a work object a positioner moves is left alone with its
/// reason, not an error for the program.
#[test]
fn a_coordinated_target_is_left_alone() {
    let src = b"MODULE M
  PERS wobjdata wStn := [FALSE,FALSE,\"STN1\",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pOnStn := [[10,20,30],[0,0,1,0],[0,0,0,0],[0,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pFixed := [[450,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL pOnStn, v100, fine, tool0 \\WObj:=wStn;
    MoveL pFixed, v100, fine, tool0;
  ENDPROC
ENDMODULE
";
    let (_, outcome) = run("m.mod", src, 120.0);
    assert_eq!(reason_of(&outcome, "pOnStn"), Some(Reason::Coordinated));
    assert!(outcome.corrections.iter().any(|c| c.id == "pFixed"));
}
