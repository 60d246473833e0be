//! How a run corrects: when the targets are reached, which visit counts,
//! what may be rewritten, the model's label for the marker, where the
//! robot stands.

use crate::digest::Encoder;
use crate::model::Moment;
use crate::schedule::{EstimateOptions, IdleSpan, Schedule, WhichVisit, SCHEDULE_ENCODING};

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
        /// Where the schedules come from: a file, or the estimate of the
        /// program being corrected.
        source: ScheduleSource,
    },
}

/// Where a run's schedule comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum ScheduleSource {
    /// The user's schedule file: it is checked against the program's
    /// targets, and the marker records the schedule itself.
    File,
    /// The estimate of `--start`, made by walking the program being
    /// corrected with these options: it names only the program's
    /// targets, so it is not checked against them again (a check of a
    /// million names, a tenth of such a run). The marker records the
    /// request, not the times: walked again on the corrected program the
    /// times differ by the corrections' microseconds, and a second run
    /// must still recognise its own output.
    Estimate(Box<EstimateOptions>),
}

/// How one run corrects.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub when: When,
    /// Which visit a target reached several times is corrected for.
    pub visit: WhichVisit,
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
    pub untrusted: OnUntrusted,
}

/// What a run does with a file whose marker is not trusted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OnUntrusted {
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
            visit: WhichVisit::Mean,
            expand_expressions: false,
            model_label: "embedded default model, embedded IRB 140 arm".to_string(),
            base_frame: None,
            split_shared: false,
            untrusted: OnUntrusted::Refuse,
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
                source: ScheduleSource::Estimate(request),
                default,
                ..
            } => estimate_basis(request, default),
            When::Schedule {
                schedule,
                joints,
                default,
                ..
            } => schedule_basis(
                |e| schedule.encode(e),
                joints,
                default,
                schedule.idle_spans(),
            ),
        }
    }
}

/// [`When::basis`] of an estimate, `estimate v1 sha256:…`: the
/// fingerprint of the request's byte encoding, version 1 (tag
/// [`ESTIMATE_ENCODING`] and a zero byte; the start minute's f64 bits;
/// the entry routine in lower case as a text; the cycles (u32); the base
/// frame: a byte 0 for none, else 1 and its translation x, y, z (mm) and
/// quaternion w, x, y, z as f64 bits; the default moment as in
/// [`schedule_basis`]). The program's own bytes are not in it: the
/// marker's cold fingerprint holds them. Documented in `docs/correct.md`;
/// `tests/correct/marker.rs` pins it.
pub(crate) fn estimate_basis(request: &EstimateOptions, default: &Option<Moment>) -> String {
    let mut e = Encoder::new(ESTIMATE_ENCODING);
    e.f64(request.start_min);
    e.text(&request.entry.to_lowercase());
    e.u32(request.cycles);
    match &request.base_frame {
        None => e.u8(0),
        Some(base) => {
            e.u8(1);
            let t = base.translation.vector;
            let q = base.rotation.quaternion();
            for v in [t.x, t.y, t.z, q.w, q.i, q.j, q.k] {
                e.f64(v);
            }
        }
    }
    encode_default(&mut e, default);
    format!("estimate v1 {}", e.finish())
}

/// The name and version of [`estimate_basis`]'s encoding.
pub const ESTIMATE_ENCODING: &str = "rapidtherm estimate 1";

/// A default moment: a byte 0 for none, 1 and the minute's f64 bits, or
/// 2 for the steady state.
fn encode_default(e: &mut Encoder, default: &Option<Moment>) {
    match default {
        None => e.u8(0),
        Some(Moment::Minute(t)) => {
            e.u8(1);
            e.f64(*t);
        }
        Some(Moment::Steady) => e.u8(2),
    }
}

/// [`When::basis`] of a schedule, `schedule v1 sha256:…`: the
/// fingerprint of the schedule's byte encoding, version 1 (tag
/// [`SCHEDULE_ENCODING`] and a zero byte; the robtargets' visits as
/// `robtargets` writes them, [`encode_visits`]; a byte 0 where the
/// jointtargets' times are looked up among the robtargets', else 1 and
/// their visits likewise; the default moment: a byte 0 for none, 1 and
/// the minute's f64 bits, or 2 for the steady state; then, only where
/// the schedule has idle spans, their number (u32) and each span's start
/// and end minute as f64 bits, in increasing time: a schedule without
/// them encodes as before they existed). Documented in
/// `docs/correct.md`; `tests/correct/marker.rs` pins it.
///
/// [`encode_visits`]: crate::schedule::encode_visits
pub(crate) fn schedule_basis(
    robtargets: impl FnOnce(&mut Encoder),
    joints: &Option<Schedule>,
    default: &Option<Moment>,
    idle: &[IdleSpan],
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
    encode_default(&mut e, default);
    if !idle.is_empty() {
        e.u32(u32::try_from(idle.len()).unwrap_or(u32::MAX));
        for span in idle {
            e.f64(span.from_min);
            e.f64(span.to_min);
        }
    }
    format!("schedule v1 {}", e.finish())
}
