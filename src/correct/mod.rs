//! Correcting a program for thermal drift: for each target, the
//! coordinates that make the warm robot reach what the cold program meant;
//! and the target-by-target comparison of two programs.
//!
//! For a target T (TCP pose in its work object, robconf C), the program
//! means the flange pose F = frames(T). The controller, with its nominal
//! model, turns a target into joints by inverse kinematics; the warm robot
//! at joints q is at warm(q). The corrected target T' is the one whose
//! nominal joints are the warm joints that reach F:
//!
//! ```text
//! q_warm = IK_warm(F, C)        warm(q_warm) = F
//! F'     = FK_nominal(q_warm)   what the controller must be told
//! T'     = frames⁻¹(F')         in the target's own tool and work object
//! ```
//!
//! For pure link expansion the warm arm has the nominal arm's shape, and
//! `IK_warm` is the closed form on the expanded lengths: exact. Effects that
//! change the shape (bending, joint offsets, ...) are solved by Newton from
//! that start. The robconf is never changed.

//!
//! Owns the orchestration of a run (this file), the per-target solve
//! (`solve`), the moments targets are corrected for (`moments`), the
//! written text (`edits`), derived targets ([`derived`]) and the report
//! (`outcome`). May import `model`, `resolve`, `schedule`, `robot`,
//! `rapid`, `thermal` and the shared `error`; never `diagnose`, `compare`
//! or the CLI.

pub mod derived;
mod edits;
mod expressions;
mod joints;
pub mod marker;
mod moments;
mod outcome;
pub mod plot;
mod progress;
pub mod runtime;
mod shared;
mod solve;
pub mod stream;
mod stream_times;

pub use edits::ORIENTATION_CHANGE_RAD;
pub use outcome::{
    Correction, Derived, Frame, FramesUse, LeftAlone, Outcome, Reason, Residual, SharedUse, Split,
    Summary,
};

use crate::error::{Error, ErrorKind, Result};
use crate::model::{Moment, WarmRobot};
use crate::rapid::{Program, TargetKind};
use crate::schedule::{Schedule, Visit};
use edits::write_files;
use joints::{correct_jointtarget, JointSolved};
use moments::check_schedule_names;
use outcome::{derived_report, summarise};
use progress::Progress;
use solve::{correct_robtarget, Run, Solved};
use std::collections::HashMap;
pub use stream_times::CutTimes;

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
        }
    }
}

impl When {
    /// The time basis in words, as the marker of a corrected file records
    /// it: a schedule by the fingerprint of its times.
    pub fn basis(&self) -> String {
        match self {
            When::At(Moment::Minute(t)) => format!("minute {t}"),
            When::At(Moment::Steady) => "steady state".to_string(),
            When::Schedule {
                schedule,
                joints,
                default,
            } => schedule_basis(schedule, joints, default),
        }
    }
}

/// [`When::basis`] of a schedule: `schedule` is its robtargets' visits
/// (as their `Debug` text), `joints` and `default` the rest.
pub(crate) fn schedule_basis(
    schedule: &dyn std::fmt::Debug,
    joints: &Option<Schedule>,
    default: &Option<Moment>,
) -> String {
    let print = marker::fingerprint_of(|w| write!(w, "{schedule:?}{joints:?}{default:?}"));
    format!("schedule {print}")
}

