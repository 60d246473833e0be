//! The loop closes through the real pipeline: a program corrected by
//! `correct` with the model a diagnosis saved lands closer to what it
//! meant, on the simulated real robot, than one corrected with the base
//! model.

use crate::common;

use nalgebra::Isometry3;
use rapidtherm::correct::{correct, Options, When};
use rapidtherm::diagnose::measurements::IRB140_LIMITS_DEG;
use rapidtherm::diagnose::simulate::{random_poses, simulate, SimSpec};
use rapidtherm::diagnose::{diagnose, diagnosed_model, prepare, DiagnoseOptions};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::model::{predict, Base, Effect, EffectKind, RowState};
use rapidtherm::rapid;
use rapidtherm::robot::frames::{flange_of_target, target_of_flange};
use rapidtherm::robot::Robot;
use rapidtherm::thermal::{default_profile, HeatingProfile};

const MINUTE: f64 = 90.0;

/// RMS distance (mm) between where the real robot puts each corrected
/// target and where the original program meant it.
fn landing_rms(program_name: &str, bytes: &[u8], model: &Model, truth: &[Effect]) -> f64 {
    let program = rapid::parse(program_name, bytes).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), model, MINUTE).unwrap();
    let options = Options::new(When::At(Moment::Minute(MINUTE)));
    let outcome = correct(&program, &warm, &options, &mut |_, _| {}).unwrap();
    let robot = Robot::irb140();
    let temps = default_profile().temps_at(MINUTE).unwrap();
    let mut sum = 0.0;
    let mut n = 0.0;
    let meanings = common::Meanings::new(&program);
    for c in outcome.corrections.iter().filter(|c| c.kind.is_robtarget()) {
        let common::Meant {
            pose: goal,
            conf,
            tool,
            wobj,
        } = meanings.of(&c.id);
        let corrected: Isometry3<f64> = c.exact.unwrap();
        let q = robot
            .ik_conf(&flange_of_target(&corrected, &tool, &wobj).unwrap(), &conf)
            .unwrap();
        let real = predict(
            &Base::default(),
            truth,
            &RowState {
                q,
                temps,
                lagged: None,
            },
        );
        let landed = target_of_flange(&real, &tool, &wobj).unwrap();
        sum += (landed.translation.vector - goal.translation.vector).norm_squared();
        n += 1.0;
    }
    (sum / n).sqrt()
}

#[test]
fn programs_corrected_with_the_diagnosed_model_land_closer() {
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/cmd/correct_data/cell.mod"
    ))
    .unwrap();
    for (kind, seed) in [
        (EffectKind::ArmBending, 7u64),
        (EffectKind::JointOffsetDrift, 8),
    ] {
        let truth = vec![Effect::with_defaults(kind)];
        let spec = SimSpec {
            base: Base::default(),
            poses: random_poses(12, &IRB140_LIMITS_DEG, seed),
            times: (0..=30).map(|i| i as f64 * 6.0).collect(),
            effects: truth.clone(),
            noise_mm: 0.01,
            orientation: false,
            measured_temps: false,
            seed,
        };
        let data = simulate(&spec, &default_profile()).unwrap();
        let base = Model::default();
        let diagnosis = diagnose(
            &prepare(&data, &base, false).unwrap(),
            &DiagnoseOptions::default()
                .with_cold_start(rapidtherm::diagnose::temps::ColdStart::Irb140),
        )
        .unwrap();
        let diagnosed = diagnosed_model(&base, &diagnosis);
        // The saved model file is what `correct --model` reads.
        let reread = Model::parse("saved.toml", &diagnosed.to_toml().unwrap()).unwrap();
        let with_base = landing_rms("cell.mod", &bytes, &base, &truth);
        let with_diagnosed = landing_rms("cell.mod", &bytes, &reread, &truth);
        eprintln!(
            "{}: corrected with the base model lands {with_base:.4} mm RMS off, with the diagnosed model {with_diagnosed:.4} mm",
            kind.name()
        );
        assert!(
            with_diagnosed < 0.5 * with_base,
            "{}: {with_diagnosed} vs {with_base}",
            kind.name()
        );
        assert!(with_diagnosed < 0.02, "{}: {with_diagnosed}", kind.name());
    }
}
