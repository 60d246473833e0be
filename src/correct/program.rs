//! Correcting a whole program, the one way it is done whatever its size:
//! the jointtargets and the robtargets moved to with several tools or
//! work objects first (few, and what they decide is written where they
//! are), then every other robtarget in file order, a chunk at a time on
//! every core (`pass`), each file written as its chunks come, in order,
//! through the caller's writer (the corrected file of a million targets
//! is never held in memory), and the report's rows kept only where the
//! caller keeps them. Every target is tried: a run reports every target
//! it refuses, each cause once. A program its marker says is corrected
//! already is written as it is.

use super::context::{CorrectWith, Run};
use super::derived_rows::{derived_bases, derived_rows};
use super::joints::correct_joints;
use super::marked::{already_corrected, keep_unmarked, unmarked_with_targets};
use super::moments::check_schedule_names;
use super::options::{OnUntrusted, Options, ScheduleSource, When};
use super::outcome::{LeftAlone, Outcome, Summary};
use super::pass::{tallied, Pass, Tally};
use super::progress::Progress;
use super::refused::{refuse_any, with_source};
use super::shared_first::solve_shared;
use super::splice::write_error;
use super::write_file::{write_files, Found, Marks};
use super::writers::{ReportRows, Writers};
use super::{expressions, fate, marker};
use crate::error::{Error, Result};
use crate::model::WarmRobot;
use crate::rapid::rewrite::Edit;
use crate::rapid::{Program, TargetKind};
use std::io::Write;

