//! What a right verdict is, written from issue 46's rules (not from the
//! diagnosis's code):
//!
//! - **Below the detection limit, name nothing.** Where nothing is withheld,
//!   or the withheld effect is below its detection limit (ρ < 1), the right
//!   verdict names no effect and nothing `unexplained`: `none`, or only the
//!   arm's own geometry and the tracker's frame, which every set holds.
//! - **Nothing assumed that the data do not say.** Without temperature
//!   columns no thermal effect may be named: everything thermal the session
//!   did (the arm's own expansion, which the model can only follow with the
//!   temperatures, and a withheld thermal effect) is then a drift in time,
//!   reported as `unexplained` (its signature). The drift has its own
//!   detection limit (`limit::drift_ratio`): below it nothing is flagged;
//!   from it to [`DRIFT_PLAIN`] times it, whether an omnibus test sees
//!   what a test of a known shape would just reveal depends on the shape,
//!   so `unexplained` and nothing are both right; beyond, the drift must be
//!   flagged. A static effect is named beside it as with temperatures.
//! - **Otherwise the withheld effect is named**, alone or as one of two the
//!   data cannot tell apart, beside at most the geometry and the frame, and
//!   nothing `unexplained` (nothing outside the library was withheld).

use super::world::{Class, Form};
use rapidtherm::model::EffectKind;

/// From this many times its detection limit, a drift in time is one no
/// test can miss: its noncentrality is 16 times the limit's, several
/// hundred, where the lack of fit over time of a few hundred rows needs
/// about a hundred.
pub const DRIFT_PLAIN: f64 = 4.0;

/// What the right verdict says of a drift in time nothing in the file
/// explains.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drift {
    /// None, or one below its detection limit: nothing `unexplained`.
    Absent,
    /// Above its limit but not plain: `unexplained` or not, both right.
    Faint,
    /// Plain: `unexplained` required.
    Plain,
}

/// What the right verdict is for a set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Expected {
    /// The effect it names (beside the geometry and the frame), if any.
    pub named: Option<EffectKind>,
    pub drift: Drift,
}

impl Expected {
    /// From the withheld class, the form, the effect's size over its
    /// detection limit (`rho`) and, without temperature columns, the
    /// session's drift in time over its limit (`rho_drift`).
    pub fn of(class: Class, form: Form, rho: f64, rho_drift: f64) -> Expected {
        let drift = match rho_drift {
            _ if form.temps => Drift::Absent,
            r if r < 1.0 => Drift::Absent,
            r if r < DRIFT_PLAIN => Drift::Faint,
            _ => Drift::Plain,
        };
        let named = match class {
            Class::Nothing => None,
            Class::Effect(_) if rho < 1.0 => None,
            Class::Effect(k) if k.is_thermal() && !form.temps => None,
            Class::Effect(k) => Some(k),
        };
        Expected { named, drift }
    }

    pub fn words(self) -> String {
        let named = self.named.map_or("nothing", |k| k.name());
        match self.drift {
            Drift::Absent => named.to_string(),
            Drift::Faint => format!("{named}, a drift flagged or not"),
            Drift::Plain => format!("{named} + drift (unexplained)"),
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
    let named_ok = match expected.named {
        None => named.is_empty(),
        Some(kind) => {
            let truth = kind.name();
            // A label paired (in a tie the data cannot break) with another.
            let partner = |a: &str, b: &str| {
                ambiguous
                    .iter()
                    .any(|p| p.iter().any(|n| n == a) && p.iter().any(|n| n == b))
            };
            let found = named.iter().any(|l| *l == truth || partner(l, truth));
            let only = named.iter().all(|l| *l == truth || partner(l, truth));
            found && only
        }
    };
    let flag_ok = match expected.drift {
        Drift::Absent => !flagged,
        Drift::Faint => true,
        Drift::Plain => flagged,
    };
    named_ok && flag_ok
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
        let nothing = Expected {
            named: None,
            drift: Drift::Absent,
        };
        let named = |k| Expected {
            named: Some(k),
            drift: Drift::Absent,
        };
        // Below the limit: nothing named, nothing flagged.
        assert!(right(nothing, &l(&["none"]), &[]));
        assert!(right(
            nothing,
            &l(&["geometry-offset", "tracker-frame"]),
            &[]
        ));
        assert!(!right(nothing, &l(&["thermal-lag"]), &[]));
        assert!(!right(
            nothing,
            &l(&["geometry-offset", "unexplained"]),
            &[]
        ));
        // Named: the effect, or its tie partner, and nothing else.
        assert!(right(
            named(lag),
            &l(&["thermal-lag", "geometry-offset"]),
            &[]
        ));
        let tie = [["expansion-scale".to_string(), "thermal-lag".to_string()]];
        assert!(right(named(lag), &l(&["expansion-scale"]), &tie));
        assert!(!right(named(lag), &l(&["expansion-scale"]), &[]));
        assert!(!right(named(lag), &l(&["thermal-lag", "gravity-sag"]), &[]));
        assert!(!right(named(lag), &l(&["thermal-lag", "unexplained"]), &[]));
        assert!(!right(named(lag), &l(&["none"]), &[]));
        // Without temperatures: never a thermal effect; the drift flagged
        // where it is plain, and beside a static effect named.
        let plain = Expected {
            named: None,
            drift: Drift::Plain,
        };
        let faint = Expected {
            named: None,
            drift: Drift::Faint,
        };
        assert!(right(plain, &l(&["geometry-offset", "unexplained"]), &[]));
        assert!(!right(plain, &l(&["none"]), &[]));
        assert!(!right(plain, &l(&["thermal-lag", "unexplained"]), &[]));
        assert!(right(faint, &l(&["none"]), &[]));
        assert!(right(faint, &l(&["unexplained"]), &[]));
        assert!(!right(faint, &l(&["joint-offset-drift"]), &[]));
        let sag = Expected {
            named: Some(EffectKind::GravitySag),
            drift: Drift::Plain,
        };
        assert!(right(sag, &l(&["gravity-sag", "unexplained"]), &[]));
        assert!(!right(sag, &l(&["gravity-sag"]), &[]));
        // The class and form decide.
        let form = Form::of_index(0);
        assert!(form.temps);
        let no_temps = Form {
            temps: false,
            ..form
        };
        let lag_class = Class::Effect(lag);
        assert_eq!(Expected::of(lag_class, form, 2.0, 0.0), named(lag));
        assert_eq!(Expected::of(lag_class, form, 0.9, 0.0), nothing);
        assert_eq!(Expected::of(lag_class, no_temps, 2.0, 5.0), plain);
        assert_eq!(Expected::of(lag_class, no_temps, 2.0, 0.5), nothing);
        assert_eq!(Expected::of(Class::Nothing, no_temps, 0.0, 2.0), faint);
    }
}
