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
mod moments;
mod outcome;
mod solve;

pub use edits::ORIENTATION_CHANGE_RAD;
pub use outcome::{Correction, Derived, Outcome, Skipped, Summary};

use crate::error::{Error, Result};
use crate::model::{Moment, WarmRobot};
use crate::rapid::{Program, TargetKind};
use crate::schedule::{Schedule, Visit};
use edits::write_files;
use moments::check_schedule_names;
use outcome::{derived_report, summarise};
use solve::{correct_jointtarget, correct_robtarget, Run, Solved};

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
}

/// Correct every target of `program` (which keeps the bytes it was parsed
/// from: the corrected files are those bytes with new numbers). `progress` is called with
/// (done, total) now and then.
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
    let total = program.targets().len() + program.jointtargets().len();
    let mut corrections = Vec::new();
    let mut skipped = Vec::new();
    let mut derived_targets = Vec::new();
    for (index, target) in program.targets().iter().enumerate() {
        if index % 4096 == 0 {
            progress(index, total);
        }
        if target.kind == TargetKind::Derived {
            derived_targets.push(index);
            continue;
        }
        match correct_robtarget(&run, index, target)? {
            Solved::Corrected(c) => corrections.push(*c),
            Solved::Skipped(s) => skipped.push(s),
            Solved::Nothing => {}
        }
    }
    for (k, jt) in program.jointtargets().iter().enumerate() {
        if k % 4096 == 0 {
            progress(program.targets().len() + k, total);
        }
        if jt.kind == TargetKind::Derived {
            continue;
        }
        corrections.push(correct_jointtarget(&run, jt)?);
    }
    progress(total, total);
    let calls = derived::calls_by_offset(program);
    let lookup = (&run.frames, &run.uses);
    let derived: Vec<Derived> = derived_targets
        .into_iter()
        .map(|i| {
            let target = &program.targets()[i];
            let mut report = derived_report(program, target, &corrections);
            report.residual_mm = derived::residual(
                program,
                target,
                &calls,
                &lookup,
                &corrections,
                warm,
                &run.states,
            );
            report
        })
        .collect();
    let outputs = write_files(program, &corrections)?;
    let summary = summarise(&corrections, &derived, &skipped);
    Ok(Outcome {
        corrections,
        derived,
        skipped,
        notes: run.notes.into_inner(),
        summary,
        outputs,
    })
}

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
        ..loc.clone()
    };
    e.at(location)
}
