//! What a right verdict is, written from issue 46's rules (not from the
//! diagnosis's code):
//!
//! - **Below the detection limit, name nothing.** Where nothing is withheld,
//!   or the withheld effect is below its detection limit (ρ < 1), the right
//!   verdict names no effect and nothing `unexplained`: `none`, or only the
//!   arm's own geometry and the tracker's frame, which every set holds.
//! - **Nothing assumed that the data do not say.** Without temperature
//!   columns no thermal effect may be named: a thermal effect of the
//!   session is then a drift in time, reported as `unexplained` (its
//!   signature). Whether an omnibus test sees a drift that a test of the
//!   effect's own shape would just reveal depends on its size, so from the
//!   limit to [`DRIFT_PLAIN`] times it `unexplained` and nothing are both
//!   right; beyond, the drift must be flagged.
//! - **Otherwise the withheld effect is named**, alone or as one of two the
//!   data cannot tell apart, beside at most the geometry and the frame, and
//!   nothing `unexplained` (nothing outside the library was withheld).

use super::world::{Class, Form};
use rapidtherm::model::EffectKind;

/// From this many times its detection limit, a thermal effect without
/// temperature columns is a drift no test can miss: its noncentrality is
/// 16 times the limit's, several hundred, where the lack of fit over time
/// of a few hundred rows needs about a hundred.
pub const DRIFT_PLAIN: f64 = 4.0;

/// What the right verdict is for a set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Expected {
    /// No effect named, nothing unexplained.
    Nothing,
    /// The withheld effect named, nothing unexplained.
    Named(EffectKind),
    /// No effect named; `unexplained` right, and required when `plain`.
    Drift { plain: bool },
}

impl Expected {
    pub fn of(class: Class, form: Form, rho: f64) -> Expected {
        match class {
            Class::Nothing => Expected::Nothing,
            Class::Effect(_) if rho < 1.0 => Expected::Nothing,
            Class::Effect(k) if k.is_thermal() && !form.temps => Expected::Drift {
                plain: rho >= DRIFT_PLAIN,
            },
            Class::Effect(k) => Expected::Named(k),
        }
    }

    pub fn words(self) -> String {
        match self {
            Expected::Nothing => "nothing".into(),
            Expected::Named(k) => k.name().into(),
            Expected::Drift { plain: true } => "drift (unexplained)".into(),
            Expected::Drift { plain: false } => "drift or nothing".into(),
        }
    }
}

/// Effects every set holds as nuisance: naming them is never wrong.
const NUISANCE: [&str; 2] = ["geometry-offset", "tracker-frame"];

/// Whether `labels` (the verdict's) with the pairs the data cannot tell
/// apart (`ambiguous`) are the right verdict.
pub fn right(expected: Expected, labels: &[String], ambiguous: &[[String; 2]]) -> bool {
    let named: Vec<&str> = labels
        .iter()
        .map(String::as_str)
        .filter(|l| *l != "none" && *l != "unexplained" && !NUISANCE.contains(l))
        .collect();
    let flagged = labels.iter().any(|l| l == "unexplained");
    match expected {
        Expected::Nothing => named.is_empty() && !flagged,
        Expected::Drift { plain } => named.is_empty() && (flagged || !plain),
        Expected::Named(kind) => {
            let truth = kind.name();
            // A label paired (in a tie the data cannot break) with another.
            let partner = |a: &str, b: &str| {
                ambiguous
                    .iter()
                    .any(|p| p.iter().any(|n| n == a) && p.iter().any(|n| n == b))
            };
            let found = named.iter().any(|l| *l == truth || partner(l, truth));
            let only = named.iter().all(|l| *l == truth || partner(l, truth));
            found && only && !flagged
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn l(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_rules_of_the_issue() {
        let lag = EffectKind::ThermalLag;
        // Below the limit: nothing named, nothing flagged.
        assert!(right(Expected::Nothing, &l(&["none"]), &[]));
        assert!(right(
            Expected::Nothing,
            &l(&["geometry-offset", "tracker-frame"]),
            &[]
        ));
        assert!(!right(Expected::Nothing, &l(&["thermal-lag"]), &[]));
        assert!(!right(
            Expected::Nothing,
            &l(&["geometry-offset", "unexplained"]),
            &[]
        ));
        // Named: the effect, or its tie partner, and nothing else.
        assert!(right(
            Expected::Named(lag),
            &l(&["thermal-lag", "geometry-offset"]),
            &[]
        ));
        let tie = [["expansion-scale".to_string(), "thermal-lag".to_string()]];
        assert!(right(Expected::Named(lag), &l(&["expansion-scale"]), &tie));
        assert!(!right(Expected::Named(lag), &l(&["expansion-scale"]), &[]));
        assert!(!right(
            Expected::Named(lag),
            &l(&["thermal-lag", "gravity-sag"]),
            &[]
        ));
        assert!(!right(
            Expected::Named(lag),
            &l(&["thermal-lag", "unexplained"]),
            &[]
        ));
        assert!(!right(Expected::Named(lag), &l(&["none"]), &[]));
        // Without temperatures: never a thermal effect; the drift flagged
        // where it is plain.
        let plain = Expected::Drift { plain: true };
        let faint = Expected::Drift { plain: false };
        assert!(right(plain, &l(&["geometry-offset", "unexplained"]), &[]));
        assert!(!right(plain, &l(&["none"]), &[]));
        assert!(!right(plain, &l(&["thermal-lag", "unexplained"]), &[]));
        assert!(right(faint, &l(&["none"]), &[]));
        assert!(right(faint, &l(&["unexplained"]), &[]));
        assert!(!right(faint, &l(&["joint-offset-drift"]), &[]));
    }
}
