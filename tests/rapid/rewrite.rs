//! The rewriter: numbers in the style of the ones they replace and within
//! resolution; edits spliced exactly, overlaps and stale old text refused.

use proptest::prelude::*;
use rapidtherm::rapid::rewrite::{
    apply_edits, format_like, Edit, POSITION_RESOLUTION, QUATERNION_RESOLUTION,
};

fn old_number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-800i32..800).prop_map(|i| i.to_string()),
        (-800_000i32..800_000, 1usize..6).prop_map(|(i, d)| format!("{:.*}", d, i as f64 / 1000.0)),
        (1u32..999).prop_map(|d| format!(".{d}")),
        (0u32..999).prop_map(|i| format!("{i}.")),
        (1u32..9, 0u32..99999, -9i32..10, any::<bool>()).prop_map(|(m, f, e, upper)| {
            let l = if upper { "E" } else { "e" };
            let sign = if e >= 0 { "+" } else { "-" };
            format!("{m}.{f:05}{l}{sign}{:02}", e.abs())
        }),
        Just("9E+09".to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn positions_within_half_a_micrometre_in_the_old_style(old in old_number(), v in -2000.0f64..2000.0) {
        let s = format_like(&old, v, POSITION_RESOLUTION);
        let back: f64 = s.parse().unwrap();
        prop_assert!((back - v).abs() <= 0.0005 + 1e-9 * v.abs(), "{old} {v} -> {s}");
        prop_assert_eq!(s.contains(['e', 'E']), old.contains(['e', 'E']), "{} -> {}", old, s);
        if let Some(l) = old.chars().find(|c| *c == 'e' || *c == 'E') {
            prop_assert!(s.contains(l), "{} -> {}", old, s);
        }
        if old.starts_with('.') && v.abs() < 1.0 && !s.contains(['e', 'E']) {
            prop_assert!(s.trim_start_matches('-').starts_with('.'), "{} -> {}", old, s);
        }
        // Never fewer decimals than the old text had.
        let decimals = |t: &str| t.split(['e', 'E']).next().unwrap().split('.').nth(1).map_or(0, str::len);
        prop_assert!(decimals(&s) >= decimals(&old), "{} -> {}", old, s);
        prop_assert_eq!(format_like(&old, v, POSITION_RESOLUTION), s);
    }

    #[test]
    fn quaternions_within_half_a_millionth(old in old_number(), v in -1.0f64..1.0) {
        let s = format_like(&old, v, QUATERNION_RESOLUTION);
        let back: f64 = s.parse().unwrap();
        prop_assert!((back - v).abs() <= 5e-7 + 1e-12, "{old} {v} -> {s}");
    }

    #[test]
    fn edits_splice_exactly(
        src in prop::collection::vec(any::<u8>(), 0..200),
        cuts in prop::collection::vec((any::<prop::sample::Index>(), 0usize..5, prop::collection::vec(any::<u8>(), 0..6)), 0..6),
    ) {
        // Non-overlapping spans from sorted cut points.
        let mut spans: Vec<(usize, usize, Vec<u8>)> = cuts
            .iter()
            .map(|(i, len, new)| {
                let s = if src.is_empty() { 0 } else { i.index(src.len() + 1) };
                (s, (s + len).min(src.len()), new.clone())
            })
            .collect();
        spans.sort_by_key(|s| s.0);
        let mut kept: Vec<(usize, usize, Vec<u8>)> = Vec::new();
        for s in spans {
            if kept.last().is_none_or(|k| s.0 >= k.1 && s.0 != k.0) {
                kept.push(s);
            }
        }
        let edits: Vec<Edit> = kept
            .iter()
            .rev() // any order is accepted
            .map(|(s, e, new)| Edit { span: *s..*e, expected_old: src[*s..*e].to_vec(), new: new.clone() })
            .collect();
        let out = apply_edits("f", &src, &edits).unwrap();
        let mut want = Vec::new();
        let mut at = 0;
        for (s, e, new) in &kept {
            want.extend_from_slice(&src[at..*s]);
            want.extend_from_slice(new);
            at = *e;
        }
        want.extend_from_slice(&src[at..]);
        prop_assert_eq!(out, want);
    }
}

#[test]
fn stale_and_overlapping_edits_are_refused() {
    let src = b"MoveL [[500,0,400]]";
    let e = |s: usize, t: usize, old: &[u8]| Edit {
        span: s..t,
        expected_old: old.to_vec(),
        new: b"1".to_vec(),
    };
    assert!(apply_edits("f", src, &[e(8, 11, b"500")]).is_ok());
    let err = apply_edits("f", src, &[e(8, 11, b"501")]).unwrap_err();
    assert!(
        err.to_string().contains("expected `501` here, found `500`"),
        "{err}"
    );
    assert!(apply_edits("f", src, &[e(8, 11, b"500"), e(10, 12, b"0,")]).is_err());
    assert!(apply_edits("f", src, &[e(12, 12, b""), e(12, 12, b"")]).is_err());
    assert!(apply_edits("f", src, &[e(18, 30, b"")]).is_err());
}

#[test]
fn robtarget_and_jointtarget_edits_rewrite_only_what_changed() {
    use rapidtherm::rapid::{self, rewrite};
    let src = b"MODULE m\r\n  CONST robtarget p := [[500,-0.5,3E2],[0.70711,0,.70711,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\r\n  CONST jointtarget j := [[0, 10.5, -20, 0, 90, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];\r\nENDMODULE\r\n";
    let prog = rapid::parse("m.mod", src).unwrap();
    let t = prog.targets().at(0);
    let v = t.value.as_ref().unwrap();
    let edits = rewrite::robtarget_edits(
        src,
        v,
        [500.0, -0.5004, 301.23456],
        Some([
            std::f64::consts::FRAC_1_SQRT_2,
            0.0,
            std::f64::consts::FRAC_1_SQRT_2,
            0.0,
        ]),
        Some([-1, 0, 0, 0]),
    );
    assert_eq!(edits.len(), 4);
    let out = rewrite::apply_edits("m.mod", src, &edits).unwrap();
    assert_eq!(out.iter().filter(|&&b| b == b'\r').count(), 4);
    let line = String::from_utf8_lossy(&out)
        .lines()
        .nth(1)
        .unwrap()
        .to_string();
    assert_eq!(
        line,
        // -0.5004 is -0.5 within 0.001 mm: that number is not rewritten.
        "  CONST robtarget p := [[500,-0.5,3.01235E2],[0.707107,0,.707107,0],[-1,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];"
    );
    let j = &prog.jointtargets()[0];
    let edits = rewrite::jointtarget_edits(src, j, [0.0, 10.51234, -20.0, 0.0, 90.0, 0.0]);
    assert_eq!(edits.len(), 1);
    // Joint angles are written to 1e-5° (the resolution the correction
    // uses; a second, coarser one is gone).
    assert_eq!(edits[0].new, b"10.51234".to_vec());
    // A change below half the resolution keeps the old text.
    assert!(rewrite::jointtarget_edits(src, j, [0.0, 10.500004, -20.0, 0.0, 90.0, 0.0]).is_empty());
}
