//! How a run corrects: when the targets are reached, which visit counts,
//! what may be rewritten, the model's label for the marker, where the
//! robot stands.

use crate::digest::Encoder;
use crate::model::Moment;
use crate::schedule::{Schedule, Visit, SCHEDULE_ENCODING};

/// When the targets are reached.
#[derive(Debug, Clone, PartialEq)]
pub enum When {
    /// Every target at one moment.
    At(Moment),
    /// Times per target (the user's file or an estimate); `default` for
    /// targets the schedule does not list (absent: an error).
    Schedule {
        schedule: Schedule,
        /// Times of jointtargets when kept apart (an estimate keeps them in
        /// their own name space); `None`: looked up in `schedule`.
        joints: Option<Schedule>,
        default: Option<Moment>,
        /// The schedules were made by walking the program being
        /// corrected (the estimate of `--start`): they name only its
        /// targets, and are not checked against them again (a check of a
        /// million names, a tenth of such a run). A schedule file is.
        of_program: bool,
    },
}

/// How one run corrects.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub when: When,
    /// Which visit a target reached several times is corrected for.
    pub visit: Visit,
    /// Write numbers in place of a robtarget literal written with named
    /// constants or expressions (otherwise it is left alone and reported).
    pub expand_expressions: bool,
    /// The model and arm, as the marker of a corrected file names them.
    pub model_label: String,
    /// Where the robot's base stands in the world (MultiMove, a pedestal):
    /// targets are written in world and work-object frames. `None`: at the
    /// world origin.
    pub base_frame: Option<nalgebra::Isometry3<f64>>,
    /// Split a declared target moved to with several tools or work
    /// objects: a copy per other pair, declared after it and named by the
    /// moves with that pair (this changes more than numbers). Without it,
    /// such a target is corrected for its first use and the others are
    /// reported with their residual.
    pub split_shared: bool,
    /// What a run does with a file whose marker is not trusted (its
    /// numbers changed since the correction, or it has no fingerprint).
    pub untrusted: Untrusted,
}

/// What a run does with a file whose marker is not trusted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Untrusted {
    /// Refuse: a run that writes would correct corrected numbers again.
    #[default]
    Refuse,
    /// Take every target as cold, and say why: a check or a report finds
    /// the targets that would move, the re-taught ones among them.
    AsCold,
}

impl Options {
    /// Every target for `when`, a target reached several times for the
    /// mean of its visits, literals with expressions left alone, the
    /// embedded model and arm.
    pub fn new(when: When) -> Options {
        Options {
            when,
            visit: Visit::Mean,
            expand_expressions: false,
            model_label: "embedded default model, embedded IRB 140 arm".to_string(),
            base_frame: None,
            split_shared: false,
            untrusted: Untrusted::Refuse,
        }
    }
}

impl When {
    /// The time basis in words, as the marker of a corrected file records
    /// it: a schedule by the fingerprint of its byte encoding
    /// ([`schedule_basis`]).
    pub fn basis(&self) -> String {
        match self {
            When::At(Moment::Minute(t)) => format!("minute {t}"),
            When::At(Moment::Steady) => "steady state".to_string(),
            When::Schedule {
                schedule,
                joints,
                default,
                ..
            } => schedule_basis(|e| schedule.encode(e), joints, default),
        }
    }
}

/// [`When::basis`] of a schedule, `schedule v1 sha256:…`: the
/// fingerprint of the schedule's byte encoding, version 1 (tag
/// [`SCHEDULE_ENCODING`] and a zero byte; the robtargets' visits as
/// `robtargets` writes them, [`encode_visits`]; a byte 0 where the
/// jointtargets' times are looked up among the robtargets', else 1 and
/// their visits likewise; the default moment: a byte 0 for none, 1 and
/// the minute's f64 bits, or 2 for the steady state). Documented in
/// `docs/correct.md`; `tests/correct/marker.rs` pins it.
///
/// [`encode_visits`]: crate::schedule::encode_visits
pub(crate) fn schedule_basis(
    robtargets: impl FnOnce(&mut Encoder),
    joints: &Option<Schedule>,
    default: &Option<Moment>,
) -> String {
    let mut e = Encoder::new(SCHEDULE_ENCODING);
    robtargets(&mut e);
    match joints {
        None => e.u8(0),
        Some(j) => {
            e.u8(1);
            j.encode(&mut e);
        }
    }
    match default {
        None => e.u8(0),
        Some(Moment::Minute(t)) => {
            e.u8(1);
            e.f64(*t);
        }
        Some(Moment::Steady) => e.u8(2),
    }
    format!("schedule v1 {}", e.finish())
}
