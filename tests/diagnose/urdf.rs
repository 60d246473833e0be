//! The diagnosis on robots given as URDF: the perturbed chain, driven
//! through the arm's joint map, is the robot's own forward kinematics; a
//! simulated effect on an IRB 120 is found again.

use nalgebra::Isometry3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rapidtherm::diagnose::arm::Arm;
use rapidtherm::diagnose::simulate::{random_poses, simulate_arm, SimSpec};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{
    self, diagnose as run_diagnosis, prepare, prepare_arm, DiagnoseOptions,
};
use rapidtherm::model::Model;
use rapidtherm::model::{predict, Effect, EffectKind, RowState, ThermalExpansion};
use rapidtherm::robot::{Joints, Robot};
use std::path::Path;

fn irb120() -> Robot {
    Robot::from_urdf_file(Path::new("tests/cmd/kin_data/irb120.urdf")).unwrap()
}

/// The IRB 120 with axes 2 and 5 pointing the other way and joint 3's
/// zero turned by 30°: signs −1 and a non-ABB offset in the map.
fn irb120_reversed() -> Robot {
    let text = std::fs::read_to_string("tests/cmd/kin_data/irb120.urdf").unwrap();
    let text = text
        .replacen(
            r#"<origin xyz="0 0 0.29" rpy="0 0 0"/><axis xyz="0 1 0"/>"#,
            r#"<origin xyz="0 0 0.29" rpy="0 0 0"/><axis xyz="0 -1 0"/>"#,
            1,
        )
        .replacen(
            r#"<origin xyz="0.302 0 0" rpy="0 0 0"/><axis xyz="0 1 0"/>"#,
            r#"<origin xyz="0.302 0 0" rpy="0 0 0"/><axis xyz="0 -1 0"/>"#,
            1,
        )
        .replacen(
            r#"<origin xyz="0 0 0.27" rpy="0 0 0"/>"#,
            r#"<origin xyz="0 0 0.27" rpy="0 0.5235987755982988 0"/>"#,
            1,
        );
    Robot::from_urdf_str("irb120_reversed.urdf", &text).unwrap()
}

fn random_joints(robot: &Robot, rng: &mut ChaCha8Rng) -> Joints {
    std::array::from_fn(|i| {
        let (lo, hi) = robot.limits[i];
        rng.random_range(lo..hi)
    })
}

fn assert_same_pose(a: &Isometry3<f64>, b: &Isometry3<f64>, what: &str) {
    let dp = (a.translation.vector - b.translation.vector).norm();
    let dr = a.rotation.angle_to(&b.rotation);
    assert!(dp < 1e-9, "{what}: position differs by {dp} mm");
    assert!(dr < 1e-12, "{what}: orientation differs by {dr} rad");
}

/// The robot's flange, on the arm expanded by the default thermal model
/// when motor temperatures are given.
fn warm_fk(robot: &Robot, q: &[f64; 6], temps: Option<&[f64; 6]>) -> Isometry3<f64> {
    match temps {
        Some(t) => robot.fk_scaled(q, &ThermalExpansion::default().scales(t)),
        None => robot.fk(q),
    }
}

/// Base model without effects, mapped back to the robot's tool0, equals
/// `Robot::fk` cold and warm, for random joints.
fn chain_is_robot_fk(robot: &Robot) {
    let arm = Arm::of_robot(robot, "test").unwrap();
    let model = Model::default();
    let base = arm.base(&model);
    assert_eq!(base.thermal, ThermalExpansion::default());
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for k in 0..200 {
        let q = random_joints(robot, &mut rng);
        let cold = [base.thermal.t_ref; 6];
        let warm: [f64; 6] = std::array::from_fn(|i| 20.0 + 5.0 * i as f64 + k as f64 * 0.1);
        for (temps, arg) in [(cold, None), (warm, Some(&warm))] {
            let row = RowState {
                q: arm.map.to_chain(&q),
                temps,
                lagged: None,
            };
            let chain = arm.map.tool0(&predict(&base, &[], &row));
            assert_same_pose(
                &chain,
                &warm_fk(robot, &q, arg),
                &format!("{} at {q:?}", robot.name),
            );
        }
        let back = arm.map.from_chain(&arm.map.to_chain(&q));
        for i in 0..6 {
            assert!((back[i] - q[i]).abs() < 1e-12);
        }
    }
}

