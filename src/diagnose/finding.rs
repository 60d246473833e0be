//! What a localisation found, as typed findings, and the one place each is
//! put in words. A sentence about where a gap lies is never written from
//! loose numbers: [`super::locate`] finds, this file words, and a test
//! compares every finding with the numbers of the localisation it came from.

use nalgebra::Vector3;
use serde::{Serialize, Serializer};

/// A principal direction of gaps: a unit vector, and whether its sign is
/// the data's (the gaps' mean runs along it) or only a line's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Principal {
    /// Unit vector; where `signed` is false, turned so that its largest
    /// component is positive.
    pub along: [f64; 3],
    pub signed: bool,
}

impl Principal {
    /// The principal direction `d` of gaps whose mean is `mean` and whose
    /// RMS along `d` is `rms_along`: signed when their mean runs along it
    /// by a fifth of that RMS or more, else the line it is. An
    /// eigenvector's sign is arbitrary, and a sign the data do not give
    /// would flip with the last digit of any input.
    pub fn of(d: &Vector3<f64>, mean: &Vector3<f64>, rms_along: f64) -> Principal {
        let along = d.dot(mean);
        let (v, signed) = if along.abs() >= 0.2 * rms_along && along != 0.0 {
            (d * along.signum(), true)
        } else {
            (d * d[d.iamax()].signum(), false)
        };
        Principal {
            along: [v.x, v.y, v.z],
            signed,
        }
    }

    /// `+y`, `(+0.50, -0.29, -0.82)`, or `±y` for a line.
    pub fn words(&self) -> String {
        let w = direction_words(&Vector3::from(self.along));
        if self.signed {
            w
        } else {
            format!("±{}", w.trim_start_matches('+'))
        }
    }
}

/// A unit direction in words: `+z`, or its components.
pub fn direction_words(d: &Vector3<f64>) -> String {
    let names = ["x", "y", "z"];
    let (i, v) = d.iter().copied().enumerate().fold((0, 0.0), |a, (i, v)| {
        if v.abs() > f64::abs(a.1) {
            (i, v)
        } else {
            a
        }
    });
    if v.abs() > 0.9 {
        format!("{}{}", if v > 0.0 { "+" } else { "-" }, names[i])
    } else {
        format!("({:+.2}, {:+.2}, {:+.2})", d.x, d.y, d.z)
    }
}

fn fmt_min(t: f64) -> String {
    if (t - t.round()).abs() < 1e-6 {
        format!("{t:.0}")
    } else {
        format!("{t:.1}")
    }
}

/// A sudden step in time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Step {
    /// Last measurement time before the step and first after, minutes.
    pub before_min: f64,
    pub after_min: f64,
    pub size_mm: f64,
    pub direction: [f64; 3],
}

/// The joint whose angle a gap follows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointFollow {
    /// 1-based axis.
    pub axis: usize,
    /// Cycles per turn of the axis.
    pub harmonic: usize,
    pub amplitude_mrad: f64,
    /// Share of the gap's mean square this harmonic explains.
    pub share: f64,
}

/// A pose and the RMS of its gap.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseGap {
    pub pose: String,
    pub rms_mm: f64,
    pub n: usize,
}

/// How the workspace is split in two.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Split {
    /// Horizontal distance of the flange from axis 1.
    Reach,
    /// Height of the flange.
    Height,
}

impl Split {
    /// The quantity split, and the names of its lower and upper half.
    pub fn names(self) -> (&'static str, &'static str, &'static str) {
        match self {
            Split::Reach => ("reach", "near reach", "far reach"),
            Split::Height => ("height", "low", "high"),
        }
    }
}

/// How a gap changes over the warm-up, judged on its change since the
/// cold start (each pose's gap less its own in the first time bin), not on
/// the raw gap, so that static error does not read as growth or hide it.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "kebab-case")]
pub enum TimeShape {
    /// The change since the cold start reaches `late_mm` RMS in the last
    /// time bin (minutes `late_min`), above 1.5 times the noise.
    Grows { late_mm: f64, late_min: [f64; 2] },
    /// There at the cold start (`early_mm` RMS in the first bin), and its
    /// change by the last bin (`late_mm`) within 1.5 times the noise.
    FromColdStart {
        early_mm: f64,
        early_min: [f64; 2],
        late_mm: f64,
    },
}

impl TimeShape {
    /// The shape in a sentence. `thermal_named`: the verdict names a
    /// thermal effect, beside which a gap is never called static (a small
    /// change can be significant and still within 1.5 times the noise).
    pub fn words(&self, thermal_named: bool) -> Option<String> {
        match self {
            TimeShape::Grows { late_mm, late_min } => Some(format!(
                "It grows with the warm-up: its change since the cold start is {:.3} mm RMS in minutes {:.0}–{:.0}.",
                late_mm, late_min[0], late_min[1]
            )),
            TimeShape::FromColdStart { .. } if thermal_named => None,
            TimeShape::FromColdStart {
                early_mm,
                early_min,
                late_mm,
            } => Some(format!(
                "It is there from the cold start on: {:.3} mm RMS in minutes {:.0}–{:.0}, and changes by {:.3} mm RMS over the warm-up, within the noise.",
                early_mm, early_min[0], early_min[1], late_mm
            )),
        }
    }
}

