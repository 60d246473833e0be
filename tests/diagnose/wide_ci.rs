//! The widened evaluation (`wide/`) at the size of every `cargo test`: one
//! seeded set per class on small forms, its rate asserted, so that a rule
//! that names what the data cannot say fails here and not only in the full
//! run (`cargo run --release --example diagnose_eval -- --sets 100`).

use super::wide::run::{evaluate, specs};
use super::wide::world::Class;

/// Every class once (seeds 46_500 + 1000·c; forms of the arms, with and
/// without temperatures, repeats, clock and frame, as `specs` spreads
/// them): at least RATE right.
#[test]
fn widened_evaluation_seeded() {
    let out = evaluate(&specs(1, 46_500, &Class::ALL), |_| {});
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

/// The rate the seeded sets must reach, per cent. On the code before issue
/// 46's rules (a5c04d6) 3 of 7 were right: a thermal-lag named without
/// temperature columns, an arm-bending named below its detection limit and
/// without temperatures, a mount drift below its limit named arm-bending
/// and `unexplained`. The floor is that baseline, so that the test can
/// fail; it is to be raised to the acceptance's 95 % (7 of 7) with the
/// rules that make it so.
const RATE: usize = 40;