#[test]
fn chain_matches_robot_fk_on_irb140_irb120_and_a_reversed_arm() {
    chain_is_robot_fk(&Robot::irb140());
    let r120 = irb120();
    chain_is_robot_fk(&r120);
    let rev = irb120_reversed();
    let map = Arm::of_robot(&rev, "test").unwrap().map;
    // The test arm must exercise the map: reversed axes and an offset.
    assert_eq!(map.signs[1], -1.0);
    assert_eq!(map.signs[4], -1.0);
    assert!(map.offsets[2].abs() > 0.1, "{:?}", map.offsets);
    chain_is_robot_fk(&rev);
    // Same lengths as the IRB 120 (only the joint conventions differ).
    let (a, b) = (
        *Arm::of_robot(&rev, "t").unwrap().nominal.opw().unwrap(),
        *Arm::of_robot(&r120, "t").unwrap().nominal.opw().unwrap(),
    );
    let la = [a.a1, a.a2, a.b, a.c1, a.c2, a.c3, a.c4];
    let lb = [b.a1, b.a2, b.b, b.c1, b.c2, b.c3, b.c4];
    for (x, y) in la.iter().zip(&lb) {
        assert!((x - y).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

#[test]
fn embedded_irb140_urdf_gives_the_same_gap_as_the_default() {
    let spec = SimSpec {
        base: Default::default(),
        poses: random_poses(8, &rapidtherm::diagnose::measurements::IRB140_LIMITS_DEG, 4),
        times: (0..=6).map(|i| f64::from(i) * 20.0).collect(),
        effects: vec![Effect::with_defaults(EffectKind::ArmBending)],
        noise_mm: 0.01,
        orientation: true,
        measured_temps: false,
        seed: 4,
    };
    let model = Model::default();
    let profile = model.profile().unwrap();
    let meas = rapidtherm::diagnose::simulate::simulate(&spec, profile.as_ref()).unwrap();
    let default = prepare(&meas, &model, false).unwrap();
    let arm = Arm::of_robot(&Robot::irb140(), "irb140.urdf").unwrap();
    let urdf = prepare_arm(&meas, &model, &arm, false).unwrap();
    let (a, b) = (diagnose::gap(&default), diagnose::gap(&urdf));
    assert!(a.rms_mm > 0.01, "the effect must make a gap: {a:?}");
    assert!((a.rms_mm - b.rms_mm).abs() < 1e-9 && (a.max_mm - b.max_mm).abs() < 1e-9);
    let (ra, rb) = (
        diagnose::orientation_gap(&default).unwrap(),
        diagnose::orientation_gap(&urdf).unwrap(),
    );
    assert!((ra.0 - rb.0).abs() < 1e-9);
}

/// Simulate `effect` on `robot`, diagnose with the same robot: the verdict
/// names the effect and the fitted parameter is close to the truth.
pub fn finds_effect_on(robot: &Robot, effect: &str, param: &str, truth: f64) {
    let arm = Arm::of_robot(robot, "test").unwrap();
    let model = Model::default();
    let spec = SimSpec {
        base: arm.base(&model),
        poses: random_poses(10, &arm.limits_deg, 5),
        times: (0..=12).map(|i| f64::from(i) * 15.0).collect(),
        effects: vec![Effect::parse_spec(effect).unwrap()],
        noise_mm: 0.01,
        orientation: false,
        measured_temps: true,
        seed: 5,
    };
    let profile = model.profile().unwrap();
    let meas = simulate_arm(&spec, &arm.map, profile.as_ref()).unwrap();
    // The data are the robot's joints: within its limits, not the IRB 140's.
    let prepared = prepare_arm(&meas, &model, &arm, false).unwrap();
    let d = run_diagnosis(
        &prepared,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap();
    let name = effect.split(':').next().unwrap();
    assert!(
        d.verdict.labels().iter().any(|v| v == name),
        "{}: verdict {:?} for {effect}",
        robot.name,
        d.verdict.labels()
    );
    let fitted = d
        .candidates
        .iter()
        .find(|c| c.name == name)
        .and_then(|c| c.params.iter().find(|p| p.name == param))
        .unwrap();
    let se = fitted.stderr.unwrap();
    assert!(
        (fitted.value - truth).abs() < 4.0 * se + 0.05 * truth.abs(),
        "{param}: {} ± {se}, truth {truth}",
        fitted.value
    );
    assert!(d.gap_after_mm < 0.3 * d.gap_before_mm, "{d:?}");
}

#[test]
fn effects_simulated_on_an_irb120_are_diagnosed_with_its_urdf() {
    let r = irb120();
    finds_effect_on(
        &r,
        "mount-drift:z_um_per_k=8",
        "mount-drift.z_um_per_k",
        8.0,
    );
    finds_effect_on(
        &irb120_reversed(),
        "joint-offset-drift:c1_urad_per_k=0,c2_urad_per_k=0,c3_urad_per_k=40,c4_urad_per_k=0,c5_urad_per_k=0,c6_urad_per_k=0",
        "joint-offset-drift.c3_urad_per_k",
        40.0,
    );
}

#[test]
fn simulated_irb120_rows_are_its_urdf_poses_and_read_back_without_gap() {
    for robot in [irb120(), irb120_reversed()] {
        let arm = Arm::of_robot(&robot, "test").unwrap();
        let model = Model::default();
        let spec = SimSpec {
            base: arm.base(&model),
            poses: random_poses(6, &arm.limits_deg, 9),
            times: vec![0.0, 60.0, 180.0],
            effects: vec![],
            noise_mm: 0.0,
            orientation: true,
            measured_temps: true,
            seed: 9,
        };
        let profile = model.profile().unwrap();
        let meas = simulate_arm(&spec, &arm.map, profile.as_ref()).unwrap();
        for m in &meas.rows {
            let want = warm_fk(&robot, &m.joints, m.temps.as_ref());
            let got = Isometry3::from_parts(m.position.into(), m.orientation.unwrap());
            assert_same_pose(&got, &want, &robot.name);
        }
        let prepared = prepare_arm(&meas, &model, &arm, false).unwrap();
        assert!(diagnose::gap(&prepared).max_mm < 1e-9);
        assert!(diagnose::orientation_gap(&prepared).unwrap().1 < 1e-9);
        // Read as an IRB 140 (no --robot), the same rows do not fit.
        let csv = meas.to_csv();
        let as_140 = rapidtherm::diagnose::measurements::Measurements::parse(
            "m.csv",
            csv.as_bytes(),
            &arm.limits_deg,
        )
        .unwrap();
        assert!(diagnose::gap(&prepare(&as_140, &model, false).unwrap()).rms_mm > 10.0);
    }
}