/// Correct every target of `program` (which keeps the bytes it was parsed
/// from: the corrected files are those bytes with new numbers). `progress` is called with
/// (done, total) now and then, in targets solved: (0, total) when the
/// first is started, (total, total) when the last is done.
pub fn correct(
    program: &Program,
    warm: &WarmRobot,
    options: &Options,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Outcome> {
    correct_all(program, warm, options, progress).map_err(|e| with_source(e, program))
}

fn correct_all(
    program: &Program,
    warm: &WarmRobot,
    options: &Options,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Outcome> {
    let basis = options.when.basis();
    if let Some(found) = marker::find(program) {
        let wanted = marker::for_run(&basis, &options.model_label, options.split_shared, b"");
        if !found.marker.same_correction(&wanted) {
            return Err(marker::refuse(program, &found, &wanted));
        }
        return Ok(already_corrected(program, &found, options));
    }
    let findings = evaluate(program, warm, options, progress)?;
    let outputs = write_files(
        program,
        &findings.corrections,
        &findings.more,
        &basis,
        options,
    )?;
    Ok(findings.into_outcome(outputs))
}

/// What a run finds before any file is written: every target's
/// correction or why it is left alone, and the edits beyond the numbers
/// (a split's copies).
struct Findings {
    corrections: Vec<Correction>,
    derived: Vec<Derived>,
    left_alone: Vec<LeftAlone>,
    residuals: Vec<Residual>,
    shared: Vec<SharedUse>,
    splits: Vec<Split>,
    notes: Vec<String>,
    more: Vec<(usize, crate::rapid::rewrite::Edit)>,
}

impl Findings {
    fn into_outcome(self, outputs: Vec<Vec<u8>>) -> Outcome {
        let summary = summarise(
            &self.corrections,
            &self.derived,
            &self.left_alone,
            (&self.shared, &self.splits),
        );
        Outcome {
            corrections: self.corrections,
            derived: self.derived,
            left_alone: self.left_alone,
            residuals: self.residuals,
            shared: self.shared,
            splits: self.splits,
            already_corrected: None,
            notes: self.notes,
            summary,
            outputs,
        }
    }
}

/// Correct every target of a program not yet corrected (see [`correct`]).
fn evaluate(
    program: &Program,
    warm: &WarmRobot,
    options: &Options,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Findings> {
    let run = Run::new(program, warm, options)?;
    if let When::Schedule {
        schedule, joints, ..
    } = &options.when
    {
        check_schedule_names(program, schedule)?;
        if let Some(j) = joints {
            check_schedule_names(program, j)?;
        }
    }
    let costly_joints = program
        .jointtargets()
        .iter()
        .filter(|jt| jt.kind != TargetKind::Derived)
        .count();
    let mut progress = Progress::new(program.targets().len() + costly_joints, progress);
    let mut corrections = Vec::new();
    let mut left_alone = Vec::new();
    let mut residuals = Vec::new();
    let mut derived_targets = Vec::new();
    let mut pending = Vec::new();
    // Every target is tried: a run reports all the targets it refuses, not
    // only the first.
    let mut errors = Vec::new();
    for (index, target) in program.targets().iter().enumerate() {
        if target.kind == TargetKind::Derived && !target.written_with_expressions() {
            derived_targets.push(index);
            continue;
        }
        progress.step();
        match correct_robtarget(&run, index, target) {
            Ok(Solved::Corrected(c, pairs)) => {
                if !pairs.is_empty() {
                    pending.push(shared::Pending {
                        correction: corrections.len(),
                        pairs,
                    });
                }
                corrections.push(*c);
            }
            Ok(Solved::LeftAlone(s)) => left_alone.push(LeftAlone {
                world_mm: solve::written_in_world(&run, index, target),
                ..s
            }),
            Err(e) => errors.push(e),
        }
    }
    for jt in program.jointtargets() {
        if jt.kind == TargetKind::Derived {
            continue;
        }
        progress.step();
        match correct_jointtarget(&run, jt) {
            Ok(JointSolved::Corrected(c, r)) => {
                corrections.push(*c);
                residuals.extend(r);
            }
            Ok(JointSolved::LeftAlone(s)) => left_alone.push(s),
            Err(e) => errors.push(e),
        }
    }
    left_alone.extend(expressions::jointtarget_expressions(program));
    if let Some(e) = Error::many(
        same_cause(errors)
            .into_iter()
            .map(|e| with_source(e, program))
            .collect(),
    ) {
        return Err(e);
    }
    let shared =
        shared::finish(&run, pending, &mut corrections).map_err(|e| with_source(e, program))?;
    let lookup = (&run.frames, &run.uses);
    let derived: Vec<Derived> = derived_targets
        .into_iter()
        .map(|i| {
            progress.step();
            let target = &program.targets()[i];
            let mut report = derived_report(program, target, &corrections);
            report.residual_mm = derived::residual(
                program,
                i,
                &run.calls,
                &lookup,
                &corrections,
                warm,
                &run.states,
                &|e| run.eval(target, e),
            );
            report
        })
        .collect();
    progress.finish();
    Ok(Findings {
        corrections,
        derived,
        left_alone,
        residuals,
        shared: shared.lines,
        splits: shared.splits,
        notes: run.notes.into_inner(),
        more: shared.edits,
    })
}

/// The outcome of a run on a program its marker says is corrected on the
/// run's basis: nothing to do, every file as it is. A split asked of a
/// program corrected without one is not made (its numbers are no longer
/// the cold ones), and a note says so.
fn already_corrected(program: &Program, found: &marker::Found, options: &Options) -> Outcome {
    let m = &found.marker;
    let how = format!(
        "{} line {} says it was corrected by rapidtherm {} for {} with {} (cold original {})",
        program.files[found.file], found.line, m.version, m.basis, m.model, m.cold
    );
    let mut notes = Vec::new();
    if options.split_shared && !m.split {
        let uses = crate::resolve::usages(program);
        let mut shared: Vec<&str> = uses
            .iter()
            .filter(|(_, u)| crate::resolve::uses_by_frames(u).len() > 1)
            .map(|(&i, _)| program.targets()[i].id.as_str())
            .collect();
        shared.sort_unstable();
        if !shared.is_empty() {
            notes.push(format!(
                "it was corrected without splitting the targets moved to with several tools or work objects ({}): each is right for its first use only; a split starts from the cold original ({})",
                shared.join(", "),
                m.cold
            ));
        }
    }
    Outcome {
        corrections: Vec::new(),
        derived: Vec::new(),
        left_alone: Vec::new(),
        residuals: Vec::new(),
        shared: Vec::new(),
        splits: Vec::new(),
        already_corrected: Some(how),
        notes,
        summary: summarise(&[], &[], &[], (&[], &[])),
        outputs: (0..program.files.len())
            .map(|f| program.source(f).to_vec())
            .collect(),
    }
}

/// Errors with one cause shown once: the targets refused for the same
/// reason (`minute 200 is outside the recording`) are named in a note of
/// the first, not repeated with their own carets.
fn same_cause(errors: Vec<Error>) -> Vec<Error> {
    // "target p20: why" and "jointtarget j1: why" share "why".
    fn cause(e: &Error) -> (&str, &str) {
        match e.message.split_once(": ") {
            Some((who, why)) if who.starts_with("target ") || who.starts_with("jointtarget ") => {
                (who, why)
            }
            _ => ("", e.message.as_str()),
        }
    }
    // Grouped through a map: a program for another arm can have every one
    // of a million targets refused for the same cause.
    let mut out: Vec<(Error, Vec<String>, usize)> = Vec::new();
    let mut by_cause: HashMap<(ErrorKind, String), usize> = HashMap::new();
    for e in errors {
        let (who, why) = cause(&e);
        if !who.is_empty() {
            let key = (e.kind, why.to_string());
            if let Some(&i) = by_cause.get(&key) {
                let (_, names, count) = &mut out[i];
                *count += 1;
                if names.len() < NAMED_PER_CAUSE {
                    names.push(who.to_string());
                }
                continue;
            }
            by_cause.insert(key, out.len());
        }
        out.push((e, Vec::new(), 0));
    }
    out.into_iter()
        .map(|(e, names, count)| match count {
            0 => e,
            n if n > names.len() => {
                e.with_note(format!("the same for {n} more: {}, ...", names.join(", ")))
            }
            n => e.with_note(format!("the same for {n} more: {}", names.join(", "))),
        })
        .collect()
}

/// How many other targets a grouped error names; the rest are counted.
const NAMED_PER_CAUSE: usize = 10;

/// Errors located in the program gain the source line and caret.
fn with_source(e: Error, program: &Program) -> Error {
    let Some(loc) = &e.location else { return e };
    if !loc.line_text.is_empty() {
        return e;
    }
    let Some(file) = program.files.iter().position(|f| *f == loc.file) else {
        return e;
    };
    let src = program.source(file);
    let line_start = src
        .split_inclusive(|&b| b == b'\n')
        .take(loc.line.saturating_sub(1))
        .map(<[u8]>::len)
        .sum::<usize>();
    let line_text = crate::error::Location::from_offset(&loc.file, src, line_start).line_text;
    let location = crate::error::Location {
        line_text,
        ..(**loc).clone()
    };
    e.at(location)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_cause_is_shown_once_with_its_targets_counted() {
        let errors: Vec<Error> = (0..25)
            .map(|i| Error::input(format!("target p{i}: unknown tool `t`")))
            .chain([Error::input("target q: another cause")])
            .collect();
        let grouped = same_cause(errors);
        assert_eq!(grouped.len(), 2);
        assert_eq!(
            grouped[0].notes,
            ["the same for 24 more: target p1, target p2, target p3, target p4, target p5, target p6, target p7, target p8, target p9, target p10, ..."]
        );
        assert!(grouped[1].notes.is_empty());
    }
}
