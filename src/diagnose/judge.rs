//! From the stages' tests to the verdict and the advice: a stage's verdict
//! by its lack-of-fit test against the noise, the stages' verdicts made
//! one, and what the user is advised to do.

use super::gap::Noise;
use super::locate::Where;
use super::stats::Test;
use super::verdict::{Advice, Verdict};
use crate::model::EffectKind;

/// One verdict from the stages': every effect named, in stage order; an
/// unexplained remainder anywhere is one.
pub(super) fn combine(verdicts: Vec<Verdict>) -> Verdict {
    let mut effects = Vec::new();
    let mut partial = Vec::new();
    let mut remainder = false;
    let mut unexplained = false;
    let mut ambiguous = false;
    for v in verdicts {
        match v {
            Verdict::None => {}
            Verdict::ExplainedBy {
                effects: e,
                remainder: r,
            } => {
                effects.extend(e);
                remainder |= r;
            }
            Verdict::Ambiguous {
                effects: e,
                remainder: r,
            } => {
                effects.extend(e);
                remainder |= r;
                ambiguous = true;
            }
            Verdict::Unexplained { partial: p } => {
                partial.extend(p);
                unexplained = true;
            }
        }
    }
    if unexplained && effects.is_empty() {
        Verdict::Unexplained { partial }
    } else if effects.is_empty() {
        Verdict::None
    } else {
        effects.extend(partial);
        let remainder = remainder || unexplained;
        if ambiguous {
            Verdict::Ambiguous { effects, remainder }
        } else {
            Verdict::ExplainedBy { effects, remainder }
        }
    }
}

/// What the verdict is judged on.
pub(super) struct Scores<'a> {
    /// Effects forward selection added, in order.
    pub(super) selected: &'a [EffectKind],
    /// The test of what the selected effects leave against the noise;
    /// `None` where no degrees of freedom are left to judge it.
    pub(super) lack_of_fit: Option<Test>,
    /// A selected effect has a runner-up the data cannot tell from it.
    pub(super) ambiguous: bool,
}

/// The verdict of one stage. `none` only where what is left is within the
/// noise by the lack-of-fit test at the stated level (the residual sum of
/// squares over its degrees of freedom against the noise variance, an F
/// test); above it `unexplained`, beside the effects named, whatever
/// shape it has. Where no lack-of-fit test could be made (the noise not
/// measured nor given, or no degrees of freedom left) nothing is called
/// unexplained by it, and the advice says what is left was not judged
/// ([`Advice::NoiseNotMeasured`]).
pub(super) fn judge(s: &Scores) -> Verdict {
    let above = s.lack_of_fit.is_some_and(|t| t.significant());
    if s.selected.is_empty() {
        if above {
            Verdict::Unexplained {
                partial: Vec::new(),
            }
        } else {
            Verdict::None
        }
    } else {
        let effects = s.selected.to_vec();
        if s.ambiguous {
            Verdict::Ambiguous {
                effects,
                remainder: above,
            }
        } else {
            Verdict::ExplainedBy {
                effects,
                remainder: above,
            }
        }
    }
}

/// What the user is advised to do. `signature_axis`: the axis of a joint
/// signature tested beyond a full calibration, which the advice names
/// before the axis a localisation of the raw gap follows (one joint's
/// error, one axis in the report).
pub(super) fn advise(
    verdict: &Verdict,
    cv0: f64,
    cv: f64,
    noise: &Noise,
    wheres: [&Where; 2],
    signature_axis: Option<usize>,
) -> Advice {
    match verdict {
        // `none` where the noise was not measured: nothing significant
        // against what is left, which is not shown to be noise.
        Verdict::None if !noise.measured() => Advice::NoiseNotMeasured { left_mm: cv },
        Verdict::None => Advice::Nothing,
        Verdict::Unexplained { .. } => Advice::LookThere {
            axis: signature_axis
                .or_else(|| wheres.iter().find_map(|w| w.joint.as_ref()).map(|j| j.axis)),
            step_min: wheres
                .iter()
                .find_map(|w| w.step.as_ref())
                .map(|s| (s.before_min, s.after_min)),
        },
        Verdict::ExplainedBy { .. } | Verdict::Ambiguous { .. } => Advice::SaveModel {
            from_mm: cv0,
            to_mm: cv,
        },
    }
}

/// `verdict` with a remainder the library does not explain.
pub(super) fn with_remainder(verdict: Verdict) -> Verdict {
    match verdict {
        Verdict::ExplainedBy { effects, .. } => Verdict::ExplainedBy {
            effects,
            remainder: true,
        },
        Verdict::Ambiguous { effects, .. } => Verdict::Ambiguous {
            effects,
            remainder: true,
        },
        _ => Verdict::Unexplained {
            partial: Vec::new(),
        },
    }
}
