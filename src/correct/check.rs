//! What fails a check of a program against its correction (`correct
//! --check`): a target that would move more than the tolerance, one left
//! cold for a reason not accepted, a use with other frames landing too
//! far off. One rule for every report of it (list, CI formats), so that
//! they never disagree.

use super::outcome::{Correction, LeftAlone, Outcome, Reason, SharedUse};
use serde::Serialize;

/// The tolerance and the accepted reasons of a check.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckRule {
    /// Largest correction (mm) that counts as no change.
    pub tolerance: f64,
    /// Reasons a target may be left alone for without failing.
    pub accepted: Vec<Reason>,
}

/// The largest tolerance (mm) a check takes: beyond it, no thermal
/// correction is told from a target re-taught (`data/gate.toml`, with its
/// reasons; the diff gate reads the same bound).
pub fn max_tolerance_mm() -> f64 {
    #[derive(serde::Deserialize)]
    struct Limits {
        max_mm: f64,
    }
    // Embedded and pinned by a test: it parses.
    toml::from_str::<Limits>(include_str!("../../data/gate.toml")).map_or(10.0, |l| l.max_mm)
}

impl CheckRule {
    /// A rule of `tolerance` mm: finite, from 0 to [`max_tolerance_mm`]
    /// (`--tolerance 1e308` let every check pass), else a usage error.
    pub fn new(tolerance: f64, accepted: Vec<Reason>) -> crate::error::Result<CheckRule> {
        let most = max_tolerance_mm();
        if !(tolerance.is_finite() && (0.0..=most).contains(&tolerance)) {
            return Err(crate::error::Error::usage(format!(
                "--tolerance {}: a length from 0 to {most} mm (a thermal correction is tenths of a mm; beyond {most} mm a re-taught target would pass as one)",
                if tolerance.abs() >= 1e6 { format!("{tolerance:e}") } else { tolerance.to_string() }
            )));
        }
        Ok(CheckRule {
            tolerance,
            accepted,
        })
    }

    /// The correction is larger than the tolerance: the program would
    /// change.
    pub fn moves(&self, c: &Correction) -> bool {
        c.correction_norm_mm > self.tolerance
    }

    /// Left as written, cold on the warm robot, for a reason not accepted.
    pub fn left_cold(&self, l: &LeftAlone) -> bool {
        l.reason.leaves_target_cold() && !self.accepted.contains(&l.reason)
    }

    /// A use with other frames landing farther off than the tolerance (a
    /// correction that small passes too), or where only the run time
    /// knows; unless shared frames are accepted.
    pub fn lands_off(&self, u: &SharedUse) -> bool {
        u.residual_mm.is_none_or(|r| r > self.tolerance)
            && !self.accepted.contains(&Reason::SharedFrames)
    }

    /// What fails the check in `outcome`: the targets that move, then
    /// those left cold, then the uses landing off.
    pub fn findings<'o>(&self, outcome: &'o Outcome) -> Vec<CheckFinding<'o>> {
        let moves = outcome
            .corrections
            .iter()
            .filter(|c| self.moves(c))
            .map(CheckFinding::Moves);
        let cold = outcome
            .left_alone
            .iter()
            .filter(|l| self.left_cold(l))
            .map(CheckFinding::LeftAlone);
        let off = outcome
            .shared
            .iter()
            .filter(|u| self.lands_off(u))
            .map(CheckFinding::OtherUse);
        moves.chain(cold).chain(off).collect()
    }
}

/// One thing a check found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CheckFinding<'o> {
    /// A target that would move more than the tolerance.
    Moves(&'o Correction),
    /// A target left cold for a reason not accepted.
    LeftAlone(&'o LeftAlone),
    /// A use with another tool or work object than its target is
    /// corrected for, landing off.
    OtherUse(&'o SharedUse),
}

/// A finding's status, as reports name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FindingStatus {
    Moves,
    LeftAlone,
    OtherUse,
}

impl FindingStatus {
    /// The status's name in reports.
    pub fn code(self) -> &'static str {
        match self {
            FindingStatus::Moves => "moves",
            FindingStatus::LeftAlone => "left-alone",
            FindingStatus::OtherUse => "other-use",
        }
    }
}

impl CheckFinding<'_> {
    pub fn status(&self) -> FindingStatus {
        match self {
            CheckFinding::Moves(_) => FindingStatus::Moves,
            CheckFinding::LeftAlone(_) => FindingStatus::LeftAlone,
            CheckFinding::OtherUse(_) => FindingStatus::OtherUse,
        }
    }

    /// The reason it is reported for (none for a target that moves).
    pub fn reason(&self) -> Option<Reason> {
        match self {
            CheckFinding::Moves(_) => None,
            CheckFinding::LeftAlone(l) => Some(l.reason),
            CheckFinding::OtherUse(_) => Some(Reason::SharedFrames),
        }
    }
}

/// How many findings of each status `findings` holds: (moves, left
/// alone, other uses).
pub fn counts(findings: &[CheckFinding]) -> (usize, usize, usize) {
    let of = |s| findings.iter().filter(|f| f.status() == s).count();
    (
        of(FindingStatus::Moves),
        of(FindingStatus::LeftAlone),
        of(FindingStatus::OtherUse),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    // Before, any finite tolerance was taken: 1e308 passed every check.
    #[test]
    fn a_tolerance_is_bounded() {
        assert_eq!(max_tolerance_mm(), 10.0);
        for ok in [0.0, 0.001, 10.0] {
            assert!(CheckRule::new(ok, Vec::new()).is_ok(), "{ok}");
        }
        for bad in [-0.001, 10.5, 1e308, f64::INFINITY, f64::NAN] {
            assert!(CheckRule::new(bad, Vec::new()).is_err(), "{bad}");
        }
    }
}
