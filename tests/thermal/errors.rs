//! Bad heating recordings: every error names the file, line and column, and
//! nothing panics on arbitrary input.

use proptest::prelude::*;
use rapidtherm::thermal::fit::{fit_axis, ModelKind};
use rapidtherm::thermal::{HeatingProfile, HeatingRecord, RecordedProfile};
use rapidtherm::ErrorKind;

const HEADER: &str = "time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c\n";

fn located(src: &str) -> (usize, usize, String) {
    let e = HeatingRecord::parse("rec.csv", src.as_bytes()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    let loc = e.location.clone().expect("a location");
    assert_eq!(loc.file, "rec.csv");
    (loc.line, loc.col, e.to_string())
}

#[test]
fn missing_column_names_the_header_line() {
    let (line, col, msg) = located("# c\ntime_min,t1_c,t2_c,t3_c,t4_c,t6_c\n0,7,7,7,7,7\n");
    assert_eq!((line, col), (2, 1));
    assert!(msg.contains("missing required column `t5_c`"), "{msg}");
}

#[test]
fn nan_names_line_and_column() {
    let (line, col, msg) = located(&format!("{HEADER}0,7,7,7,7,7,7\n0.5,7,7,NaN,7,7,7\n"));
    assert_eq!((line, col), (3, 9));
    assert!(msg.contains("`NaN` is not a finite number"), "{msg}");
    assert!(msg.contains("rec.csv:3:9: error:"), "{msg}");
}

#[test]
fn time_going_backwards_names_the_row() {
    let (line, col, msg) = located(&format!(
        "{HEADER}0,7,7,7,7,7,7\n1,7,7,7,7,7,7\n\n0.5,7,7,7,7,7,7\n"
    ));
    assert_eq!((line, col), (5, 1));
    assert!(msg.contains("goes backwards"), "{msg}");
}

#[test]
fn fewer_points_than_parameters_names_the_axis_column() {
    let src = format!("{HEADER}0,7,7,7,7,7,7\n1,8,8,8,8,8,8\n2,9,9,9,9,9,9\n");
    let rec = HeatingRecord::parse("rec.csv", src.as_bytes()).unwrap();
    let e = fit_axis(&rec, 4, ModelKind::Poly(3), None).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    let loc = e.location.clone().unwrap();
    assert_eq!((loc.line, loc.col), (4, 9));
    assert!(e.message.contains("`t4_c`: 3 points"), "{}", e.message);
    let e = fit_axis(&rec, 6, ModelKind::TwoTau, None).unwrap_err();
    assert!(e.message.contains("5 parameters"), "{}", e.message);
    // With T(0) pinned, the first-order model has 2 parameters: enough
    // points. (A straight rise over 2 minutes cannot tell its time
    // constant: that fit is refused as degenerate, not for its points.)
    match fit_axis(&rec, 6, ModelKind::FirstOrder, Some(7.0)) {
        Ok(_) => {}
        Err(e) => assert_eq!(e.kind, ErrorKind::NoConvergence, "{e}"),
    }
}

#[test]
fn short_row_is_located() {
    let (line, _, msg) = located(&format!("{HEADER}0,7,7,7,7,7\n"));
    assert_eq!(line, 2);
    assert!(msg.contains("column `t6_c` is missing"), "{msg}");
}

#[test]
fn recorded_profile_interpolates_the_sample_between_rows() {
    let src = format!("{HEADER}10,7,8,9,10,11,12\n10.5,8,9,10,11,12,14\n");
    let rec = HeatingRecord::parse("rec.csv", src.as_bytes()).unwrap();
    let p = RecordedProfile::new(&rec);
    assert_eq!(
        p.temps_at(10.25).unwrap(),
        [7.5, 8.5, 9.5, 10.5, 11.5, 13.0]
    );
    let e = p.temps_at(5.0).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported);
    assert_eq!(p.holding_ends().temps_at(5.0).unwrap()[0], 7.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Arbitrary bytes after a valid header: an error or a record, never a
    /// panic; any record it accepts has non-decreasing, finite times.
    #[test]
    fn arbitrary_input_never_panics(body in proptest::collection::vec(any::<u8>(), 0..400)) {
        let mut src = HEADER.as_bytes().to_vec();
        src.extend(body);
        if let Ok(rec) = HeatingRecord::parse("p.csv", &src) {
            prop_assert!(rec.times.windows(2).all(|w| w[0] <= w[1]));
            prop_assert!(rec.times.iter().all(|t| t.is_finite() && *t >= 0.0));
            for kind in [ModelKind::Poly(2), ModelKind::FirstOrder] {
                let _ = fit_axis(&rec, 1, kind, None);
            }
        }
    }

    /// Numeric rows in random order and values: parse errors are located.
    #[test]
    fn numeric_rows_parse_or_locate(rows in proptest::collection::vec(
        (-5.0f64..200.0, proptest::array::uniform6(-50.0f64..80.0)), 1..30)) {
        let mut src = String::from(HEADER);
        for (t, temps) in &rows {
            src.push_str(&format!("{t}"));
            for v in temps { src.push_str(&format!(",{v}")); }
            src.push('\n');
        }
        match HeatingRecord::parse("p.csv", src.as_bytes()) {
            Ok(rec) => {
                prop_assert_eq!(rec.len(), rows.len());
                let p = RecordedProfile::new(&rec);
                let (lo, hi) = p.window();
                let mid = p.temps_at((lo + hi) / 2.0).unwrap();
                prop_assert!(mid.iter().all(|v| (-50.0..=80.0).contains(v)));
            }
            Err(e) => {
                let loc = e.location.unwrap();
                prop_assert!(loc.line >= 2 && loc.line <= rows.len() + 1);
            }
        }
    }
}

/// A recording shorter than its time constants (50 minutes of a motor
/// heating with 40 min and 4 h, 0.05 °C noise, 0.1 °C steps): a fit is a
/// curve whose terms the data support, or refused; never terms that run
/// away (the 116 K at a 4,900-min time constant, or −669,010 + 669,021 K,
/// that a real 49-minute recording once gave).
#[test]
fn a_short_recording_never_gives_a_degenerate_curve() {
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut text = String::from(HEADER);
    let mut t = 0.0;
    while t <= 50.0 + 1e-9 {
        let mut row = format!("{t:.3}");
        for ax in 0..6 {
            let (a1, a2) = (3.0 + ax as f64, 6.0 + 1.5 * ax as f64);
            let noise: f64 = (rng.random::<f64>() - 0.5) * 0.17;
            let v = 20.0 + a1 * -(-t / 40.0f64).exp_m1() + a2 * -(-t / 240.0f64).exp_m1() + noise;
            row.push_str(&format!(",{:.1}", (v * 10.0).round() / 10.0));
        }
        text.push_str(&row);
        text.push('\n');
        t += 0.5;
    }
    let rec = HeatingRecord::parse("short.csv", text.as_bytes()).unwrap();
    let mut refused = 0;
    for axis in 1..=6 {
        let y = &rec.temps[axis - 1];
        let range = y.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - y.iter().copied().fold(f64::INFINITY, f64::min);
        for kind in [ModelKind::FirstOrder, ModelKind::TwoTau] {
            match fit_axis(&rec, axis, kind, None) {
                Ok(f) => {
                    let rapidtherm::thermal::fit::Curve::Saturating(c) = &f.curve else {
                        panic!("a saturating model gives a saturating curve");
                    };
                    // No term at the time-constant bound (100 spans), no
                    // pair that cancels.
                    for k in &c.terms {
                        assert!(k.tau < 0.99 * 100.0 * 50.0, "axis {axis} {kind}: {k:?}");
                    }
                    if let [a, b] = c.terms.as_slice() {
                        assert!(
                            a.delta.signum() == b.delta.signum()
                                || a.delta.abs().min(b.delta.abs()) <= 3.0 * range,
                            "axis {axis} {kind}: {a:?} {b:?} (data rise {range})"
                        );
                    }
                }
                Err(e) => {
                    assert_eq!(e.kind, ErrorKind::NoConvergence, "{e}");
                    assert!(e.message.contains("degenerate"), "{e}");
                    refused += 1;
                }
            }
        }
    }
    // The 4-h term cannot be told from 50 minutes: some two-tau fits are
    // refused rather than printed, and the others say how little they know
    // of the steady temperature.
    assert!(refused > 0);
    let widest = (1..=6)
        .filter_map(|axis| fit_axis(&rec, axis, ModelKind::TwoTau, None).ok())
        .filter_map(|f| f.steady_interval.map(|(lo, hi)| hi - lo))
        .fold(0.0, f64::max);
    assert!(widest > 1.0, "widest steady interval {widest} °C");
}

/// On a recording as long as its warm-up (the 168-min reference sample)
/// the steady temperature is told to within half a degree by the model the
/// data support (two time constants, or what `auto` chooses).
#[test]
fn a_full_recording_tells_its_steady_temperature() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/samples/heating_irb140_60pct.csv"
    );
    let rec = HeatingRecord::parse(path, &std::fs::read(path).unwrap()).unwrap();
    for axis in 1..=6 {
        let two = fit_axis(&rec, axis, ModelKind::TwoTau, None).unwrap();
        let auto = fit_axis(&rec, axis, ModelKind::Auto, None).unwrap();
        for f in [&two, &auto] {
            let (lo, hi) = f.steady_interval.unwrap();
            assert!(hi - lo < 0.5, "axis {axis} {}: {lo}..{hi}", f.model_name());
        }
    }
}
