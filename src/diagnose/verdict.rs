//! The result of a diagnosis as data: the verdict, the scores behind it and
//! what to do about it. No sentences here: [`super::prose`] words them,
//! and a caller may word them its own way.

use super::detect::{BelowLimit, DetectionLimit};
use super::drift::TimeDrift;
use super::gap::{GapStats, Noise};
use super::joint_signature::{JointLimit, JointSignature};
use super::locate::Where;
use super::prepare::Registration;
use super::separation::Separation;
use super::signature::QuadraticGrowth;
use super::stability::Stability;
use super::stats::Test;
use super::temps::TempSource;
use crate::model::{EffectEntry, EffectKind};
use nalgebra::Vector3;
use serde::{Serialize, Serializer};

/// What the diagnosis concludes.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Nothing to explain: the gap is at the measurement noise, or shows no
    /// structure above an assumed (not measured) noise level.
    None,
    /// The effects (in the order selected) explain the gap; with
    /// `remainder`, clear structure is left that they do not explain.
    ExplainedBy {
        effects: Vec<EffectKind>,
        remainder: bool,
    },
    /// As [`Verdict::ExplainedBy`], but the data hardly tell a selected
    /// effect from another one ([`Diagnosis::ambiguities`] says which and
    /// how to separate them).
    Ambiguous {
        effects: Vec<EffectKind>,
        remainder: bool,
    },
    /// No effect of the library explains the gap; `partial` explain only
    /// part of it.
    Unexplained { partial: Vec<EffectKind> },
}

impl Verdict {
    /// The verdict as labels: the effects' names, `unexplained` when
    /// something is left unexplained, or `none`.
    pub fn labels(&self) -> Vec<String> {
        match self {
            Verdict::None => vec!["none".into()],
            Verdict::ExplainedBy { effects, remainder }
            | Verdict::Ambiguous { effects, remainder } => {
                let mut v: Vec<String> = effects.iter().map(|k| k.name().to_string()).collect();
                if *remainder {
                    v.push("unexplained".into());
                }
                v
            }
            Verdict::Unexplained { .. } => vec!["unexplained".into()],
        }
    }

    /// The effects the verdict names (none for `none` and `unexplained`).
    pub fn effects(&self) -> &[EffectKind] {
        match self {
            Verdict::ExplainedBy { effects, .. } | Verdict::Ambiguous { effects, .. } => effects,
            Verdict::None | Verdict::Unexplained { .. } => &[],
        }
    }
}

impl Serialize for Verdict {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.labels().serialize(s)
    }
}

/// Which stage of a diagnosis scored an effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScoredIn {
    /// Each pose's own offset fitted, held out by time span.
    OverTime,
    /// Thermal effects on top of the static ones found, held out by pose
    /// and time, where that saw more than the first stage.
    Absolute,
    /// The thermal effects found held fixed, held out by pose and time.
    Static,
    /// One stage over every effect.
    All,
}

impl ScoredIn {
    /// The name in reports and JSON.
    pub fn name(self) -> &'static str {
        match self {
            ScoredIn::OverTime => "over-time",
            ScoredIn::Absolute => "absolute",
            ScoredIn::Static => "static",
            ScoredIn::All => "all",
        }
    }
}

/// One stage of a diagnosis and its held-out gap.
#[derive(Debug, Clone, Serialize)]
pub struct StageSummary {
    pub part: ScoredIn,
    pub gap_before_mm: f64,
    pub gap_after_mm: f64,
    pub effects: Vec<String>,
    /// Whether the poses give more numbers than a full kinematic
    /// calibration takes up (for the static part; the time variation is
    /// always judged): else the arm's own geometry cannot be told from
    /// other static causes.
    pub judged: bool,
    /// The test of what the stage leaves against the noise (`null` where
    /// no degrees of freedom are left to judge it).
    pub lack_of_fit: Option<Test>,
}

