//! The loop closes: targets corrected with the diagnosed model land closer
//! to their goal on the simulated real robot than targets corrected with
//! the base model.

use nalgebra::{DMatrix, DVector, Isometry3};
use rapidtherm::diagnose::measurements::IRB140_LIMITS_DEG;
use rapidtherm::diagnose::simulate::{random_poses, simulate, SimSpec};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{diagnose, diagnosed_model, prepare, DiagnoseOptions};
use rapidtherm::model::{predict, Base, Effect, EffectKind, RowState};
use rapidtherm::model::{Model, Moment, WarmRobot};
use rapidtherm::robot::Joints;
use rapidtherm::robot::Robot;
use rapidtherm::thermal::{default_profile, HeatingProfile};

/// 6-D pose error (mm; rotation vector scaled by 500 mm so both count).
fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> DVector<f64> {
    let dp = b.translation.vector - a.translation.vector;
    let dr = (b.rotation * a.rotation.inverse()).scaled_axis() * 500.0;
    DVector::from_vec(vec![dp.x, dp.y, dp.z, dr.x, dr.y, dr.z])
}

/// Joints at which `model` puts the flange at `goal` (damped Newton from
/// `q0`): what a correction with that model would write.
fn correct(model: &Model, goal: &Isometry3<f64>, q0: &Joints, t: f64) -> Joints {
    let warm = WarmRobot::new(Robot::irb140(), model, t).unwrap();
    let state = warm.state(Moment::Minute(t)).unwrap();
    let mut q = *q0;
    for _ in 0..20 {
        let pose = warm.flange(&q, &state);
        let e = pose_error(&pose, goal);
        if e.norm() < 1e-9 {
            break;
        }
        let mut j = DMatrix::zeros(6, 6);
        for k in 0..6 {
            let mut qk = q;
            qk[k] += 1e-7;
            let pk = warm.flange(&qk, &state);
            j.set_column(k, &(-pose_error(&pk, &pose) / 1e-7));
        }
        let a = j.transpose() * &j + DMatrix::identity(6, 6) * 1e-9;
        let step = a.cholesky().unwrap().solve(&(j.transpose() * e));
        for k in 0..6 {
            q[k] += step[k];
        }
    }
    q
}

#[test]
fn corrections_with_the_diagnosed_model_land_closer() {
    let profile = default_profile();
    for (kind, seed) in [
        (EffectKind::ArmBending, 51u64),
        (EffectKind::JointOffsetDrift, 52),
        (EffectKind::GravitySag, 53),
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
        let meas = simulate(&spec, &profile).unwrap();
        let base_model = Model::default();
        let prepared = prepare(&meas, &base_model, false).unwrap();
        let d = diagnose(
            &prepared,
            &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
        )
        .unwrap();
        let diagnosed = diagnosed_model(&base_model, &d);

        // Goals: poses taught on the cold robot (its nominal model), reached
        // during the warm-up.
        let goals = random_poses(
            20,
            &[
                (-170.0, 170.0),
                (-40.0, 80.0),
                (-120.0, 30.0),
                (-150.0, 150.0),
                (-100.0, -20.0),
                (-180.0, 180.0),
            ],
            seed + 1000,
        );
        let (mut base_sq, mut diag_sq, mut none_sq, mut n) = (0.0, 0.0, 0.0, 0.0);
        for (i, (_, qg)) in goals.iter().enumerate() {
            let t = [30.0, 90.0, 180.0][i % 3];
            let goal = base_model.robot.opw.unwrap().fk(qg);
            let real = |q: &Joints| {
                let row = RowState {
                    q: *q,
                    temps: profile.temps_at(t).unwrap(),
                    lagged: None,
                };
                predict(&Base::default(), &truth, &row).translation.vector
            };
            let miss = |q: &Joints| -> f64 { (real(q) - goal.translation.vector).norm_squared() };
            none_sq += miss(qg);
            base_sq += miss(&correct(&base_model, &goal, qg, t));
            diag_sq += miss(&correct(&diagnosed, &goal, qg, t));
            n += 1.0;
        }
        let (none, base, diag) = (
            (none_sq / n).sqrt(),
            (base_sq / n).sqrt(),
            (diag_sq / n).sqrt(),
        );
        eprintln!(
            "{}: uncorrected {none:.4} mm, corrected with base model {base:.4} mm, with diagnosed model {diag:.4} mm (verdict {:?})",
            kind.name(),
            d.verdict.labels()
        );
        assert!(diag < 0.5 * base, "{}: {diag} vs {base}", kind.name());
        assert!(diag < 0.02, "{}: {diag}", kind.name());
    }
}
