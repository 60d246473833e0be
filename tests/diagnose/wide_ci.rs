//! The widened evaluation (`wide/`) at the size of every `cargo test`: two
//! seeded sets per class, its rate asserted, so that a rule
//! that names what the data cannot say fails here and not only in the full
//! run (`cargo run --release --example diagnose_eval -- --sets 100`).

use super::wide::run::{evaluate, specs};
use super::wide::world::Class;

/// Every class twice (seeds 46_500 + 1000·c + i, i = 0, 1; forms of the
/// arms, with and without temperatures, repeats, clock and frame, as
/// `specs` spreads them): at least RATE right.
#[test]
fn widened_evaluation_seeded() {
    let out = evaluate(&specs(2, 46_500, &Class::ALL), |_| {});
    let text = format!(
        "{}\n{}",
        out.records
            .iter()
            .map(|r| r.line())
            .collect::<Vec<_>>()
            .join("\n"),
        out.table()
    );
    if std::env::var_os("DIAG_VERBOSE").is_some() {
        eprintln!("{text}");
    }
    let (r, n) = out.total();
    assert!(
        r * 100 >= n * RATE,
        "{r}/{n} right, below {RATE} %:\n{text}"
    );
}

/// The rate the seeded sets must reach, per cent: the acceptance's 95 %,
/// which of 14 sets is all 14. On the code before issue 46's rules
/// (a5c04d6) 3 of the first 7 were right: a thermal-lag named without
/// temperature columns, an arm-bending named below its detection limit and
/// without temperatures, a mount drift below its limit named arm-bending
/// and `unexplained`; at stop 45 (a97c746), 40 % was the floor. The full
/// run (`examples/diagnose_eval.rs`, 700 sets) is in docs/diagnose.md.
const RATE: usize = 95;

/// Where each pose is measured once there is no pose's own offset to take
/// out: a thermal effect shows only in the whole gap, and its detection
/// limit and the "below the limit" rule must be taken there. Taken over
/// time (each pose centred on itself), every effect's own part was zero,
/// its limit infinite, and these two were dropped as below it: a lag of
/// 9 times its limit on a KR 210 (the held-out gap 0.181 → 0.050 mm with
/// it) and an expansion of 3.7 times its limit on the IRB 140.
#[test]
fn thermal_effects_of_poses_measured_once_are_judged_on_the_whole_gap() {
    use super::wide::world::{generate, Form, Spec};
    use rapidtherm::diagnose::measurements::Measurements;
    use rapidtherm::diagnose::{diagnose, prepare_arm, DiagnoseOptions};
    use rapidtherm::model::{EffectKind, Model};
    for (kind, form, seed) in [
        (EffectKind::ThermalLag, 11, 48_017),
        (EffectKind::ExpansionScale, 8, 47_057),
    ] {
        let spec = Spec {
            class: Class::Effect(kind),
            form: Form::of_index(form),
            seed,
        };
        assert!(
            spec.form.temps && !spec.form.repeats,
            "{}",
            spec.form.label()
        );
        let set = generate(&spec);
        let m = Measurements::parse("wide.csv", set.csv.as_bytes(), &set.arm.limits_deg).unwrap();
        let p = prepare_arm(&m, &Model::default(), &set.arm, !spec.form.registered).unwrap();
        let d = diagnose(&p, &DiagnoseOptions::default()).unwrap();
        let labels = d.verdict.labels();
        assert!(
            labels.iter().any(|l| l == kind.name()),
            "seed {seed}: {} not named: {labels:?}",
            kind.name()
        );
        let limit = d
            .detection_limits
            .iter()
            .find(|l| l.effect == kind)
            .unwrap_or_else(|| panic!("seed {seed}: no detection limit for {}", kind.name()));
        assert!(
            limit.flange_mm.is_finite() && limit.flange_mm < set.truth.size_mm,
            "seed {seed}: limit {} mm against a withheld {} mm",
            limit.flange_mm,
            set.truth.size_mm
        );
    }
}
