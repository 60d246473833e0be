//! The correction checked independently on every sample program: the
//! corrected target, turned into joints by the controller's nominal model
//! and driven through the warm model, lands on the original target.

use crate::common;

use approx::assert_relative_eq;
use nalgebra::{Isometry3, UnitQuaternion};
use rapidtherm::compare::diff;
use rapidtherm::correct::{correct, Options, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid::{self, Program, TargetKind};
use rapidtherm::resolve::target_pose;
use rapidtherm::robot::frames::{flange_of_target, target_of_flange};
use rapidtherm::robot::Robot;
use rapidtherm::thermal::{default_profile, HeatingProfile};
use std::path::PathBuf;

fn sample_programs() -> Vec<(String, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples");
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("mod" | "modx" | "prg" | "sys")
            )
        })
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    out.sort();
    assert!(out.len() >= 8, "the samples folder holds the RAPID samples");
    out
}

fn at(minute: f64) -> Options {
    Options::new(When::At(Moment::Minute(minute)))
}

fn run(name: &str, bytes: &[u8], minute: f64) -> (Program, rapidtherm::correct::Outcome) {
    let program = rapid::parse(name, bytes).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), minute).unwrap();
    let outcome = correct(&program, &warm, &at(minute), &mut |_, _| {}).unwrap();
    (program, outcome)
}

/// Same rotation (q or −q) within `eps` per component.
fn same_rotation(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>, eps: f64) -> bool {
    let (a, b) = (a.quaternion(), b.quaternion());
    let d1 = (a.coords - b.coords).amax();
    let d2 = (a.coords + b.coords).amax();
    d1.min(d2) < eps
}

#[test]
fn corrected_targets_land_on_the_original_through_the_warm_model() {
    let minute = 120.0;
    let temps = default_profile().temps_at(minute).unwrap();
    let scales = Model::default().thermal.scales(&temps);
    let robot = Robot::irb140();
    let mut checked = 0;
    for (name, bytes) in sample_programs() {
        let (program, outcome) = run(&name, &bytes, minute);
        let meanings = common::Meanings::new(&program);
        for c in outcome.corrections.iter().filter(|c| c.kind.is_robtarget()) {
            let common::Meant {
                pose: original,
                conf,
                tool,
                wobj,
            } = meanings.of(&c.id);
            let corrected = c.exact.unwrap();
            // The controller: nominal IK of the corrected target, same robconf.
            let flange = flange_of_target(&corrected, &tool, &wobj).unwrap();
            let q = robot.ik_conf(&flange, &conf).unwrap();
            // The warm robot at those joints.
            let reached: Isometry3<f64> =
                target_of_flange(&robot.fk_scaled(&q, &scales), &tool, &wobj).unwrap();
            let miss = (reached.translation.vector - original.translation.vector).norm();
            assert!(miss < 1e-6, "{name} {}: lands {miss} mm off", c.id);
            assert!(
                same_rotation(&reached.rotation, &original.rotation, 1e-9),
                "{name} {}: orientation differs",
                c.id
            );
            checked += 1;
        }
    }
    assert!(checked > 5000, "every sample target is checked ({checked})");
}

#[test]
fn written_numbers_are_within_half_a_micrometre_of_the_exact_correction() {
    for (name, bytes) in sample_programs() {
        let (program, outcome) = run(&name, &bytes, 90.0);
        let corrected = rapid::parse(&name, &outcome.outputs[0]).unwrap();
        for c in outcome.corrections.iter().filter(|c| c.kind.is_robtarget()) {
            let exact = c.exact.unwrap().translation.vector;
            let t = corrected.target(&c.id).unwrap();
            let written = t.value.as_ref().unwrap().trans_values();
            for k in 0..3 {
                assert!(
                    (written[k] - exact[k]).abs() <= 0.0005 + 1e-9,
                    "{name} {}: written {} vs exact {}",
                    c.id,
                    written[k],
                    exact[k]
                );
            }
        }
        assert_eq!(program.targets().len(), corrected.targets().len());
    }
}

#[test]
fn at_reference_temperature_nothing_is_rewritten() {
    for (name, bytes) in sample_programs() {
        let (_, outcome) = run(&name, &bytes, 0.0);
        assert_eq!(
            outcome.outputs[0], bytes,
            "{name}: --at 0 must keep every byte"
        );
        assert_eq!(outcome.summary.rewritten, 0);
    }
}

#[test]
fn diff_of_corrected_program_agrees_with_the_reported_corrections_and_drift() {
    for (name, bytes) in sample_programs() {
        let (program, outcome) = run(&name, &bytes, 150.0);
        let corrected = rapid::parse(&name, &outcome.outputs[0]).unwrap();
        let d = diff(&program, &corrected).unwrap();
        for c in outcome.corrections.iter().filter(|c| c.kind.is_robtarget()) {
            let t = d.targets.iter().find(|t| t.id == c.id).unwrap();
            // The text is rounded to 0.001 mm per coordinate.
            assert!(
                (t.dist - c.correction_norm_mm).abs() < 0.001,
                "{name} {}: diff {} vs correction {}",
                c.id,
                t.dist,
                c.correction_norm_mm
            );
            // The correction undoes the drift (to second order).
            assert!(
                (t.dist - c.drift_norm_mm).abs() < 0.002,
                "{name} {}: diff {} vs drift {}",
                c.id,
                t.dist,
                c.drift_norm_mm
            );
        }
        assert!(d.only_in_a.is_empty() && d.only_in_b.is_empty());
    }
}