/// What to do about the gap.
#[derive(Debug, Clone, PartialEq)]
pub enum Advice {
    /// The model is as good as the measurement: what is left passed the
    /// lack-of-fit test against a measured or given noise.
    Nothing,
    /// No effect is significant against what is left (`left_mm`, 3-D RMS
    /// held out), but the noise was not measured (no repeated poses) nor
    /// given: whether that is noise cannot be said. Repeat poses, or give
    /// the instrument's noise level.
    NoiseNotMeasured { left_mm: f64 },
    /// Save the model with the diagnosed effects and correct programs with
    /// it: the held-out gap goes from `from_mm` to `to_mm`.
    SaveModel { from_mm: f64, to_mm: f64 },
    /// Look where the gap points (an axis, a step between two minutes) and
    /// measure more poses and times there before trusting a correction.
    LookThere {
        axis: Option<usize>,
        step_min: Option<(f64, f64)>,
    },
}

#[derive(Debug, Clone, Serialize)]
pub struct ParamOut {
    pub name: String,
    pub unit: String,
    pub value: f64,
    /// `null` when the data cannot identify it (held at zero).
    pub stderr: Option<f64>,
    /// Why the data cannot identify it, where they cannot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held: Option<super::unidentified::Unidentified>,
}

#[derive(Debug, Clone, Serialize)]
pub struct CandidateOut {
    pub name: String,
    /// The stage that scored it ([`StageSummary::part`]).
    pub part: ScoredIn,
    /// Share of the held-out mean-square gap above the noise that this
    /// effect alone removes.
    pub explained: f64,
    pub cv_rms_mm: f64,
    pub bic: Option<f64>,
    /// Its F test against the stage's model without it.
    pub test: Option<Test>,
    pub params: Vec<ParamOut>,
    pub selected: bool,
    pub error: Option<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct StepOut {
    pub added: String,
    /// The stage that added it ([`StageSummary::part`]).
    pub part: ScoredIn,
    pub gap_before_mm: f64,
    pub gap_after_mm: f64,
    pub drop_pct: f64,
    pub runner_up: Option<String>,
    /// The F test that added it.
    pub test: Option<Test>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Ambiguity {
    pub pair: [String; 2],
    /// Cosine of the two effects' contributions where they were scored
    /// one against the other; `None` where the tie showed only in the
    /// whole set (either in it scores alike).
    pub correlation: Option<f64>,
    pub separate_by: Separation,
}

/// Why an effect the selection took is not named in the verdict.
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "reason", rename_all = "kebab-case")]
pub enum NotNamedWhy {
    /// None of its parameters is pinned by the data (each held as not
    /// identifiable, or on a bound of its range).
    Unpinned,
    /// It fits, but below what these poses, times and noise could reveal.
    BelowLimit { size_mm: f64, limit_mm: f64 },
    /// Named in fewer than 80 % of the resampled fits: a candidate.
    Unstable { named_in: usize, resamples: usize },
}

/// An effect the selection took that the verdict does not name (JSON
/// `not_named`), and why.
#[derive(Debug, Clone, Serialize)]
pub struct NotNamed {
    pub effect: EffectKind,
    #[serde(flatten)]
    pub why: NotNamedWhy,
}

impl NotNamed {
    /// Of a selection's `below` limits, `stability` and `unpinned` effects,
    /// the effects not named, once each (the first reason found: unpinned,
    /// below the limit, unstable).
    pub fn of(
        unpinned: &[EffectKind],
        below: &[BelowLimit],
        stability: &[Stability],
    ) -> Vec<NotNamed> {
        let mut out: Vec<NotNamed> = unpinned
            .iter()
            .map(|&effect| NotNamed {
                effect,
                why: NotNamedWhy::Unpinned,
            })
            .collect();
        for b in below {
            if !out.iter().any(|n| n.effect == b.effect) {
                out.push(NotNamed {
                    effect: b.effect,
                    why: NotNamedWhy::BelowLimit {
                        size_mm: b.size_mm,
                        limit_mm: b.limit_mm,
                    },
                });
            }
        }
        for st in stability.iter().filter(|st| !st.stable()) {
            if !out.iter().any(|n| n.effect == st.effect) {
                out.push(NotNamed {
                    effect: st.effect,
                    why: NotNamedWhy::Unstable {
                        named_in: st.named_in,
                        resamples: st.resamples,
                    },
                });
            }
        }
        out
    }
}

