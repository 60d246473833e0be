//! Blind tests of the diagnosis: data simulated with one known effect (or
//! none, or effects outside the library, made here by the test itself) and
//! diagnosed with the base model.

use rapidtherm::diagnose::chain::{fk_chain, Perturbation};
use rapidtherm::diagnose::effects::{Base, Effect, EffectKind};
use rapidtherm::diagnose::measurements::{Measurements, IRB140_LIMITS_DEG};
use rapidtherm::diagnose::simulate::{random_poses, simulate, SimSpec};
use rapidtherm::diagnose::{diagnose, prepare, Diagnosis, Options};
use rapidtherm::model::Model;
use rapidtherm::thermal::default_profile;

const NOISE: f64 = 0.01;

fn spec(effects: Vec<Effect>, seed: u64) -> SimSpec {
    SimSpec {
        base: Base::default(),
        poses: random_poses(12, &IRB140_LIMITS_DEG, seed),
        times: (0..=30).map(|i| i as f64 * 6.0).collect(),
        effects,
        noise_mm: NOISE,
        orientation: false,
        measured_temps: false,
        seed,
    }
}

fn run(meas: &Measurements) -> Diagnosis {
    let prepared = prepare(meas, &Model::default(), false).unwrap();
    diagnose(&prepared, &Options::default()).unwrap()
}

fn scaled(kind: EffectKind, factor: f64) -> Effect {
    let mut e = Effect::with_defaults(kind);
    for p in &mut e.params {
        *p *= factor;
    }
    e
}

#[test]
fn probe() {
    let profile = default_profile();
    for kind in EffectKind::ALL {
        let meas = simulate(&spec(vec![scaled(kind, 1.0)], 3), &profile).unwrap();
        let t = std::time::Instant::now();
        let d = run(&meas);
        eprintln!(
            "{:20} -> {:?} before {:.4} after {:.4} noise {:.4} amb {:?} steps {:?} ({:?})",
            kind.name(),
            d.verdict,
            d.gap_before_mm,
            d.gap_after_mm,
            d.noise.rms_mm,
            d.ambiguous,
            d.steps.iter().map(|s| (s.added.clone(), s.gap_after_mm)).collect::<Vec<_>>(),
            t.elapsed()
        );
    }
}

#[test]
fn probe2() {
    let profile = default_profile();
    let meas = simulate(&spec(vec![scaled(EffectKind::GeometryOffset, 1.0)], 3), &profile).unwrap();
    let d = run(&meas);
    for c in &d.candidates {
        eprintln!("{} cv {:.4} err {:?}", c.name, c.cv_rms_mm, c.error);
    }
}
