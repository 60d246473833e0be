//! Blind tests of the diagnosis: data simulated with one known effect (or
//! none, or effects outside the library made here by the test itself, or
//! library effects in other parameterisations) and diagnosed with the base
//! model, as a user would.

use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rapidtherm::diagnose::measurements::{Measurements, IRB140_LIMITS_DEG};
use rapidtherm::diagnose::simulate::{random_poses, simulate, SimSpec};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{diagnose, prepare, DiagnoseOptions, Diagnosis};
use rapidtherm::model::chain::{fk_chain, Perturbation};
use rapidtherm::model::Model;
use rapidtherm::model::{Base, Effect, EffectKind, RowState};
use rapidtherm::thermal::MotorTemps;
use rapidtherm::thermal::TempHistory;
use rapidtherm::thermal::{default_profile, HeatingProfile};

const NOISE: f64 = 0.01;

fn noise_rms() -> f64 {
    NOISE * 3f64.sqrt()
}

fn spec(effects: Vec<Effect>, poses: usize, times: usize, seed: u64) -> SimSpec {
    let step = 180.0 / (times - 1) as f64;
    SimSpec {
        base: Base::default(),
        poses: random_poses(poses, &IRB140_LIMITS_DEG, seed),
        times: (0..times).map(|i| i as f64 * step).collect(),
        effects,
        noise_mm: NOISE,
        orientation: false,
        measured_temps: false,
        seed,
    }
}

