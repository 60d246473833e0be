//! Correcting a whole program: every robtarget and jointtarget tried (a
//! run reports every target it refuses, each cause once), derived
//! targets' residuals, other tools and work objects, and the corrected
//! files; or, for a program its marker says is corrected already,
//! nothing.

use super::context::Run;
use super::edits::write_files;
use super::joints::{correct_jointtarget, JointSolved};
use super::moments::check_schedule_names;
use super::options::{Options, When};
use super::outcome::{
    derived_report, summarise, Correction, Derived, LeftAlone, Outcome, Residual, SharedUse, Split,
};
use super::progress::Progress;
use super::target::{correct_robtarget, Solved};
use super::{derived, expressions, marker, shared, solve};
use crate::error::{Error, ErrorKind, Result};
use crate::model::WarmRobot;
use crate::rapid::{Program, TargetKind};
use std::collections::HashMap;

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
pub(super) struct Findings {
    pub corrections: Vec<Correction>,
    pub derived: Vec<Derived>,
    pub left_alone: Vec<LeftAlone>,
    pub residuals: Vec<Residual>,
    pub shared: Vec<SharedUse>,
    pub splits: Vec<Split>,
    pub notes: Vec<String>,
    pub more: Vec<(usize, crate::rapid::rewrite::Edit)>,
}

impl Findings {
    pub(super) fn into_outcome(self, outputs: Vec<Vec<u8>>) -> Outcome {
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
pub(super) fn evaluate(
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
/// the first, not repeated with their own carets. Errors about a target
/// are told apart by their kind and cause (their message, which does not
/// name the target: see [`Subject`](crate::error::Subject)).
fn same_cause(errors: Vec<Error>) -> Vec<Error> {
    // Grouped through a map: a program for another arm can have every one
    // of a million targets refused for the same cause.
    let mut out: Vec<(Error, Vec<String>, usize)> = Vec::new();
    let mut by_cause: HashMap<(ErrorKind, String), usize> = HashMap::new();
    for e in errors {
        if let Some(subject) = &e.subject {
            let key = (e.kind, e.message.clone());
            if let Some(&i) = by_cause.get(&key) {
                let (_, names, count) = &mut out[i];
                *count += 1;
                if names.len() < NAMED_PER_CAUSE {
                    names.push(subject.to_string());
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
        let about = |id: &str| crate::error::Subject::Target(id.to_string());
        let errors: Vec<Error> = (0..25)
            .map(|i| Error::input("unknown tool `t`").about(about(&format!("p{i}"))))
            .chain([Error::input("another cause").about(about("q"))])
            .chain([Error::input("unknown tool `t`")])
            .collect();
        let grouped = same_cause(errors);
        // An error about no target is never grouped.
        assert_eq!(grouped.len(), 3);
        assert_eq!(
            grouped[0].notes,
            ["the same for 24 more: target p1, target p2, target p3, target p4, target p5, target p6, target p7, target p8, target p9, target p10, ..."]
        );
        assert!(grouped[1].notes.is_empty());
    }
}
