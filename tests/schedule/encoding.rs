//! A corrected file's marker records its schedule by the fingerprint of
//! the schedule's byte encoding (`schedule::encode_visits`, version 1):
//! the encoding is the one documented, written here byte by byte from
//! the visits, whatever the order and case they were recorded in.

use proptest::prelude::*;
use rapidtherm::digest::{fingerprint, Encoder};
use rapidtherm::schedule::{Schedule, SCHEDULE_ENCODING};

/// The documented bytes of the visits, in first-visit order, identifiers
/// in lower case.
fn documented(visits: &[(String, f64)]) -> Vec<u8> {
    let mut order: Vec<String> = Vec::new();
    let mut times: Vec<Vec<f64>> = Vec::new();
    for (id, t) in visits {
        let key = id.to_ascii_lowercase();
        match order.iter().position(|k| *k == key) {
            Some(i) => times[i].push(*t),
            None => {
                order.push(key);
                times.push(vec![*t]);
            }
        }
    }
    let mut b = SCHEDULE_ENCODING.as_bytes().to_vec();
    b.push(0);
    b.extend_from_slice(&(order.len() as u32).to_le_bytes());
    for (id, ts) in order.iter().zip(&times) {
        b.extend_from_slice(&(id.len() as u32).to_le_bytes());
        b.extend_from_slice(id.as_bytes());
        b.extend_from_slice(&(ts.len() as u32).to_le_bytes());
        for t in ts {
            b.extend_from_slice(&t.to_bits().to_le_bytes());
        }
    }
    b
}

fn encoded(s: &Schedule) -> String {
    let mut e = Encoder::new(SCHEDULE_ENCODING);
    s.encode(&mut e);
    e.finish()
}

/// Identifiers as programs have them: long shared prefixes, one a prefix
/// of another, case mixed, digits, `#`, `:` and `{`.
fn id() -> impl Strategy<Value = String> {
    let stems = prop::sample::select(vec![
        "main#",
        "M1:main#",
        "p",
        "pApproach",
        "pGrid{",
        "T_ROB1:Path_10#",
    ]);
    (stems, 0u32..2000, any::<bool>()).prop_map(|(stem, n, bare)| {
        if bare && n < 10 {
            stem.to_string()
        } else {
            format!("{stem}{n}")
        }
    })
}

proptest! {
    #[test]
    fn a_schedule_encodes_as_documented(
        visits in prop::collection::vec((id(), -1.0e5..1.0e17f64), 0..200),
    ) {
        let mut s = Schedule::new();
        for (id, t) in &visits {
            s.visit(id, *t);
        }
        prop_assert_eq!(encoded(&s), fingerprint(&documented(&visits)));
    }
}

#[test]
fn case_and_the_zeros_sign_are_read_as_rapid_and_ieee_754_read_them() {
    let mut a = Schedule::new();
    a.visit("P10", 1.0);
    a.visit("main#1", 0.0);
    let mut b = Schedule::new();
    b.visit("p10", 1.0);
    b.visit("MAIN#1", 0.0);
    assert_eq!(encoded(&a), encoded(&b), "identifiers ignore case");
    let mut c = Schedule::new();
    c.visit("p10", 1.0);
    c.visit("main#1", -0.0);
    assert_ne!(encoded(&a), encoded(&c), "-0.0 is not 0.0");
    let mut d = Schedule::new();
    d.visit("main#1", 0.0);
    d.visit("p10", 1.0);
    assert_ne!(encoded(&a), encoded(&d), "first-visit order counts");
}