/// One thing a localisation found and says. Each is said only where the
/// gap is above 1.5 times the noise and the finding passes its own bar
/// (written beside it in [`super::locate::locate`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    /// The gap's size follows the mean motor temperature rise.
    FollowsTemperature { correlation: f64 },
    /// Most of the gap's mean square lies along one direction.
    Along { direction: Principal, share: f64 },
    /// The poses with the largest gap (at most three).
    LargestAt { poses: Vec<PoseGap> },
    /// One half of the workspace carries a larger gap than the other.
    LargerAt {
        split: Split,
        /// The upper half (far, high) is the larger.
        upper: bool,
        median_mm: f64,
        larger_mm: f64,
        smaller_mm: f64,
    },
    /// The gap follows a harmonic of one joint's angle.
    FollowsJoint(JointFollow),
    /// A sudden step in time.
    Step(Step),
}

impl Finding {
    /// The finding in a sentence.
    pub fn words(&self) -> String {
        match self {
            Finding::FollowsTemperature { correlation } => format!(
                "Its size follows the motor temperature rise (correlation {correlation:.2})."
            ),
            Finding::Along { direction, share } => format!(
                "Mostly along {} ({:.0} % of it).",
                direction.words(),
                share * 100.0
            ),
            Finding::LargestAt { poses } => {
                let list: Vec<String> = poses
                    .iter()
                    .map(|p| format!("{} ({:.3} mm)", p.pose, p.rms_mm))
                    .collect();
                format!("Largest at poses {}.", list.join(", "))
            }
            Finding::LargerAt {
                split,
                upper,
                median_mm,
                larger_mm,
                smaller_mm,
            } => {
                let (what, lower_name, upper_name) = split.names();
                let name = if *upper { upper_name } else { lower_name };
                format!(
                    "Larger at {name} ({what} split at {median_mm:.0} mm): {larger_mm:.3} mm vs {smaller_mm:.3} mm."
                )
            }
            Finding::FollowsJoint(j) => format!(
                "It follows the angle of axis {}: {} cycle(s) per turn, amplitude {:.3} mrad ({:.0} % of it).",
                j.axis,
                j.harmonic,
                j.amplitude_mrad,
                j.share * 100.0
            ),
            Finding::Step(s) => format!(
                "A step of {:.3} mm along {} between minute {} and {}.",
                s.size_mm,
                direction_words(&Vector3::from(s.direction)),
                fmt_min(s.before_min),
                fmt_min(s.after_min)
            ),
        }
    }
}

/// Serialise findings as their sentences (the JSON field `where.words`).
pub fn serialize_words<S: Serializer>(findings: &[Finding], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(findings.iter().map(Finding::words))
}

impl Split {
    /// The names of the lower and upper half in a chain calibration's
    /// remainder (`near`, `far`; `low`, `high`).
    pub fn short_names(self) -> (&'static str, &'static str) {
        match self {
            Split::Reach => ("near", "far"),
            Split::Height => ("low", "high"),
        }
    }
}

/// One thing the remainder of a chain calibration shows
/// ([`super::chain_residual`]): every share is the part of its mean square
/// a small least-squares model explains.
#[derive(Debug, Clone, PartialEq)]
pub enum RemainderFinding {
    /// RMS per base axis, and the principal direction with its share.
    Axes {
        axis_rms_mm: [f64; 3],
        direction: Principal,
        share: f64,
    },
    /// The rows with the largest gap (pose label, mm; at most three).
    LargestAt { poses: Vec<(String, f64)> },
    /// The RMS of the two halves of the workspace split at the median.
    ByRegion {
        split: Split,
        median_mm: f64,
        lower_mm: f64,
        upper_mm: f64,
    },
    /// The joint whose angle (one and two cycles per turn) explains most.
    Joint { axis: usize, share: f64 },
    /// A smooth trend over the measurement order.
    Order { share: f64 },
}

impl RemainderFinding {
    /// The finding in a sentence.
    pub fn words(&self) -> String {
        match self {
            RemainderFinding::Axes {
                axis_rms_mm,
                direction,
                share,
            } => format!(
                "Per base axis x, y, z: {:.3}, {:.3}, {:.3} mm RMS; the largest direction, {}, carries {:.0} % of it{}.",
                axis_rms_mm[0],
                axis_rms_mm[1],
                axis_rms_mm[2],
                direction.words(),
                100.0 * share,
                if *share < 0.5 {
                    " (no single direction)"
                } else {
                    ""
                }
            ),
            RemainderFinding::LargestAt { poses } => {
                let list: Vec<String> = poses
                    .iter()
                    .map(|(pose, mm)| format!("{pose} ({mm:.3} mm)"))
                    .collect();
                format!("Largest at poses {}.", list.join(", "))
            }
            RemainderFinding::ByRegion {
                split,
                median_mm,
                lower_mm,
                upper_mm,
            } => {
                let (what, ..) = split.names();
                let (lo, hi) = split.short_names();
                format!(
                    "By {what} (split at {median_mm:.0} mm): {lower_mm:.3} mm {lo}, {upper_mm:.3} mm {hi}."
                )
            }
            RemainderFinding::Joint { axis, share } => format!(
                "The angle of axis {axis} (one and two cycles per turn) explains {:.0} % of it{}.",
                100.0 * share,
                if *share < 0.2 {
                    "; no joint dominates"
                } else {
                    ""
                }
            ),
            RemainderFinding::Order { share } => format!(
                "A smooth trend over the measurement order explains {:.0} % of it{}.",
                100.0 * share,
                if *share < 0.1 { ": nothing drifts" } else { "" }
            ),
        }
    }
}

/// Serialise a remainder's findings as their sentences (the JSON field
/// `words` of a chain calibration's remainder).
pub fn serialize_remainder_words<S: Serializer>(
    findings: &[RemainderFinding],
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_seq(findings.iter().map(RemainderFinding::words))
}
