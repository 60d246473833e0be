//! What fails `correct --check`: one rule for its list (table, CSV, JSON)
//! and its CI reports (`ci_report`), so that the two never disagree.

use rapidtherm::correct::{Correction, LeftAlone, Reason, SharedUse};

/// `--tolerance` and `--accept` of a check.
pub struct CheckRule<'a> {
    pub tolerance: f64,
    pub accepted: &'a [Reason],
}

impl CheckRule<'_> {
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
}
