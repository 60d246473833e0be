//! Every effect on a general serial chain (`rapidtherm::model::general`):
//! on the IRB 140's own chain the same numbers as its OPW form, and on a
//! UR5 (`tests/data/ur5/ur5.urdf`, no OPW form) effects simulated on
//! it are diagnosed with it.

use super::urdf::finds_effect_on;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rapidtherm::model::{predict, Base, Effect, EffectKind, Geometry, RowState};
use rapidtherm::robot::Robot;
use std::path::Path;
use std::sync::Arc;

fn ur5() -> Robot {
    Robot::from_urdf_file(Path::new("tests/data/ur5/ur5.urdf")).unwrap()
}

#[test]
fn irb140_as_a_chain_predicts_what_its_opw_form_does() {
    let opw = Base::default();
    let chain = Base {
        nominal: Geometry::Chain(Arc::new(Robot::irb140().chain)),
        ..Base::default()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    // Every effect but the geometric calibration's, whose joint-origin
    // errors are written in each form's own joint frames; at magnitudes
    // far above the defaults so that a misplaced term shows.
    let kinds: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .filter(|k| *k != EffectKind::GeometryOffset)
        .collect();
    for kind in kinds.iter().copied().map(Some).chain([None]) {
        let effects: Vec<Effect> = match kind {
            Some(k) => vec![scaled_defaults(k, 5.0)],
            None => kinds.iter().map(|&k| scaled_defaults(k, -3.0)).collect(),
        };
        for _ in 0..50 {
            let q = std::array::from_fn(|_| rng.random_range(-2.5..2.5));
            let temps = std::array::from_fn(|_| rng.random_range(7.0..45.0));
            let lagged = Some(std::array::from_fn(|_| {
                std::array::from_fn(|_| rng.random_range(7.0..45.0))
            }));
            let row = RowState { q, temps, lagged };
            let (a, b) = (
                predict(&opw, &effects, &row),
                predict(&chain, &effects, &row),
            );
            let dp = (a.translation.vector - b.translation.vector).norm();
            let dr = a.rotation.angle_to(&b.rotation);
            assert!(dp < 1e-9 && dr < 1e-12, "{kind:?}: {dp} mm, {dr} rad");
        }
    }
}

fn scaled_defaults(kind: EffectKind, factor: f64) -> Effect {
    let mut e = Effect::with_defaults(kind);
    if kind != EffectKind::ThermalLag {
        for p in &mut e.params {
            *p *= factor;
        }
    }
    e
}

#[test]
fn thermal_effects_simulated_on_a_ur5_are_diagnosed_with_its_urdf() {
    let r = ur5();
    assert!(
        r.opw.is_err(),
        "the UR5 must be an arm without the OPW form"
    );
    finds_effect_on(
        &r,
        "joint-offset-drift:c2_urad_per_k=20,c3_urad_per_k=-15",
        "joint-offset-drift.c2_urad_per_k",
        20.0,
    );
    finds_effect_on(
        &r,
        "arm-bending:lower_urad_per_k=40,upper_urad_per_k=-30",
        "arm-bending.lower_urad_per_k",
        40.0,
    );
}

/// The IRB 140's URDF with masses on the lower arm, the upper arm, the
/// wrist and a tool hung on tool0.
fn irb140_with_masses() -> Robot {
    let inertial = |xyz: &str, kg: f64| {
        format!(
            r#"<inertial><origin xyz="{xyz}" rpy="0 0 0"/><mass value="{kg}"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>"#
        )
    };
    let text = rapidtherm::robot::urdf::IRB140_URDF
        .replace(
            r#"<link name="link_2"/>"#,
            &format!(
                r#"<link name="link_2">{}</link>"#,
                inertial("0 0 0.18", 10.0)
            ),
        )
        .replace(
            r#"<link name="link_3"/>"#,
            &format!(r#"<link name="link_3">{}</link>"#, inertial("0.2 0 0", 6.0)),
        )
        .replace(
            r#"<link name="link_6"/>"#,
            &format!(r#"<link name="link_6">{}</link>"#, inertial("0 0 0", 2.0)),
        )
        .replace(
            r#"<link name="tool0"/>"#,
            &format!(r#"<link name="tool0">{}</link>"#, inertial("0 0 0.1", 1.0)),
        );
    Robot::from_urdf_str("irb140_masses.urdf", &text).unwrap()
}

#[test]
fn gravity_torques_come_from_the_urdf_inertials() {
    let chain = irb140_with_masses().chain;
    assert_eq!(chain.masses.len(), 4);
    // At zero the lower arm stands over axis 2 (no lever); the upper arm's
    // mass is 200 mm out, the wrist's 445 mm, the tool's 545 mm (tool0's z
    // points forward), all measured from axes 2 and 3 alike.
    let tau = 6.0 * 200.0 + 2.0 * 445.0 + 1.0 * 545.0;
    let expect = [tau / (19.0 * 740.0), 0.0, tau / (9.0 * 380.0)];
    for q1 in [0.0, 1.3, -2.2] {
        let l = rapidtherm::model::general::gravity_levers(&chain, &[q1, 0.0, 0.0, 0.7, 0.0, 0.4]);
        for (a, b) in l.iter().zip(expect) {
            assert!((a - b).abs() < 1e-12, "{l:?} vs {expect:?}");
        }
    }
    // Arm straight up: no torque on either axis.
    let up = [0.0, 0.0, -std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0];
    let l = rapidtherm::model::general::gravity_levers(&chain, &up);
    assert!(l.iter().all(|v| v.abs() < 1e-9), "{l:?}");
    // With masses, sag has two compliances: its second lever has no place.
    let g = Geometry::Chain(Arc::new(chain));
    assert!(!g.has_param(EffectKind::GravitySag, 1));
    assert!(g.has_param(EffectKind::GravitySag, 2));
    assert!(!g.has_param(EffectKind::GeometryOffset, 0));
    assert!(g.has_param(EffectKind::GeometryOffset, 5));
}

/// The loop on an arm without the OPW form: simulated on a UR5, diagnosed
/// on its URDF, the diagnosed model's corrections (the warm robot's
/// joints for a cold target, as `correct` computes them, through the UR5's
/// numeric IK) put the simulated real robot on poses it was not diagnosed
/// on far closer than the uncorrected joints do.
#[test]
fn a_model_diagnosed_on_a_ur5_corrects_the_ur5() {
    use rapidtherm::diagnose::arm::Arm;
    use rapidtherm::diagnose::simulate::{random_poses, simulate_arm, SimSpec};
    use rapidtherm::diagnose::{diagnose, diagnosed_model, prepare_arm, DiagnoseOptions};
    use rapidtherm::model::{Model, Moment, WarmRobot};

    let robot = ur5();
    let arm = Arm::of_robot(&robot, "ur5.urdf").unwrap();
    let model = Model::default();
    let truth = vec![
        Effect::parse_spec("joint-offset-drift:c2_urad_per_k=30,c3_urad_per_k=-25").unwrap(),
        Effect::parse_spec("expansion-scale:dk_lower=1.5,dk_upper=1.5").unwrap(),
    ];
    let spec = SimSpec {
        base: arm.base(&model),
        poses: random_poses(12, &arm.limits_deg, 9),
        times: (0..=18).map(|i| 10.0 * f64::from(i)).collect(),
        effects: truth.clone(),
        noise_mm: 0.01,
        orientation: false,
        measured_temps: false,
        seed: 9,
    };
    let profile = model.profile().unwrap();
    let meas = simulate_arm(&spec, &arm.map, profile.as_ref()).unwrap();
    let prepared = prepare_arm(&meas, &model, &arm, false).unwrap();
    let d = diagnose(
        &prepared,
        &DiagnoseOptions::default().with_cold_start(rapidtherm::diagnose::temps::ColdStart::Irb140),
    )
    .unwrap();
    let fitted = diagnosed_model(&model, &d);
    let t = 120.0;
    let warm = WarmRobot::new(robot.clone(), &fitted, t).unwrap();
    let state = warm.state(Moment::Minute(t)).unwrap();
    let temps = profile.temps_at(t).unwrap();
    let real = |q: &[f64; 6]| {
        predict(
            &spec.base,
            &truth,
            &RowState {
                q: *q,
                temps,
                lagged: None,
            },
        )
        .translation
        .vector
    };
    let (mut cold_sq, mut corrected_sq, mut n) = (0.0, 0.0, 0);
    for (_, q) in random_poses(20, &arm.limits_deg, 77) {
        let goal = robot.fk(&q);
        let conf = robot.conf_of(&q);
        let Ok(qc) = warm.joints_for(&goal, &conf, &state) else {
            continue; // at a singularity: `correct` reports it, never guesses
        };
        cold_sq += (real(&q) - goal.translation.vector).norm_squared();
        corrected_sq += (real(&qc) - goal.translation.vector).norm_squared();
        n += 1;
    }
    assert!(n >= 15, "only {n} of 20 poses corrected");
    let (cold, corrected) = (
        (cold_sq / n as f64).sqrt(),
        (corrected_sq / n as f64).sqrt(),
    );
    if std::env::var_os("DIAG_VERBOSE").is_some() {
        eprintln!(
            "UR5 loop: {n} poses, {cold:.4} mm uncorrected, {corrected:.4} mm corrected, verdict {:?}",
            d.verdict.labels()
        );
    }
    assert!(
        corrected < 0.2 * cold,
        "warm error {cold:.4} mm uncorrected, {corrected:.4} mm corrected ({:?})",
        d.verdict.labels()
    );
}