fn run(meas: &Measurements) -> Diagnosis {
    let prepared = prepare(meas, &Model::default(), false).unwrap();
    let d = diagnose(
        &prepared,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap();
    if std::env::var_os("DIAG_VERBOSE").is_some() {
        eprintln!("{}", summary(&d));
        for c in &d.candidates {
            eprintln!("  {} {:.4} {:?}", c.name, c.cv_rms_mm, c.error);
        }
        for s in &d.steps {
            eprintln!(
                "  step {} {:.4} -> {:.4}",
                s.added, s.gap_before_mm, s.gap_after_mm
            );
        }
    }
    d
}

fn scaled(kind: EffectKind, factor: f64) -> Effect {
    // 12 poses: geometry-offset's lengths and zeros, not its joint origins.
    let mut e = super::fit::lengths_and_zeros(Effect::with_defaults(kind));
    for p in &mut e.params {
        *p *= factor;
    }
    e
}

fn summary(d: &Diagnosis) -> String {
    format!(
        "verdict {:?}, held-out {:.4} -> {:.4} mm, ambiguous {:?}, partial {:?}, where {:?}",
        d.verdict.labels(),
        d.gap_before_mm,
        d.gap_after_mm,
        d.ambiguous,
        d.partial,
        d.where_after.words()
    )
}

/// Replace the positions of `meas` by `real(row index, row) + noise`.
fn remeasure(
    meas: &mut Measurements,
    seed: u64,
    real: impl Fn(usize, f64, &[f64; 6]) -> Vector3<f64>,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = Normal::new(0.0, NOISE).unwrap();
    for (i, r) in meas.rows.iter_mut().enumerate() {
        let p = real(i, r.time_min, &r.joints);
        r.position = p + Vector3::new(n.sample(&mut rng), n.sample(&mut rng), n.sample(&mut rng));
    }
}

fn warm(t: f64) -> MotorTemps {
    default_profile().temps_at(t).unwrap()
}

/// Every effect at its default magnitude, with orientation measured: the
/// right effect named first in every set, and the held-out gap after
/// within 1.5× the noise RMS. The sets at half and two and a half times
/// the default (`each_library_effect_at_three_magnitudes`, minutes in a
/// debug build) are the same sets the full sweep draws.
#[test]
fn each_library_effect_is_named_first() {
    named_first(&[1]);
}

/// For every effect, three data sets at different magnitudes, seeds and
/// poses: the right effect named first in at least 90 % of them, and the
/// held-out gap after within 1.5× the noise RMS. Run it with
/// `cargo test --release --test diagnose three_magnitudes -- --ignored`.
#[test]
#[ignore = "24 sets, minutes: cargo test --release --test diagnose three_magnitudes -- --ignored"]
fn each_library_effect_at_three_magnitudes() {
    named_first(&[0, 1, 2]);
}

/// The sets `which` (0: half the default, logged temperatures off; 1: the
/// default with orientation; 2: two and a half times it with logged
/// temperatures) of every effect, at least 90 % right.
fn named_first(which: &[usize]) {
    let profile = default_profile();
    let mut total = 0;
    let mut right = 0;
    let mut failures = Vec::new();
    for (k, kind) in EffectKind::ALL.into_iter().enumerate() {
        for (j, factor) in [0.5, 1.0, 2.5].into_iter().enumerate() {
            if !which.contains(&j) {
                continue;
            }
            let seed = 100 + 10 * k as u64 + j as u64;
            let mut s = spec(vec![scaled(kind, factor)], 12, 31, seed);
            // Vary the data's form too: orientation and logged temperatures.
            s.orientation = j == 1;
            s.measured_temps = j == 2;
            let meas = simulate(&s, &profile).unwrap();
            let d = run(&meas);
            total += 1;
            let named = d.verdict.labels().first().map(String::as_str) == Some(kind.name());
            let small = d.gap_after_mm <= 1.5 * noise_rms();
            if named && small {
                right += 1;
            } else {
                failures.push(format!("{} ×{factor}: {}", kind.name(), summary(&d)));
            }
        }
    }
    assert!(
        right * 10 >= total * 9,
        "{right}/{total} right; failures:\n{}",
        failures.join("\n")
    );
}

#[test]
fn noise_only_gives_none() {
    let profile = default_profile();
    for seed in [1, 2, 3] {
        let meas = simulate(&spec(vec![], 12, 31, seed), &profile).unwrap();
        let d = run(&meas);
        assert_eq!(d.verdict.labels(), vec!["none"], "{}", summary(&d));
        // The noise estimate from repeated poses is close to the truth.
        assert!(
            (d.noise.per_axis_mm - NOISE).abs() < 0.2 * NOISE,
            "{:?}",
            d.noise
        );
    }
}

/// The detection limit means what it says: an effect at twice the size the
/// report gives for a set is named on the same poses, times and noise (the
/// limit is the size at which the test would reject with 90 % power; at
/// twice it the power is all but certain). Below the limit no single set
/// can show anything: whether a smaller effect is named is a matter of
/// chance, and a seeded set with nothing in it may lie just short of the
/// test's level.
#[test]
fn an_effect_at_twice_its_detection_limit_is_named() {
    let profile = default_profile();
    let seed = 1;
    let quiet = run(&simulate(&spec(vec![], 12, 31, seed), &profile).unwrap());
    assert_eq!(quiet.verdict.labels(), vec!["none"], "{}", summary(&quiet));
    for kind in [EffectKind::ExpansionScale, EffectKind::MountDrift] {
        let limit = quiet
            .detection_limits
            .iter()
            .find(|l| l.effect == kind)
            .unwrap_or_else(|| panic!("no detection limit for {}", kind.name()));
        assert!(
            limit.of_default.is_finite() && limit.of_default > 0.0 && limit.flange_mm > 0.0,
            "{limit:?}"
        );
        let e = scaled(kind, 2.0 * limit.of_default);
        let d = run(&simulate(&spec(vec![e], 12, 31, seed), &profile).unwrap());
        assert!(
            d.verdict.labels().iter().any(|l| l == kind.name()),
            "{} at twice its detection limit ({:.4} mm): {}",
            kind.name(),
            limit.flange_mm,
            summary(&d)
        );
    }
}

/// Rule 6 of issue 46: an effect that fits but lies below what the poses,
/// times and noise could reveal is not named. On the set of
/// `an_effect_at_twice_its_detection_limit_is_named` (seed 1), a scaled
/// expansion at a quarter of the limit the report gives for it (0.002 mm
/// when measured on main) was named with the held-out gap no lower; it
/// must not be. The one at twice the limit is named, and named again in
/// at least 80 % of the resampled fits (rule 5), which the report gives.
#[test]
fn an_effect_below_its_detection_limit_is_not_named() {
    let profile = default_profile();
    let seed = 1;
    let quiet = run(&simulate(&spec(vec![], 12, 31, seed), &profile).unwrap());
    let kind = EffectKind::ExpansionScale;
    let limit = quiet
        .detection_limits
        .iter()
        .find(|l| l.effect == kind)
        .unwrap()
        .clone();
    let d = run(&simulate(
        &spec(vec![scaled(kind, 0.25 * limit.of_default)], 12, 31, seed),
        &profile,
    )
    .unwrap());
    assert!(
        !d.verdict.effects().contains(&kind),
        "{} at a quarter of its detection limit ({:.4} mm): {}",
        kind.name(),
        limit.flange_mm,
        summary(&d)
    );
    let d = run(&simulate(
        &spec(vec![scaled(kind, 2.0 * limit.of_default)], 12, 31, seed),
        &profile,
    )
    .unwrap());
    assert!(d.verdict.effects().contains(&kind), "{}", summary(&d));
    let st = d
        .stability
        .iter()
        .find(|s| s.effect == kind)
        .expect("the stability of the effect named");
    assert!(st.resamples >= 8 && st.frequency >= 0.8, "{st:?}");
    assert!(
        d.words().iter().any(|w| w.contains("resampled fits")),
        "{:#?}",
        d.words()
    );
}

/// Whether a verdict flags what no effect of the library explains and names
/// no effect beyond the arm's own geometry and the instrument's frame, which
/// every real set may carry (a geometric calibration takes up part of any
/// static error).
fn unexplained_only(labels: &[String]) -> bool {
    labels.iter().any(|l| l == "unexplained")
        && labels
            .iter()
            .all(|l| ["unexplained", "geometry-offset", "tracker-frame"].contains(&l.as_str()))
}

/// A cyclic error of one gear (Δq = A·sin(n·q + φ)), outside the library:
/// `unexplained`, and the residual follows that axis's angle.
#[test]
fn cyclic_gear_error_is_unexplained_and_located_on_its_axis() {
    let profile = default_profile();
    for (axis, harmonic, amp, seed) in [(1usize, 2.0, 0.4e-3, 7u64), (3, 3.0, 0.4e-3, 8)] {
        let mut meas = simulate(&spec(vec![], 40, 7, seed), &profile).unwrap();
        let base = Base::default();
        remeasure(&mut meas, seed, |_, t, q| {
            let mut p = Perturbation::default();
            p.dq[axis - 1] = amp * (harmonic * q[axis - 1] + 0.3).sin();
            let opw = base.thermal.expand(base.nominal.opw().unwrap(), &warm(t));
            fk_chain(&opw, q, &p).translation.vector
        });
        let d = run(&meas);
        assert!(unexplained_only(&d.verdict.labels()), "{}", summary(&d));
        let located = if d.partial.is_empty() {
            &d.where_
        } else {
            &d.where_after
        };
        let joint = located.joint.as_ref().expect("the joint it follows");
        assert_eq!(joint.axis, axis, "{}", summary(&d));
        assert_eq!(joint.harmonic as f64, harmonic, "{}", summary(&d));
    }
}

/// The base jumps 0.1 mm (mostly down) at minute 93: `unexplained`, with
/// the step located between the measurements around it.
#[test]
fn sudden_base_jump_is_unexplained_and_located_in_time() {
    let profile = default_profile();
    let mut meas = simulate(&spec(vec![], 12, 31, 21), &profile).unwrap();
    let base = Base::default();
    let jump = Vector3::new(0.02, 0.0, -0.1);
    remeasure(&mut meas, 21, |_, t, q| {
        let p = base
            .thermal
            .expand(base.nominal.opw().unwrap(), &warm(t))
            .fk(q)
            .translation
            .vector;
        if t > 93.0 {
            p + jump
        } else {
            p
        }
    });
    let d = run(&meas);
    // Unexplained, and no thermal effect forced onto it; the step's mean
    // over the session is a rigid offset the static stage may call a frame.
    assert!(
        d.verdict.labels().iter().any(|l| l == "unexplained")
            && d.verdict.effects().iter().all(|k| !k.is_thermal()),
        "{}",
        summary(&d)
    );
    let located = if d.partial.is_empty() {
        &d.where_
    } else {
        &d.where_after
    };
    let step = located.step.as_ref().expect("a step in time");
    assert_eq!(
        (step.before_min, step.after_min),
        (90.0, 96.0),
        "{}",
        summary(&d)
    );
    assert!(step.direction[2] < -0.9, "{:?}", step);
}

#[test]
fn mixture_of_two_effects_finds_both() {
    let profile = default_profile();
    for (a, b, seed) in [
        (EffectKind::ArmBending, EffectKind::TrackerFrame, 31u64),
        (EffectKind::MountDrift, EffectKind::GravitySag, 32),
    ] {
        let meas = simulate(
            &spec(vec![scaled(a, 1.0), scaled(b, 1.0)], 12, 31, seed),
            &profile,
        )
        .unwrap();
        let d = run(&meas);
        assert!(
            d.verdict.labels().iter().any(|v| v == a.name())
                && d.verdict.labels().iter().any(|v| v == b.name()),
            "{}",
            summary(&d)
        );
        assert!(d.gap_after_mm <= 1.5 * noise_rms(), "{}", summary(&d));
    }
}

/// Library effects in parameterisations the library does not use.
#[test]
fn other_parameterisations_are_still_recognised() {
    let profile = default_profile();
    let base = Base::default();
    let th = base.thermal.clone();

    // Expansion in only one link (the upper arm twice the base model's).
    let mut one_link = Effect::zero(EffectKind::ExpansionScale);
    one_link.params[2] = 1.0;
    let meas = simulate(&spec(vec![one_link], 12, 31, 41), &profile).unwrap();
    let d = run(&meas);
    assert_eq!(
        d.verdict.labels().first().map(String::as_str),
        Some("expansion-scale"),
        "{}",
        summary(&d)
    );

    // Second-order lag: the structure follows the motors through two
    // cascaded first-order lags (20 and 15 min).
    let hist = TempHistory::from_profile(&profile, 180.0).unwrap();
    let first = hist.lagged(20.0);
    let recs: Vec<(f64, MotorTemps)> = (0..=360)
        .map(|i| (i as f64 * 0.5, first.at(i as f64 * 0.5)))
        .collect();
    let second_hist = TempHistory::from_records(&recs, th.t_ref);
    let second = second_hist.lagged(15.0);
    let mut meas = simulate(&spec(vec![], 12, 31, 42), &profile).unwrap();
    let lag_marker = vec![Effect::zero(EffectKind::ThermalLag)];
    remeasure(&mut meas, 42, |_, t, q| {
        let row = RowState {
            q: *q,
            temps: warm(t),
            lagged: Some([second.at(t); 4]),
        };
        rapidtherm::model::predict(&base, &lag_marker, &row)
            .translation
            .vector
    });
    let d = run(&meas);
    assert_eq!(
        d.verdict.labels().first().map(String::as_str),
        Some("thermal-lag"),
        "{}",
        summary(&d)
    );
    assert!(d.gap_after_mm <= 1.5 * noise_rms(), "{}", summary(&d));

    // Mount drift driven by the room warming linearly (3 K in 3 h) rather
    // than by the base motor: a shift up and a tilt about x.
    let mut meas = simulate(&spec(vec![], 12, 31, 44), &profile).unwrap();
    remeasure(&mut meas, 44, |_, t, q| {
        let rise = 3.0 * t / 180.0;
        let p = Perturbation {
            base: nalgebra::Isometry3::from_parts(
                nalgebra::Translation3::new(0.0, 0.0, 0.02 * rise),
                nalgebra::UnitQuaternion::from_scaled_axis(Vector3::new(20e-6 * rise, 0.0, 0.0)),
            ),
            ..Perturbation::default()
        };
        fk_chain(&th.expand(base.nominal.opw().unwrap(), &warm(t)), q, &p)
            .translation
            .vector
    });
    let d = run(&meas);
    // The library's mount drift follows the base motor, which saturates
    // within the hour; this one follows the room, linearly. Named as mount
    // drift, or left unexplained with no other thermal effect forced on it.
    let labels = d.verdict.labels();
    assert!(
        labels.first().map(String::as_str) == Some("mount-drift")
            || (labels.iter().any(|l| l == "unexplained")
                && d.verdict.effects().iter().all(|k| !k.is_thermal())),
        "{}",
        summary(&d)
    );

    // Nonuniform bending: curvature growing linearly along the lower arm
    // (tip displacement θL/3 instead of θL/2 for a tip rotation θ), written
    // as uniform bending of 4θ/3 plus a turn of −θ/3 at the joint.
    let mut meas = simulate(&spec(vec![], 12, 31, 43), &profile).unwrap();
    remeasure(&mut meas, 43, |_, t, q| {
        let temps = warm(t);
        let rise = th.link_temps(&temps)[1] - th.t_ref;
        let theta = 40e-6 * rise;
        let p = Perturbation {
            kappa_lower: 4.0 / 3.0 * theta / base.nominal.opw().unwrap().c2,
            dq: [0.0, -theta / 3.0, 0.0, 0.0, 0.0, 0.0],
            ..Perturbation::default()
        };
        let opw = th.expand(base.nominal.opw().unwrap(), &temps);
        fk_chain(&opw, q, &p).translation.vector
    });
    let d = run(&meas);
    let labels = d.verdict.labels();
    // Exactly a uniform bending plus a joint turn: the library's picture of
    // it is either, or both.
    let named = ["arm-bending", "joint-offset-drift"]
        .iter()
        .any(|n| labels.iter().any(|l| l == n))
        || d.ambiguous
            .iter()
            .any(|p| p.iter().any(|n| n == "arm-bending"));
    assert!(named, "{}", summary(&d));
}

/// A library effect plus a smaller one from outside the library: the
/// library effect is named first and the rest is flagged as unexplained,
/// located on its axis.
#[test]
fn library_effect_plus_outside_effect_names_one_and_flags_the_rest() {
    let profile = default_profile();
    let seed = 61;
    let bending = Effect::with_defaults(EffectKind::ArmBending);
    let mut meas = simulate(&spec(vec![], 40, 11, seed), &profile).unwrap();
    let base = Base::default();
    remeasure(&mut meas, seed, |_, t, q| {
        let temps = warm(t);
        let (warm, mut p) = rapidtherm::model::perturbation(
            &base,
            std::slice::from_ref(&bending),
            &RowState {
                q: *q,
                temps,
                lagged: None,
            },
        );
        p.dq[1] += 0.12e-3 * (2.0 * q[1] + 0.5).sin();
        rapidtherm::model::fk_perturbed(&base, &warm, q, &p)
            .translation
            .vector
    });
    let d = run(&meas);
    assert_eq!(
        d.verdict.labels().first().map(String::as_str),
        Some("arm-bending"),
        "{}",
        summary(&d)
    );
    assert!(
        d.verdict.labels().iter().any(|v| v == "unexplained"),
        "{}",
        summary(&d)
    );
    let joint = d
        .where_after
        .joint
        .as_ref()
        .expect("the joint the rest follows");
    assert_eq!((joint.axis, joint.harmonic), (2, 2), "{}", summary(&d));
}

/// Each pose measured once (no repeats, so no measured noise level) with
/// an instrument noisier than the nominal 0.01 mm: structureless data give
/// `none`; with a gear error no library effect is named and the gap is
/// located on its axis.
#[test]
fn without_repeated_poses_only_structure_is_unexplained() {
    let profile = default_profile();
    for gear in [false, true] {
        let mut s = spec(vec![], 200, 2, 71);
        s.times = vec![0.0];
        s.measured_temps = true;
        let mut meas = simulate(&s, &profile).unwrap();
        for (i, r) in meas.rows.iter_mut().enumerate() {
            r.time_min = i as f64 * 0.9;
        }
        let base = Base::default();
        let mut rng = ChaCha8Rng::seed_from_u64(71);
        let n = Normal::new(0.0, 0.02).unwrap();
        for r in &mut meas.rows {
            let mut p = Perturbation::default();
            if gear {
                p.dq[2] = 0.4e-3 * (3.0 * r.joints[2]).sin();
            }
            let cold = base.thermal.expand(base.nominal.opw().unwrap(), &[7.0; 6]);
            r.position = fk_chain(&cold, &r.joints, &p).translation.vector
                + Vector3::new(n.sample(&mut rng), n.sample(&mut rng), n.sample(&mut rng));
        }
        let d = run(&meas);
        if gear {
            // The noise is not measured: what is left cannot be tested
            // against it (issue 46: no assumed instrument level), so the
            // verdict names no library effect beyond the geometry and the
            // frame, says the noise was not measured where it names
            // nothing, and the gap still points at the gear's axis.
            let labels = d.verdict.labels();
            assert!(
                unexplained_only(&labels)
                    || labels.iter().all(|l| {
                        ["none", "geometry-offset", "tracker-frame"].contains(&l.as_str())
                    }),
                "{}",
                summary(&d)
            );
            if d.verdict == rapidtherm::diagnose::Verdict::None {
                assert!(
                    matches!(
                        d.advice,
                        rapidtherm::diagnose::Advice::NoiseNotMeasured { .. }
                    ),
                    "{}",
                    summary(&d)
                );
            }
            assert_eq!(
                d.where_.joint.as_ref().map(|j| j.axis),
                Some(3),
                "{}",
                summary(&d)
            );
        } else {
            assert_eq!(d.verdict.labels(), vec!["none"], "{}", summary(&d));
        }
    }
}
