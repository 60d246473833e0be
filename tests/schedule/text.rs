//! A corrected file's marker records its schedule by a fingerprint of the
//! schedule's `Debug` text: that text must stay what it was when the
//! visits were kept in a sorted map, or files corrected before would read
//! as corrected for another schedule.

use proptest::prelude::*;
use rapidtherm::schedule::Schedule;
use std::collections::BTreeMap;

/// The text as the sorted map wrote it (`pretty`: with `{:#?}`).
fn as_the_sorted_map_in(visits: &[(String, f64)], pretty: bool) -> String {
    #[derive(Debug)]
    struct Schedule {
        #[allow(dead_code)] // read by Debug
        visits: BTreeMap<String, Vec<f64>>,
        #[allow(dead_code)]
        order: Vec<String>,
    }
    let mut s = Schedule {
        visits: BTreeMap::new(),
        order: Vec::new(),
    };
    for (id, t) in visits {
        let key = id.to_ascii_lowercase();
        if !s.visits.contains_key(&key) {
            s.order.push(id.clone());
        }
        s.visits.entry(key).or_default().push(*t);
    }
    if pretty {
        format!("{s:#?}")
    } else {
        format!("{s:?}")
    }
}

fn as_the_sorted_map(visits: &[(String, f64)]) -> String {
    as_the_sorted_map_in(visits, false)
}

/// Identifiers as programs have them: long shared prefixes (past 16
/// bytes too), one a prefix of another, case mixed, digits, `#` and `:`.
fn id() -> impl Strategy<Value = String> {
    let stems = prop::sample::select(vec![
        "main#",
        "M1:main#",
        "p",
        "pApproach",
        "a_very_long_module:a_long_routine#",
        "a_very_long_module:a_long_routinE#",
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
    fn the_text_is_the_sorted_maps(
        visits in prop::collection::vec((id(), -1.0e5..1.0e17f64), 0..200),
    ) {
        let mut s = Schedule::new();
        for (id, t) in &visits {
            s.visit(id, *t);
        }
        prop_assert_eq!(format!("{s:?}"), as_the_sorted_map(&visits));
        // Written by hand for speed, the plain text; pretty, as ever.
        prop_assert_eq!(format!("{s:#?}"), as_the_sorted_map_in(&visits, true));
    }
}

#[test]
fn tiny_huge_and_negative_times_are_written_as_debug_writes_them() {
    let visits: Vec<(String, f64)> = [0.0, -0.0, 1e-7, 1.5e-5, 1e16, 3.0, -2.5, 0.1 + 0.2]
        .iter()
        .enumerate()
        .map(|(i, &t)| (format!("main#{i}"), t))
        .collect();
    let mut s = Schedule::new();
    for (id, t) in &visits {
        s.visit(id, *t);
    }
    assert_eq!(format!("{s:?}"), as_the_sorted_map(&visits));
}
