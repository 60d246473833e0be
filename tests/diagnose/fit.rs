//! The fit itself: parameters recovered within their standard errors,
//! unidentifiable parameters detected (never NaN or huge), registration of
//! an instrument frame, and bad data refused with clear errors.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rapidtherm::diagnose::fit::fit;
use rapidtherm::diagnose::measurements::{Measurements, IRB140_LIMITS_DEG};
use rapidtherm::diagnose::simulate::{random_poses, simulate, SimSpec};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{diagnose, gap, prepare, DiagnoseOptions};
use rapidtherm::error::ErrorKind;
use rapidtherm::model::effects::GEOMETRY_ORIGINS_FROM;
use rapidtherm::model::Model;
use rapidtherm::model::{Base, Effect, EffectKind};
use rapidtherm::thermal::default_profile;

fn data(effects: Vec<Effect>, orientation: bool, seed: u64) -> Measurements {
    let spec = SimSpec {
        base: Base::default(),
        poses: random_poses(15, &IRB140_LIMITS_DEG, seed),
        times: (0..=20).map(|i| i as f64 * 9.0).collect(),
        effects,
        noise_mm: 0.01,
        orientation,
        measured_temps: false,
        seed,
    };
    simulate(&spec, &default_profile()).unwrap()
}

#[test]
fn parameters_are_recovered_within_their_standard_errors() {
    let mut z2 = Vec::new();
    for (kind, orientation, seed) in [
        (EffectKind::GeometryOffset, true, 1u64),
        (EffectKind::ArmBending, false, 2),
        (EffectKind::GravitySag, false, 3),
        (EffectKind::MountDrift, false, 4),
        (EffectKind::ThermalLag, false, 5),
    ] {
        let truth = lengths_and_zeros(Effect::with_defaults(kind));
        let meas = data(vec![truth.clone()], orientation, seed);
        let p = prepare(&meas, &Model::default(), false).unwrap();
        let all: Vec<usize> = (0..p.problem.rows.len()).collect();
        let f = fit(&p.problem, &all, &[kind]).unwrap();
        // From 12 poses geometry-offset fits lengths and zeros only.
        let fitted = fitted_params(kind);
        for ((info, est), true_value) in kind.params()[..fitted]
            .iter()
            .zip(&f.params[0])
            .zip(&truth.params)
        {
            let se = est.stderr.expect("identifiable with these data");
            assert!(se.is_finite() && se > 0.0);
            let z = (est.value - true_value) / se;
            assert!(
                z.abs() < 4.5,
                "{}.{}: {} vs {} ± {se}",
                kind.name(),
                info.name,
                est.value,
                true_value
            );
            z2.push(z * z);
        }
    }
    // Standard errors neither far too small nor far too large.
    let rms_z = (z2.iter().sum::<f64>() / z2.len() as f64).sqrt();
    assert!((0.4..2.0).contains(&rms_z), "RMS z-score {rms_z}");
}

#[test]
fn unidentifiable_parameters_are_detected_not_nan() {
    // Axis-6 zero without orientation data, and geometry-offset together
    // with tracker-frame (c1 and the frame's z, axis-1 zero and the
    // frame's rotation about z are the same motion).
    let meas = data(
        vec![lengths_and_zeros(Effect::with_defaults(
            EffectKind::GeometryOffset,
        ))],
        false,
        9,
    );
    let p = prepare(&meas, &Model::default(), false).unwrap();
    let all: Vec<usize> = (0..p.problem.rows.len()).collect();
    let f = fit(
        &p.problem,
        &all,
        &[EffectKind::GeometryOffset, EffectKind::TrackerFrame],
    )
    .unwrap();
    let geometry = &f.params[0];
    assert!(
        geometry[10].stderr.is_none(),
        "dq6 without orientation: {:?}",
        geometry[10]
    );
    let dropped = f
        .params
        .iter()
        .flat_map(|ps| &ps[..fitted_params(EffectKind::GeometryOffset).min(ps.len())])
        .filter(|p| p.stderr.is_none())
        .count();
    assert!(
        dropped >= 3,
        "dq6, one of dc1/z and one of dq1/rz: {dropped} dropped"
    );
    for p in f.params.iter().flatten() {
        assert!(p.value.is_finite() && p.value.abs() < 10.0, "{p:?}");
    }
    // Still explains the data.
    assert!((f.rss / f.n_obs as f64).sqrt() < 0.013);
}