/// The file with the bytes of every robtarget and jointtarget number cut
/// out: what must not change when targets are corrected.
fn outside_numbers(name: &str, bytes: &[u8]) -> Vec<u8> {
    let program = rapid::parse(name, bytes).unwrap();
    let mut spans: Vec<std::ops::Range<usize>> = program
        .targets()
        .iter()
        .filter(|t| t.kind != TargetKind::Derived)
        .flat_map(|t| match &t.value {
            Some(v) => v.numbers().map(|n| n.span()).collect::<Vec<_>>(),
            None => Vec::new(),
        })
        .chain(
            program
                .jointtargets()
                .iter()
                .flat_map(|j| j.robax.iter().map(|n| n.span())),
        )
        .collect();
    spans.sort_by_key(|s| s.start);
    let mut kept = Vec::new();
    let mut at = 0;
    for s in &spans {
        kept.extend_from_slice(&bytes[at..s.start]);
        at = s.end;
    }
    kept.extend_from_slice(&bytes[at..]);
    kept
}

/// The bytes without the marker's two lines a correction adds (under the
/// module header, and the numbers' fingerprint above the last ENDMODULE:
/// the only bytes besides numbers a correction writes).
fn without_marker(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut removed = 0;
    for line in bytes.split_inclusive(|&b| b == b'\n') {
        if String::from_utf8_lossy(line)
            .trim_start()
            .starts_with("! rapidtherm ")
        {
            removed += 1;
            continue;
        }
        out.extend_from_slice(line);
    }
    assert!(removed <= 2, "one marker per file, of two lines");
    out
}

#[test]
fn untouched_bytes_stay_identical() {
    for (name, bytes) in sample_programs() {
        let (_, outcome) = run(&name, &bytes, 60.0);
        let written = without_marker(&outcome.outputs[0]);
        assert_eq!(
            outside_numbers(&name, &bytes),
            outside_numbers(&name, &written),
            "{name}: bytes outside target numbers changed"
        );
    }
}

#[test]
fn steady_state_corrects_more_than_minute_30() {
    let (name, bytes) = sample_programs()
        .into_iter()
        .find(|(n, _)| n.starts_with("two_modules"))
        .unwrap();
    let program = rapid::parse(&name, &bytes).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 30.0).unwrap();
    let steady = correct(
        &program,
        &warm,
        &Options::new(When::At(Moment::Steady)),
        &mut |_, _| {},
    )
    .unwrap();
    let early = correct(&program, &warm, &at(30.0), &mut |_, _| {}).unwrap();
    assert!(steady.summary.max_mm > early.summary.max_mm);
    assert_relative_eq!(
        steady.corrections[0].temps_c[5],
        default_profile().axes[5].steady(),
        epsilon = 1e-12
    );
}

#[test]
fn derived_targets_report_their_residual_drift_after_the_base_is_corrected() {
    let (name, bytes) = sample_programs()
        .into_iter()
        .find(|(n, _)| n.starts_with("weld_cell"))
        .unwrap();
    let (_, outcome) = run(&name, &bytes, 120.0);
    let d = outcome
        .derived
        .iter()
        .find(|d| d.expr.starts_with("Offs(pNahtEnde"))
        .unwrap();
    let residual = d
        .residual_mm
        .expect("Offs with literal offsets is evaluated");
    // Moving the base undoes most of the drift 50 mm above it, not all:
    // the arm's pose differs there.
    assert!(
        residual > 0.0 && residual < 0.25 * d.base_correction_mm,
        "{residual} vs {}",
        d.base_correction_mm
    );
}

#[test]
fn offs_and_reltool_displace_in_work_object_and_tool_frames() {
    use rapidtherm::correct::derived::{apply, calls_by_offset};
    let src = b"MODULE m\n  CONST robtarget p:=[[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    MoveL Offs(p, 10, -5, 20), v100, fine, tool0;\n    MoveL RelTool(p, 0, 0, 30 \\Rz:=90), v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";
    let program = rapid::parse("m.mod", src).unwrap();
    let calls = calls_by_offset(&program);
    let base = target_pose(&program, &program.target("p").unwrap())
        .unwrap()
        .unwrap()
        .0;
    let derived: Vec<_> = program
        .targets()
        .iter()
        .filter(|t| t.kind == TargetKind::Derived)
        .map(|t| apply(calls[&t.origin.pos.offset], &base).unwrap())
        .collect();
    let offs = derived[0].translation.vector;
    assert!((offs - nalgebra::Vector3::new(510.0, -5.0, 420.0)).norm() < 1e-12);
    // The tool points down: 30 mm along its z is 30 mm lower.
    let rel = &derived[1];
    assert!((rel.translation.vector - nalgebra::Vector3::new(500.0, 0.0, 370.0)).norm() < 1e-9);
    assert!((rel.rotation.angle_to(&base.rotation).to_degrees() - 90.0).abs() < 1e-9);
}