impl Verdict {
    /// The verdict without the effects `out`: where none is left, `none`,
    /// or `unexplained` where something was left unexplained beside them.
    pub fn without(self, out: &[EffectKind]) -> Verdict {
        let keep = |e: Vec<EffectKind>| -> Vec<EffectKind> {
            e.into_iter().filter(|k| !out.contains(k)).collect()
        };
        match self {
            Verdict::ExplainedBy { effects, remainder } => {
                let effects = keep(effects);
                match (effects.is_empty(), remainder) {
                    (true, false) => Verdict::None,
                    (true, true) => Verdict::Unexplained {
                        partial: Vec::new(),
                    },
                    (false, _) => Verdict::ExplainedBy { effects, remainder },
                }
            }
            Verdict::Ambiguous { effects, remainder } => {
                let effects = keep(effects);
                match (effects.is_empty(), remainder) {
                    (true, false) => Verdict::None,
                    (true, true) => Verdict::Unexplained {
                        partial: Vec::new(),
                    },
                    (false, _) => Verdict::Ambiguous { effects, remainder },
                }
            }
            Verdict::Unexplained { partial } => Verdict::Unexplained {
                partial: keep(partial),
            },
            Verdict::None => Verdict::None,
        }
    }
}

/// The whole diagnosis.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnosis {
    /// Serialised as its labels ([`Verdict::labels`]).
    pub verdict: Verdict,
    /// Held-out RMS gap of the current model, mm.
    pub gap_before_mm: f64,
    /// Held-out RMS gap of the saved model, mm (its effects fitted
    /// without the rows scored).
    pub gap_after_mm: f64,
    pub gap: GapStats,
    /// The saved model's gap on every row.
    pub gap_after: GapStats,
    pub noise: Noise,
    /// The level of each stage's family of tests.
    pub level: f64,
    pub candidates: Vec<CandidateOut>,
    pub steps: Vec<StepOut>,
    /// Pairs of effects the data cannot tell apart.
    pub ambiguous: Vec<[String; 2]>,
    pub ambiguities: Vec<Ambiguity>,
    /// Effects that explain part of a gap that stays unexplained.
    pub partial: Vec<String>,
    /// Where the gap of the current model lies.
    #[serde(rename = "where")]
    pub where_: Where,
    /// Where what is left after the selected effects lies.
    pub where_after: Where,
    /// What is left unexplained changes over time (located with each
    /// pose's own offset taken out), rather than from pose to pose.
    pub left_over_time: bool,
    /// A growth with the square of the link temperatures over time, which
    /// no effect of the library has.
    pub quadratic_growth: Option<QuadraticGrowth>,
    /// A joint's own error beyond the static calibration (a cyclic error
    /// of its angle, backlash), which no effect of the library has.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub joint_signature: Option<JointSignature>,
    /// Where the static stage is judged, the detection limit of every
    /// joint signature tried (a missed cyclic error or backlash below it
    /// was within what the data could show).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub joint_limits: Vec<JointLimit>,
    /// For every effect of the library, the smallest size these poses,
    /// times and noise would have revealed.
    pub detection_limits: Vec<DetectionLimit>,
    pub registration: Option<Registration>,
    /// Which source drove the temperatures (the data's columns, a heating
    /// record, a cold start the caller assumed, or none).
    pub temperatures: TempSource,
    /// Where no temperatures drive anything: a drift in time that the
    /// model leaves, with its shape and size (reported as `unexplained`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_drift: Option<TimeDrift>,
    /// For every effect a stage selected, how often it is named again over
    /// resampled fits.
    pub stability: Vec<Stability>,
    /// Effects the selection took that the verdict does not name, and why.
    pub not_named: Vec<NotNamed>,
    /// The stages of the diagnosis: with poses measured again and again,
    /// first what changes with time, then what stays; else one.
    pub stages: Vec<StageSummary>,
    /// What to do about it.
    #[serde(skip)]
    pub advice: Advice,
    /// The selected effects with their fitted parameters.
    #[serde(skip)]
    pub fitted: Vec<EffectEntry>,
    #[serde(skip)]
    pub gaps_before: Vec<Vector3<f64>>,
    #[serde(skip)]
    pub gaps_after: Vec<Vector3<f64>>,
    /// The model to save and the gaps measured on it (every "after" above
    /// is its), where the diagnosis was of measurements.
    #[serde(skip)]
    pub saved: Option<super::saved::Saved>,
}