#[test]
fn register_recovers_a_tracker_frame() {
    let mut meas = data(vec![], false, 11);
    let frame = Isometry3::from_parts(
        Translation3::new(1500.0, -300.0, 80.0),
        UnitQuaternion::from_euler_angles(0.02, -0.01, 0.6),
    );
    for r in &mut meas.rows {
        r.position = frame.transform_point(&r.position.into()).coords;
    }
    let plain = prepare(&meas, &Model::default(), false).unwrap();
    assert!(gap(&plain).rms_mm > 100.0);
    let reg = prepare(&meas, &Model::default(), true).unwrap();
    let r = reg.registration.clone().unwrap();
    let t = Vector3::from(r.translation_mm);
    assert!((t - frame.translation.vector).norm() < 0.05, "{t}");
    assert!(
        (r.rotation_deg[2] - 0.6f64.to_degrees()).abs() < 0.2,
        "{:?}",
        r.rotation_deg
    );
    assert!(gap(&reg).rms_mm < 0.025, "{}", gap(&reg).rms_mm);
}

#[test]
fn too_few_rows_is_a_clear_error() {
    let mut meas = data(vec![], false, 12);
    meas.rows.truncate(8);
    let p = prepare(&meas, &Model::default(), false).unwrap();
    let e = diagnose(
        &p,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    assert!(e.message.contains("too few measurements"), "{}", e.message);
    // A fit with more parameters than values refuses too.
    let e = fit(&p.problem, &[0], &[EffectKind::GeometryOffset]).unwrap_err();
    assert!(e.message.contains("too few"), "{}", e.message);
}

#[test]
fn a_model_with_effects_simulates_base_plus_effects() {
    // The diagnosed model reproduces the data it was diagnosed on, and
    // diagnosing again with it finds nothing more.
    let meas = data(
        vec![Effect::with_defaults(EffectKind::JointOffsetDrift)],
        false,
        13,
    );
    let p = prepare(&meas, &Model::default(), false).unwrap();
    let d = diagnose(
        &p,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap();
    assert_eq!(d.verdict.labels(), vec!["joint-offset-drift"]);
    let model = rapidtherm::diagnose::diagnosed_model(&Model::default(), &d);
    let text = model.to_toml().unwrap();
    let model = Model::parse("m.toml", &text).unwrap();
    let p2 = prepare(&meas, &model, false).unwrap();
    assert!(gap(&p2).rms_mm < 0.02);
    let d2 = diagnose(
        &p2,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap();
    assert_eq!(d2.verdict.labels(), vec!["none"], "{:?}", d2.words());
}

#[test]
fn folds_hold_out_whole_poses_and_whole_time_blocks() {
    let meas = data(vec![], false, 14);
    let p = prepare(&meas, &Model::default(), false).unwrap();
    let folds = rapidtherm::diagnose::select::make_folds(&p.problem, 4);
    assert_eq!(folds.folds.len(), 4);
    let rows = &p.problem.rows;
    let mut tested = vec![false; rows.len()];
    let all_times: std::collections::BTreeSet<u64> =
        rows.iter().map(|r| r.time_min as u64).collect();
    let all_poses: std::collections::BTreeSet<usize> = rows.iter().map(|r| r.pose).collect();
    for (train, test) in &folds.folds {
        let train_poses: std::collections::BTreeSet<usize> =
            train.iter().map(|&i| rows[i].pose).collect();
        let train_times: std::collections::BTreeSet<u64> =
            train.iter().map(|&i| rows[i].time_min as u64).collect();
        // Whole poses and a whole contiguous block of times are absent from
        // training, and every row of theirs is scored.
        let unseen_poses: Vec<usize> = all_poses.difference(&train_poses).copied().collect();
        let unseen_times: Vec<u64> = all_times.difference(&train_times).copied().collect();
        assert!(unseen_poses.len() >= 3, "{unseen_poses:?}");
        assert!(unseen_times.len() >= 5, "{unseen_times:?}");
        let block: Vec<u64> = all_times
            .iter()
            .copied()
            .filter(|t| (unseen_times[0]..=*unseen_times.last().unwrap()).contains(t))
            .collect();
        assert_eq!(block, unseen_times, "the held-out times are contiguous");
        for (i, r) in rows.iter().enumerate() {
            let held =
                unseen_poses.contains(&r.pose) || unseen_times.contains(&(r.time_min as u64));
            assert_eq!(held, test.contains(&i));
        }
        for &i in test {
            tested[i] = true;
        }
    }
    assert!(
        tested.iter().all(|&t| t),
        "every row is scored once or more"
    );
}

#[test]
fn a_single_pose_cannot_tell_a_tilt_from_a_shift() {
    // One pose over the warm-up: a base tilt moves it exactly like a base
    // shift, up to the arm's tiny expansion. The tilts must be dropped, not
    // fitted to huge compensating values.
    let spec = SimSpec {
        base: Base::default(),
        poses: random_poses(1, &IRB140_LIMITS_DEG, 3),
        times: (0..=30).map(|i| i as f64 * 6.0).collect(),
        effects: vec![Effect::with_defaults(EffectKind::MountDrift)],
        noise_mm: 0.01,
        orientation: false,
        measured_temps: false,
        seed: 3,
    };
    let meas = simulate(&spec, &default_profile()).unwrap();
    let p = prepare(&meas, &Model::default(), false).unwrap();
    let all: Vec<usize> = (0..p.problem.rows.len()).collect();
    let f = fit(&p.problem, &all, &[EffectKind::MountDrift]).unwrap();
    let params = &f.params[0];
    assert!(
        params[3].stderr.is_none() && params[4].stderr.is_none(),
        "{params:?}"
    );
    for (info, p) in EffectKind::MountDrift.params().iter().zip(params) {
        assert!(
            p.value.abs() < 10.0 * info.default.abs().max(1.0),
            "{}: {p:?}",
            info.name
        );
    }
}

#[test]
fn noisy_orientations_do_not_spoil_the_positions() {
    // A probe whose orientation noise is 150× the default: the weight of
    // orientation residuals follows the estimated noise, so the position
    // fit stays at the position noise.
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let mut meas = data(
        vec![Effect::with_defaults(EffectKind::JointOffsetDrift)],
        true,
        15,
    );
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(15);
    let n = Normal::new(0.0, 3e-3).unwrap();
    for r in &mut meas.rows {
        let w = Vector3::new(n.sample(&mut rng), n.sample(&mut rng), n.sample(&mut rng));
        r.orientation = r
            .orientation
            .map(|o| o * UnitQuaternion::from_scaled_axis(w));
    }
    let p = prepare(&meas, &Model::default(), false).unwrap();
    let d = diagnose(
        &p,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap();
    // The drift named, nothing unexplained, and no static effect beyond
    // the frame and geometry: the poses' means, tested by F, carry the
    // drift's own fitting error at each pose's mean temperature, which a
    // frame or a zero takes up.
    let labels = d.verdict.labels();
    assert_eq!(
        labels.first().map(String::as_str),
        Some("joint-offset-drift"),
        "{:?}",
        d.words()
    );
    assert!(
        labels[1..]
            .iter()
            .all(|l| l == "tracker-frame" || l == "geometry-offset"),
        "{:?}",
        d.words()
    );
    assert!(
        d.gap_after_mm < 1.5 * 0.01 * 3f64.sqrt(),
        "{}",
        d.gap_after_mm
    );
}

#[test]
fn registration_does_not_swallow_thermal_drift() {
    // Bending data recorded in a tracker's own frame: registered on the
    // cold start, the diagnosis still finds the bending, and no other
    // effect beyond the instrument frame (what the registration on the
    // cold start's 15 points leaves of it, 0.003 mm, is significant on
    // 300 rows), and nothing unexplained.
    let mut meas = data(
        vec![Effect::with_defaults(EffectKind::ArmBending)],
        false,
        16,
    );
    let frame = Isometry3::from_parts(
        Translation3::new(1500.0, -300.0, 80.0),
        UnitQuaternion::from_euler_angles(0.0, 0.0, 0.6),
    );
    for r in &mut meas.rows {
        r.position = frame.transform_point(&r.position.into()).coords;
    }
    let p = prepare(&meas, &Model::default(), true).unwrap();
    assert_eq!(p.registration.as_ref().unwrap().rows_used, 15);
    let d = diagnose(
        &p,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap();
    let labels = d.verdict.labels();
    assert_eq!(
        labels.first().map(String::as_str),
        Some("arm-bending"),
        "{:?}",
        d.words()
    );
    assert!(
        labels[1..].iter().all(|l| l == "tracker-frame"),
        "{:?}",
        d.words()
    );
}

/// An effect without the joint-origin part of geometry-offset, which is
/// fitted only from 30 poses or more (these tests have 12).
pub fn lengths_and_zeros(mut e: Effect) -> Effect {
    if e.kind == EffectKind::GeometryOffset {
        e.params[GEOMETRY_ORIGINS_FROM..].fill(0.0);
    }
    e
}

/// Parameters of `kind` a fit from 12 poses estimates.
fn fitted_params(kind: EffectKind) -> usize {
    if kind == EffectKind::GeometryOffset {
        GEOMETRY_ORIGINS_FROM
    } else {
        kind.params().len()
    }
}

/// A fit asked for again is answered from the memo (the fast path ran:
/// its hit count rose) with the very fit made the first time; a fit of
/// other rows, or started elsewhere, is made afresh. A fold's fit started
/// from the fit on all rows ends where a cold fit of the fold ends.
#[test]
fn a_fit_asked_again_is_remembered_and_a_warm_start_ends_where_a_cold_one_does() {
    use rapidtherm::diagnose::fit::fit_from;
    let truth = Effect::with_defaults(EffectKind::ThermalLag);
    let meas = data(vec![truth], false, 11);
    let p = prepare(&meas, &Model::default(), false).unwrap();
    let all: Vec<usize> = (0..p.problem.rows.len()).collect();
    let kinds = [EffectKind::ThermalLag, EffectKind::ArmBending];
    let first = fit(&p.problem, &all, &kinds).unwrap();
    let hits = p.problem.memo.hits();
    let again = fit(&p.problem, &all, &kinds).unwrap();
    assert_eq!(p.problem.memo.hits(), hits + 1);
    assert_eq!(first.effects, again.effects);
    assert_eq!(first.rss.to_bits(), again.rss.to_bits());
    // Another set of rows: no hit.
    let fold: Vec<usize> = all.iter().copied().filter(|i| i % 5 != 0).collect();
    let cold = fit(&p.problem, &fold, &kinds).unwrap();
    assert_eq!(p.problem.memo.hits(), hits + 1);
    let warm = fit_from(&p.problem, &fold, &kinds, &first.effects).unwrap();
    assert_eq!(p.problem.memo.hits(), hits + 1);
    // Both at the fold's minimum: residuals equal to a thousandth of the
    // noise variance over the fold.
    let n = cold.n_obs as f64;
    assert!(
        (warm.rss - cold.rss).abs() / n < 1e-3 * 0.01 * 0.01,
        "warm {} cold {}",
        warm.rss,
        cold.rss
    );
}
