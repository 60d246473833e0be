//! Measurements mean what they say and models are plausible or refused
//! (issue 53). A model's bounds are read here from
//! data/plausible_effects.toml itself (by unit, or by a parameter's own
//! name), not from the reader under test.

use proptest::prelude::*;
use rapidtherm::diagnose::measurements::{Measurements, IRB140_LIMITS_DEG};
use rapidtherm::model::{EffectKind, Model};
use std::collections::BTreeMap;

const HEADER: &str = "time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm";

fn refused(src: &str) -> (usize, usize, String) {
    let e = Measurements::parse("m.csv", src.as_bytes(), &IRB140_LIMITS_DEG).unwrap_err();
    let loc = e.location.clone().expect("a location");
    (loc.line, loc.col, e.message)
}

#[test]
fn two_x_mm_columns_are_refused() {
    // The second `x_mm` is the 11th column, at character 67 of the header
    // (HEADER is 65 characters, then a comma).
    let src = format!("{HEADER},x_mm\n0,0,0,0,0,30,0,515,0,712,999\n");
    let (line, col, msg) = refused(&src);
    assert_eq!((line, col), (1, 67), "{msg}");
    assert!(msg.contains("named twice"), "{msg}");
}

#[test]
fn a_motor_temperature_in_kelvin_is_refused() {
    let src = format!(
        "{HEADER},t1_c,t2_c,t3_c,t4_c,t5_c,t6_c\n0,0,0,0,0,30,0,515,0,712,7,7,7,7,7,300.15\n"
    );
    let (line, _, msg) = refused(&src);
    assert_eq!(line, 2);
    assert!(msg.contains("kelvin"), "{msg}");
}

/// Every effect parameter's bound, `(kind, parameter) → bound`, from the
/// data file.
fn bounds() -> BTreeMap<(String, String), f64> {
    let text = include_str!("../../data/plausible_effects.toml");
    let file: BTreeMap<String, BTreeMap<String, f64>> = toml::from_str(text).unwrap();
    let mut out = BTreeMap::new();
    for kind in EffectKind::ALL {
        let table = &file[kind.name()];
        for p in kind.params() {
            let b = table.get(p.name).or_else(|| table.get(p.unit)).unwrap();
            out.insert((kind.name().to_string(), p.name.to_string()), *b);
        }
    }
    out
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// A model file with one effect parameter is read exactly when the
    /// parameter is within its bound, and refused at its key otherwise.
    #[test]
    fn a_model_is_read_only_within_the_plausible_bounds(
        pick in 0usize..1000,
        ratio in 0.01f64..100.0,
        negative in any::<bool>(),
    ) {
        let all = bounds();
        let ((kind, param), bound) = all.iter().nth(pick % all.len()).unwrap();
        // A negative time constant is refused for its sign.
        let negative = negative && kind != "thermal-lag";
        let value = bound * ratio * if negative { -1.0 } else { 1.0 };
        // Away from the bound itself (its decimal print).
        prop_assume!((ratio - 1.0).abs() > 1e-6);
        let text = format!(
            "{}\n[[effects]]\nname = \"{kind}\"\n[effects.params]\n{param} = {value:?}\n",
            include_str!("../../data/irb140/model.toml")
        );
        match Model::parse("m.toml", &text) {
            Ok(_) => prop_assert!(ratio < 1.0, "{} = {} taken beyond {}", param, value, bound),
            Err(e) => {
                prop_assert!(ratio > 1.0, "{} = {} refused: {}", param, value, e);
                let key = format!("`effects[1].params.{param}`");
                prop_assert!(e.message.contains(&key), "{}", e);
                prop_assert_eq!(e.location.unwrap().line, text.lines().count());
            }
        }
    }
}
