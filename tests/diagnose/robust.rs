//! Nothing panics on any input: arbitrary measurement files are either
//! refused with a located error or give finite numbers.

use proptest::prelude::*;
use rapidtherm::diagnose::measurements::{Measurements, IRB140_LIMITS_DEG};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{diagnose, gap, prepare, DiagnoseOptions};
use rapidtherm::model::Model;

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        60 => (-90.0f64..50.0).prop_map(|v| format!("{v}")),
        30 => (-2000.0f64..2000.0).prop_map(|v| format!("{v:.3}")),
        1 => Just("NaN".to_string()),
        1 => Just("inf".to_string()),
        1 => Just("1e308".to_string()),
        1 => Just("".to_string()),
        1 => Just("x".to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn arbitrary_measurement_files_never_panic(
        rows in prop::collection::vec(prop::collection::vec(value(), 10..12), 0..40),
        with_temps in any::<bool>(),
        sorted_time in any::<bool>(),
        clean in prop::collection::vec((-90.0f64..50.0, -1500.0f64..1500.0), 0..40),
    ) {
        // Either arbitrary fields, or valid rows with arbitrary geometry.
        let rows: Vec<Vec<String>> = if sorted_time && !clean.is_empty() {
            clean
                .iter()
                .map(|(q, x)| {
                    let mut r: Vec<String> = (0..7).map(|k| format!("{}", q * (k as f64 + 1.0) / 7.0)).collect();
                    r.extend([format!("{x}"), format!("{}", x * 0.5), format!("{}", 700.0 - x * 0.1)]);
                    r
                })
                .collect()
        } else {
            rows
        };
        let mut text = String::from("time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm");
        if with_temps {
            text.push_str(",t1_c");
        }
        text.push('\n');
        for (i, r) in rows.iter().enumerate() {
            let mut r = r.clone();
            if sorted_time {
                r[0] = format!("{}", i * 5);
            }
            text.push_str(&r.join(","));
            text.push('\n');
        }
        if let Ok(m) = Measurements::parse("fuzz.csv", text.as_bytes(), &IRB140_LIMITS_DEG) {
            if let Ok(p) = prepare(&m, &Model::default(), false) {
                let g = gap(&p);
                prop_assert!(g.rms_mm.is_finite() && g.max_mm.is_finite());
                // With the cold start assumed, and with nothing assumed (no
                // thermal candidate, a drift in time, the noise maybe not
                // measured).
                for opts in [DiagnoseOptions::default().with_cold_start(ColdStart::Irb140), DiagnoseOptions::default()] {
                    if let Ok(d) = diagnose(&p, &opts) {
                        prop_assert!(d.gap_after_mm.is_finite());
                        prop_assert!(d.noise.per_axis_mm.is_finite());
                    }
                }
            }
        }
    }
}

#[test]
fn repeated_identical_rows_are_refused_and_one_pose_does_not_break_the_fits() {
    // Exact copies of a row are no measurements: refused at the first copy,
    // naming the row copied.
    let header = "time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm\n";
    let mut text = String::from(header);
    for _ in 0..40 {
        text.push_str("10,0,0,0,0,0,0,515.01,0,712\n");
    }
    let e = Measurements::parse("same.csv", text.as_bytes(), &IRB140_LIMITS_DEG).unwrap_err();
    assert!(
        e.message.contains("38 more repeat line 2 exactly"),
        "{}",
        e.message
    );
    assert_eq!(e.location.as_ref().map(|l| l.line), Some(3));
    // One pose measured again and again (the tracker's noise in the last
    // digits): nothing identifiable, no panic, no NaN.
    let mut text = String::from(header);
    for k in 0..40 {
        text.push_str(&format!(
            "10,0,0,0,0,0,0,{:.3},0,712\n",
            515.0 + 0.001 * k as f64
        ));
    }
    let m = Measurements::parse("one.csv", text.as_bytes(), &IRB140_LIMITS_DEG).unwrap();
    let p = prepare(&m, &Model::default(), false).unwrap();
    match diagnose(
        &p,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    ) {
        Ok(d) => assert!(d.gap_after_mm.is_finite() && d.gap_before_mm.is_finite()),
        Err(e) => assert!(!e.message.is_empty()),
    }
}
