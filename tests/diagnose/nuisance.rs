//! The diagnosis on blind data with the nuisance of real measurements
//! (`world.rs`): a tracker metres away at any heading, the arm's own
//! geometric error, a reflector off the flange, 0.02 mm noise, sets with
//! and without logged temperatures, mixtures and two effects outside the
//! library. The diagnosis is run as a user runs it: the CSV parsed, the
//! instrument frame registered, the calibrated default model.

use super::world::{generate, DataSet, Effect, SetSpec};
use nalgebra::Vector3;
use rapidtherm::diagnose::measurements::{Measurements, IRB140_LIMITS_DEG};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{diagnose, prepare, DiagnoseOptions, Diagnosis, ScoredIn};
use rapidtherm::model::{EffectKind, Model};

/// What a set holds, by the library's names; `outside`: an effect the
/// library does not have.
struct Case {
    label: String,
    spec: SetSpec,
}

fn run(set: &DataSet) -> Diagnosis {
    let meas = Measurements::parse("blind.csv", set.csv.as_bytes(), &IRB140_LIMITS_DEG).unwrap();
    let prepared = prepare(&meas, &Model::default(), true).unwrap();
    diagnose(
        &prepared,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap()
}

fn summary(d: &Diagnosis) -> String {
    format!(
        "verdict {:?}, held-out {:.4} -> {:.4} mm (noise {:.4}), ambiguous {:?}, steps {:?}",
        d.verdict.labels(),
        d.gap_before_mm,
        d.gap_after_mm,
        d.noise.rms_mm,
        d.ambiguous,
        d.steps
            .iter()
            .map(|s| format!("{} {:.4}->{:.4}", s.added, s.gap_before_mm, s.gap_after_mm))
            .collect::<Vec<_>>()
    )
}

/// Whether the verdict is right: every thermal effect in the set named and
/// no other; a static library effect in the set named; a set with an
/// effect outside the library flagged `unexplained`, and one without not.
/// The static nuisance every set carries (the arm's geometry, the
/// tracker's frame) may be named or not.
fn right(case: &Case, d: &Diagnosis) -> bool {
    let labels = d.verdict.labels();
    let truth: Vec<&str> = case.spec.effects.iter().filter_map(Effect::name).collect();
    let outside = case.spec.effects.iter().any(|e| e.name().is_none());
    let thermal_named: Vec<&str> = labels
        .iter()
        .map(String::as_str)
        .filter(|l| EffectKind::from_name(l).is_some_and(EffectKind::is_thermal))
        .collect();
    let ambiguous_with = |name: &str| {
        d.ambiguous
            .iter()
            .any(|pair| pair.iter().any(|n| n == name))
    };
    let thermal_truth: Vec<&str> = truth
        .iter()
        .copied()
        .filter(|n| EffectKind::from_name(n).is_some_and(EffectKind::is_thermal))
        .collect();
    let all_found = truth
        .iter()
        .all(|t| labels.iter().any(|l| l == t) || ambiguous_with(t));
    let no_spurious = thermal_named.iter().all(|n| {
        thermal_truth.contains(n)
            || thermal_truth
                .iter()
                .any(|t| ambiguous_with(t) && ambiguous_with(n))
    });
    let static_ok = labels.iter().all(|l| {
        l == "geometry-offset"
            || l == "tracker-frame"
            || l == "unexplained"
            || l == "none"
            || truth.contains(&l.as_str())
            || EffectKind::from_name(l).is_some_and(EffectKind::is_thermal)
    });
    let flagged = labels.iter().any(|l| l == "unexplained");
    // A knock is located: a step between the measurements around it.
    let located = case.spec.effects.iter().all(|e| match e {
        Effect::Knock(at, _) => [&d.where_after, &d.where_]
            .iter()
            .filter_map(|w| w.step.as_ref())
            .any(|s| s.before_min < *at && *at < s.after_min),
        _ => true,
    });
    all_found && no_spurious && static_ok && flagged == outside && located
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    let mut add = |label: &str, effects: Vec<Effect>, seed: u64, logged: bool| {
        let mut spec = SetSpec::new(effects, seed);
        spec.temps_logged = logged;
        out.push(Case {
            label: format!(
                "{label} (seed {seed}, temps {})",
                if logged {
                    "logged"
                } else {
                    "from the heating model"
                }
            ),
            spec,
        });
    };
    for (i, logged) in [true, false].into_iter().enumerate() {
        let s = 1000 + 100 * i as u64;
        add("nothing", vec![], s, logged);
        add(
            "expansion-scale",
            vec![Effect::ExpansionScale([2.5, 2.0, 2.5, 2.0])],
            s + 1,
            logged,
        );
        add(
            "expansion-scale + thermal-lag",
            vec![Effect::ExpansionScale([3.0; 4]), Effect::ThermalLag(45.0)],
            s + 2,
            logged,
        );
        add(
            "arm-bending",
            vec![Effect::ArmBending([25e-6, 35e-6])],
            s + 3,
            logged,
        );
        add(
            "joint-offset-drift",
            vec![Effect::JointOffsetDrift([
                0.0, 40e-6, -30e-6, 0.0, 30e-6, 0.0,
            ])],
            s + 4,
            logged,
        );
        add(
            "mount-drift",
            vec![Effect::MountDrift(
                Vector3::new(0.001, -0.001, 0.006),
                [3e-6, -2e-6],
            )],
            s + 5,
            logged,
        );

        add(
            "expansion-scale + joint-offset-drift",
            vec![
                Effect::ExpansionScale([2.0, 2.5, 2.5, 2.0]),
                Effect::JointOffsetDrift([0.0, 30e-6, -40e-6, 0.0, 0.0, 0.0]),
            ],
            s + 7,
            logged,
        );
        add(
            "knock at minute 88",
            vec![Effect::Knock(88.0, Vector3::new(0.03, -0.02, -0.05))],
            s + 8,
            logged,
        );
    }
    // Calibration-style sessions: many poses, a few times each, where the
    // static part can be judged on held-out poses.
    let mut calib = |label: &str, effects: Vec<Effect>, seed: u64| {
        let mut spec = SetSpec::new(effects, seed);
        spec.poses = 40;
        spec.times = vec![0.0, 45.0, 90.0, 135.0, 180.0];
        out.push(Case {
            label: format!("{label} (seed {seed}, 40 poses)"),
            spec,
        });
    };
    calib("nothing", vec![], 1200);
    calib("gravity-sag", vec![Effect::GravitySag([8e-6, 10e-6])], 1201);
    calib("gravity-sag", vec![Effect::GravitySag([4e-6, 6e-6])], 1202);
    calib("axis-2 backlash", vec![Effect::Backlash(2, 0.25e-3)], 1203);
    calib(
        "arm-bending + gravity-sag",
        vec![
            Effect::ArmBending([25e-6, 35e-6]),
            Effect::GravitySag([6e-6, 8e-6]),
        ],
        1204,
    );
    out
}

/// Minutes in a debug build (21 sets): not in every `cargo test`, where
/// `eval::evaluation_seeded` runs one set of every class under the same
/// kinds of nuisance. Run it with
/// `cargo test --release --test diagnose verdicts_hold -- --ignored`.
#[test]
#[ignore = "21 sets, minutes: cargo test --release --test diagnose verdicts_hold -- --ignored"]
fn verdicts_hold_under_the_nuisance_of_real_measurements() {
    let cases = cases();
    let mut right_count = 0;
    let mut shrinks = Vec::new();
    let mut time_shrinks = Vec::new();
    let mut report = Vec::new();
    for case in &cases {
        let set = generate(&case.spec);
        assert!(set.rows > 100);
        let d = run(&set);
        let ok = right(case, &d);
        right_count += ok as usize;
        // Held-out shrink of the part of the gap that is not noise.
        let n2 = d.noise.rms_mm.powi(2);
        let excess = |before: f64, after: f64| {
            1.0 - (after * after - n2).max(0.0) / (before * before - n2).max(1e-12)
        };
        let shrink = excess(d.gap_before_mm, d.gap_after_mm);
        shrinks.push(shrink);
        let thermal = case.spec.effects.iter().any(|e| {
            e.name()
                .and_then(EffectKind::from_name)
                .is_some_and(EffectKind::is_thermal)
        });
        if let Some(s) = d
            .stages
            .iter()
            .find(|s| s.part == ScoredIn::OverTime)
            .filter(|_| thermal)
        {
            time_shrinks.push(excess(s.gap_before_mm, s.gap_after_mm));
        }
        report.push(format!(
            "{} {}: {}",
            if ok { "ok  " } else { "FAIL" },
            case.label,
            summary(&d)
        ));
    }
    shrinks.sort_by(f64::total_cmp);
    let median = shrinks[shrinks.len() / 2];
    time_shrinks.sort_by(f64::total_cmp);
    let time_median = time_shrinks[time_shrinks.len() / 2];
    let text = report.join("\n");
    if std::env::var_os("DIAG_VERBOSE").is_some() {
        eprintln!(
            "{text}\nright {right_count}/{}, median shrink {median:.3}, over time {time_median:.3}",
            cases.len()
        );
    }
    assert!(
        right_count * 10 >= cases.len() * 9,
        "{right_count}/{} right:\n{text}",
        cases.len()
    );
    assert!(median >= 0.8, "median held-out shrink {median:.3}:\n{text}");
    assert!(
        time_median >= 0.8,
        "median held-out shrink over time {time_median:.3}:\n{text}"
    );
}

/// A debugging aid: one case of [`cases`] (`DIAG_SEED`, its seed; the
/// first case without it), its candidates printed, and held to the rule
/// of [`right`] as [`verdicts_hold_under_the_nuisance_of_real_measurements`]
/// holds every case: it fails where the verdict is wrong.
#[test]
#[ignore = "a debugging aid: DIAG_SEED=n prints one case's candidates and fails where its verdict is wrong"]
fn one_case() {
    let cases = cases();
    let seed: u64 = std::env::var("DIAG_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(cases[0].spec.seed);
    let Some(case) = cases.into_iter().find(|c| c.spec.seed == seed) else {
        panic!("no case has the seed {seed}");
    };
    let set = generate(&case.spec);
    if let Some(path) = std::env::var_os("DIAG_DUMP") {
        std::fs::write(path, &set.csv).unwrap();
    }
    let d = run(&set);
    eprintln!("{}: {}", case.label, summary(&d));
    for c in &d.candidates {
        eprintln!("  {} {:.4} {:?}", c.name, c.cv_rms_mm, c.error);
    }
    eprintln!("{:?}", d.where_.words());
    eprintln!("{:?}", d.where_after.words());
    for s in &d.stages {
        eprintln!("{s:?}");
    }
    for c in d.candidates.iter().filter(|c| c.selected) {
        for p in &c.params {
            eprintln!("  {} {:.4} {:?}", p.name, p.value, p.stderr);
        }
    }
    assert!(right(&case, &d), "{}: {}", case.label, summary(&d));
}

/// A wider randomised sweep (minutes): `DIAG_SWEEP=N` sets (20 without
/// it) with random effects, magnitudes, seeds, tracker distance and
/// noise, each held to the rule of [`right`]; prints each verdict and
/// fails below [`SWEEP_RIGHT`] right.
#[test]
#[ignore = "a randomised sweep: DIAG_SWEEP=N cargo test --test diagnose sweep -- --ignored --nocapture"]
fn sweep() {
    use rand::{RngExt, SeedableRng};
    let n: u64 = std::env::var("DIAG_SWEEP").map_or(20, |v| v.parse().unwrap());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut right_count = 0;
    for i in 0..n {
        let m: f64 = rng.random_range(0.6..2.0);
        let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let effects = match rng.random_range(0..8) {
            0 => vec![],
            1 => vec![Effect::ExpansionScale([1.0 + 1.5 * m; 4])],
            2 => vec![Effect::ArmBending([25e-6 * m * sign, 35e-6 * m])],
            3 => vec![Effect::JointOffsetDrift([
                0.0,
                30e-6 * m * sign,
                -30e-6 * m,
                0.0,
                20e-6 * m,
                0.0,
            ])],
            4 => vec![Effect::MountDrift(
                Vector3::new(0.001, -0.001, 0.006 * m * sign),
                [3e-6 * m, -2e-6],
            )],
            5 => vec![Effect::Knock(
                rng.random_range(40.0..140.0),
                Vector3::new(0.03, -0.02, -0.05) * m,
            )],
            6 => vec![
                Effect::ExpansionScale([1.0 + 1.5 * m; 4]),
                Effect::JointOffsetDrift([0.0, 30e-6 * sign, -40e-6, 0.0, 0.0, 0.0]),
            ],
            _ => vec![
                Effect::ExpansionScale([3.0; 4]),
                Effect::ThermalLag(rng.random_range(30.0..60.0)),
            ],
        };
        let mut spec = SetSpec::new(effects, 5000 + i);
        spec.temps_logged = rng.random_bool(0.5);
        spec.noise_mm = rng.random_range(0.015..0.03);
        spec.tracker_mm = rng.random_range(2000.0..6000.0);
        spec.poses = rng.random_range(10..20);
        let case = Case {
            label: format!("{:?}", spec.effects),
            spec,
        };
        let d = run(&generate(&case.spec));
        let ok = right(&case, &d);
        right_count += ok as usize;
        eprintln!(
            "{} {}: {}",
            if ok { "ok  " } else { "FAIL" },
            case.label,
            summary(&d)
        );
        if !ok && std::env::var_os("DIAG_VERBOSE").is_some() {
            eprintln!(
                "    after: {:?} where: {:?}",
                d.where_after.words(),
                d.where_.step
            );
            for c in &d.candidates {
                eprintln!(
                    "    {} {} {:.4} {:?}",
                    c.part.name(),
                    c.name,
                    c.cv_rms_mm,
                    c.error
                );
            }
            eprintln!("    stages {:?}", d.stages);
        }
    }
    eprintln!("right {right_count}/{n}");
    let (num, den) = SWEEP_RIGHT;
    assert!(
        right_count as u64 * den >= n * num,
        "{right_count}/{n} right, below {num} in {den}"
    );
}

/// The share of right verdicts the sweep asks for: nine in ten, the bar
/// [`verdicts_hold_under_the_nuisance_of_real_measurements`] holds the
/// chosen cases to (docs/diagnose.md: "the test asks for 90 %").
const SWEEP_RIGHT: (u64, u64) = (9, 10);