/// Correct every target of `program` (which keeps the bytes it was parsed
/// from: the corrected files are those bytes with new numbers), every
/// report row kept and every file's new bytes in the outcome. `progress`
/// is called with (done, total) now and then, in targets solved: (0,
/// total) when the first is started, (total, total) when the last is
/// done.
pub fn correct(
    program: &Program,
    warm: &WarmRobot,
    options: &Options,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Outcome> {
    correct_in_memory(program, CorrectWith::fresh(warm, options), progress)
}

/// [`correct`] with what the program alone decides made before, or its
/// error ([`correct_prepared`]).
pub(crate) fn correct_in_memory<'p>(
    program: &'p Program,
    run: CorrectWith<'_, 'p>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Outcome> {
    let mut bufs: Vec<Vec<u8>> = (0..program.files.len())
        .map(|f| Vec::with_capacity(program.source(f).len()))
        .collect();
    let corrected = {
        let mut outs: Vec<&mut (dyn Write + Send)> = bufs
            .iter_mut()
            .map(|b| b as &mut (dyn Write + Send))
            .collect();
        correct_prepared(
            program,
            run,
            Writers::new(&mut outs, ReportRows::Every),
            progress,
        )?
    };
    let mut outcome = corrected.outcome;
    for (f, buf) in bufs.iter_mut().enumerate() {
        if !corrected.changed[f] {
            *buf = program.source(f).to_vec();
        }
    }
    outcome.outputs = bufs;
    Ok(outcome)
}

/// A run corrected into its writers.
pub struct Corrected {
    /// What it found (no outputs: they went to the writers; rows as
    /// kept).
    pub outcome: Outcome,
    /// Whether each file changes. Where one does not, what was written
    /// to its writer is not its output: the file is as it was (and gets
    /// no marker).
    pub changed: Vec<bool>,
}

/// [`correct`], each file's corrected bytes written to `outs` (one writer
/// per file, in the program's file order) as they are made, the rows kept
/// as `to` says. On an error, what was written is to be thrown away.
pub fn correct_into(
    program: &Program,
    warm: &WarmRobot,
    options: &Options,
    to: Writers<'_, '_>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Corrected> {
    correct_prepared(program, CorrectWith::fresh(warm, options), to, progress)
}

/// [`correct_into`] with what was made ahead of it ([`Ahead`]): what the
/// program alone decides (beside an estimate's walk, or its error) and
/// each file's fingerprint (beside the parse).
pub(crate) fn correct_prepared<'p>(
    program: &'p Program,
    with: CorrectWith<'_, 'p>,
    to: Writers<'_, '_>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Corrected> {
    correct_all(program, with, to, progress).map_err(|e| with_source(e, program))
}

fn correct_all<'p>(
    program: &'p Program,
    with: CorrectWith<'_, 'p>,
    mut to: Writers<'_, '_>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Corrected> {
    let (options, keep) = (with.options, to.rows);
    let basis = options.when.basis();
    let distrust = marker::untrusted(program);
    if let Some(u) = &distrust {
        if options.untrusted == OnUntrusted::Refuse {
            return Err(marker::refuse_untrusted(program, u));
        }
    }
    if let (Some(found), None) = (marker::find(program), &distrust) {
        let wanted = marker::for_run(&basis, &options.model_label, options.split_shared, b"");
        if !found.marker.same_correction(&wanted) {
            return Err(marker::refuse(program, &found, &wanted));
        }
        let marked = marker::marked_files(program);
        let unmarked = unmarked_with_targets(program, &marked);
        // A run that writes, on a program whose every file with targets
        // is marked: the files are what it would write.
        if keep == ReportRows::SummaryOnly && unmarked.is_empty() {
            for (f, out) in to.outs.iter_mut().enumerate() {
                out.write_all(program.source(f)).map_err(write_error)?;
            }
            return Ok(Corrected {
                outcome: already_corrected(program, &found, options),
                changed: vec![false; program.files.len()],
            });
        }
        // Else the whole run, as on a cold program, cut to what is still
        // cold ([`super::marked`]); split as the file was, so that the
        // uses it left shared are the ones found.
        let as_made = Options {
            split_shared: found.marker.split,
            ..options.clone()
        };
        let run = CorrectWith::new(with.warm, &as_made, with.ahead);
        to.rows = ReportRows::Every;
        let mut all = correct_body(program, run, to, progress, None)?;
        let (o, changed) = (&mut all.outcome, &mut all.changed[..]);
        keep_unmarked(program, &marked, &unmarked, &found, o, changed, options);
        if keep == ReportRows::SummaryOnly {
            all.outcome.corrections.clear();
        }
        return Ok(all);
    }
    correct_body(program, with, to, progress, distrust)
}

/// [`correct_all`] past the marker: every target of the program taken as
/// cold (`distrust`: why a marker it holds is not trusted, for the notes).
fn correct_body<'p>(
    program: &'p Program,
    with: CorrectWith<'_, 'p>,
    to: Writers<'_, '_>,
    progress: &mut dyn FnMut(usize, usize),
    distrust: Option<marker::Untrusted>,
) -> Result<Corrected> {
    let (warm, options, mut ahead) = (with.warm, with.options, with.ahead);
    let (outs, keep) = (to.outs, to.rows);
    let basis = options.when.basis();
    // What the program alone decides, and each file's fingerprint for
    // its marker: made ahead where the caller had them made, else now.
    let cold_joints = ahead.cold_joints.take().filter(|c| c.fits(program));
    let (prepared, colds) = ahead.setup_and_prints(program, options)?;
    let mut run = Run::with(prepared, warm, options);
    run.cold_joints = cold_joints;
    check_schedule_files(program, &options.when)?;
    let targets = program.targets();
    let costly_joints = program
        .jointtargets()
        .iter()
        .filter(|jt| jt.kind != TargetKind::Derived)
        .count();
    let mut progress = Progress::new(targets.len() + costly_joints, progress);
    // Every target is tried: a run reports all the targets it refuses, not
    // only the first (robtargets in order, then jointtargets).
    let mut errors: Vec<(usize, Error)> = Vec::new();
    let joints = correct_joints(&run, &mut progress);
    let early = solve_shared(&run, &mut errors)?;
    let bases = derived_bases(&run);
    let mut fixed: Vec<Vec<Edit>> = vec![Vec::new(); program.files.len()];
    for (f, e) in joints.edits.iter().chain(&early.more) {
        if let Some(list) = fixed.get_mut(*f) {
            list.push(e.clone());
        }
    }
    let pass = Pass {
        run: &run,
        keep_rows: keep == ReportRows::Every,
        write: true,
        early: &early.rows,
        bases: &bases,
        buffers: Default::default(),
    };
    let mut found = Found::default();
    let marks = Marks {
        basis: &basis,
        colds: &colds,
    };
    let changed = write_files(
        &pass,
        &early,
        fixed,
        outs,
        &marks,
        &mut found,
        &mut progress,
    )?;
    errors.append(&mut found.errors);
    errors.sort_by_key(|e| e.0);
    errors.extend(joints.errors);
    refuse_any(errors, program)?;
    let early_error = early.error;
    if let Some(e) = early_error {
        return Err(e);
    }
    let derived = derived_rows(&run, &found.derived, &found.rows, &mut progress);
    progress.finish();
    let mut corrections = found.rows;
    let mut tally = found.tally;
    for c in joints.rows {
        tally.add(tallied(&c));
        corrections.push(c);
    }
    if keep == ReportRows::SummaryOnly {
        // Only the derived targets' bases were kept, for their residuals.
        corrections.clear();
    }
    let by_index = fate::left_by_index(&found.left);
    let mut left_alone: Vec<LeftAlone> = found.left.into_iter().map(|(_, l)| l).collect();
    left_alone.extend(joints.left);
    left_alone.extend(expressions::jointtarget_expressions(program));
    // Every move instruction accounted for: its fate read from its
    // targets', and a row for each argument that reaches none.
    let (moves, move_counts, unread) = fate::fates(
        program,
        &run.set.lookup,
        &fate::Decided {
            robtargets: &by_index,
            others: &left_alone,
            frames: &run.set.frames,
        },
        keep == ReportRows::Every,
    );
    left_alone.extend(unread);
    let mut summary = summary(
        &tally,
        derived.len(),
        left_alone.len(),
        early.lines.len(),
        early.splits.len(),
    );
    summary.moves = move_counts;
    Ok(Corrected {
        outcome: Outcome {
            moves,
            corrections,
            derived,
            left_alone,
            residuals: joints.residuals,
            shared: early.lines,
            splits: early.splits,
            already_corrected: None,
            notes: distrust
                .iter()
                .map(|u| marker::untrusted_note(program, u))
                .chain(run.notes())
                .collect(),
            summary,
            outputs: Vec::new(),
        },
        changed,
    })
}

/// A schedule read from a file names only routines and targets of the
/// program.
fn check_schedule_files(program: &Program, when: &When) -> Result<()> {
    if let When::Schedule {
        schedule,
        joints,
        source: ScheduleSource::File,
        ..
    } = when
    {
        check_schedule_names(program, schedule)?;
        if let Some(j) = joints {
            check_schedule_names(program, j)?;
        }
    }
    Ok(())
}

/// The summary of the corrections tallied (in the report's order), and
/// the counts of the rest. Every row counts in the largest and RMS
/// correction: a jointtarget's at the flange, as its row shows it.
fn summary(
    tally: &Tally,
    derived: usize,
    left_alone: usize,
    shared: usize,
    split: usize,
) -> Summary {
    Summary {
        corrected: tally.corrected,
        rewritten: tally.rewritten,
        max_mm: tally.max_mm,
        rms_mm: tally.rms_mm(),
        max_drift_mm: tally.max_drift_mm,
        derived,
        left_alone,
        shared,
        split,
        moves: super::outcome::MoveCounts::default(),
    }
}
