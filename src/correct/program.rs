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
use super::in_order::in_order;
use super::joints::{correct_jointtarget, JointSolved};
use super::marked::{already_corrected, keep_unmarked, unmarked_with_targets};
use super::moments::check_schedule_names;
use super::options::{OnUntrusted, Options, ScheduleSource, When};
use super::outcome::{derived_report, Correction, Derived, LeftAlone, Outcome, Residual, Summary};
use super::pass::{tallied, Buffers, Done, Pass, Tally};
use super::progress::Progress;
use super::splice::{write_error, Splice};
use super::target::{correct_robtarget, with_others, Solved};
use super::writers::{ReportRows, Writers};
use super::{derived, expressions, fate, marker, shared};
use crate::error::{Error, ErrorKind, Result};
use crate::model::WarmRobot;
use crate::rapid::numprint::NumberPrint;
use crate::rapid::rewrite::Edit;
use crate::rapid::{Program, TargetKind};
use std::borrow::Cow;
use std::collections::{HashMap, HashSet};
use std::io::Write;

/// Targets one core takes at a time.
const CHUNK: usize = 4_096;
/// How many chunks the cores may correct ahead of the writing: what
/// memory holds at once.
const AHEAD: usize = 8;

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
    if let When::Schedule {
        schedule,
        joints,
        source: ScheduleSource::File,
        ..
    } = &options.when
    {
        check_schedule_names(program, schedule)?;
        if let Some(j) = joints {
            check_schedule_names(program, j)?;
        }
    }
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
    let mut changed = Vec::with_capacity(program.files.len());
    for (f, out) in outs.iter_mut().enumerate() {
        let mut fixed = std::mem::take(&mut fixed[f]);
        for rows in early.rows.values() {
            for e in rows
                .iter()
                .filter(|r| r.file_index == f)
                .flat_map(|r| &r.edits)
            {
                fixed.push(e.clone());
            }
        }
        let file_changed = write_file(
            &pass,
            (f, &basis, &colds[f]),
            fixed,
            &mut **out,
            (&mut found, &mut progress),
        )?;
        changed.push(file_changed);
    }
    errors.append(&mut found.errors);
    errors.sort_by_key(|e| e.0);
    errors.extend(joints.errors);
    // Only the errors shown get their line's text (each a walk through
    // their file): the rest are counted.
    if let Some(e) = Error::many(
        same_cause(errors.into_iter().map(|(_, e)| e).collect())
            .into_iter()
            .enumerate()
            .map(|(k, e)| match k <= crate::error::MAX_RELATED {
                true => with_source(e, program),
                false => e,
            })
            .collect(),
    ) {
        return Err(e);
    }
    let early_error = early.error;
    if let Some(e) = early_error {
        return Err(e);
    }
    // Derived targets: left as written, their bases' corrections carry
    // them; what remains at each is its residual.
    // The index by name is built only for them: a million declared
    // targets made it a second's work on one core.
    let index_of =
        (!found.derived.is_empty()).then(|| program.target_index(|t| t.kind != TargetKind::Inline));
    let passed = match found.derived.is_empty() {
        true => HashMap::new(),
        false => crate::resolve::settled_parameters(program),
    };
    // No derived targets: no index, and nothing below runs.
    let lookups = index_of
        .iter()
        .map(|index| (&run.set.frames, &run.set.uses, index));
    let derived: Vec<Derived> = (lookups.flat_map(|l| found.derived.iter().map(move |&i| (i, l))))
        .map(|(i, lookup)| {
            progress.step();
            let target = targets.at(i);
            let reads: Vec<&str> = match passed.is_empty() {
                true => Vec::new(),
                false => (run.set.calls.get(&target.origin.pos.offset).into_iter())
                    .flat_map(|c| &c.args)
                    .filter(|a| !a.optional)
                    .filter_map(|a| a.value.as_ref().and_then(crate::rapid::Expr::as_name))
                    .collect(),
            };
            let mut report = derived_report(program, &target, &found.rows, &passed, &reads);
            report.residual_mm = derived::residual(
                program,
                i,
                &run.set.calls,
                &lookup,
                &found.rows,
                warm,
                &run.states,
                &|e| run.eval(&target, e),
            );
            report
        })
        .collect();
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
        (early.lines.len(), early.splits.len()),
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

/// What the pass over the files found, in order.
#[derive(Default)]
struct Found {
    rows: Vec<Correction>,
    tally: Tally,
    left: Vec<(usize, LeftAlone)>,
    derived: Vec<usize>,
    errors: Vec<(usize, Error)>,
    /// Where the last chunk of the file being written left the rest of
    /// it ([`Done::tail_from`]).
    tail_from: Option<usize>,
}

/// File `f` written through `out`: its bytes up to its first target with
/// the marker (under its module header, written as if the file changes:
/// the caller throws the output away where it does not), then its
/// robtargets a chunk at a time, corrected on every core and written in
/// order as they come ([`in_order`]). Whether the file changes.
fn write_file(
    pass: &Pass,
    (f, basis, cold): (usize, &str, &str),
    mut fixed: Vec<Edit>,
    out: &mut (dyn Write + Send),
    (found, progress): (&mut Found, &mut Progress),
) -> Result<bool> {
    // Every byte up to the numbers' line goes through the fingerprint of
    // the numbers, the marker's proof: it is of what is written.
    let src = pass.run.program.source(f);
    let end = marker::numbers_at(src);
    let mut printed = Printed {
        out,
        print: NumberPrint::new(),
        held: Vec::with_capacity(PRINT_PIECE),
    };
    let changed = write_numbers(
        pass,
        (f, basis, cold),
        &mut fixed,
        &mut printed,
        end,
        (found, progress),
    )?;
    let Printed {
        out,
        mut print,
        held,
    } = printed;
    print.feed(&held);
    // The seal: the marker's fields with the numbers.
    let seal = file_marker(pass, basis, cold).seal(&print.finish());
    out.write_all(&marker::numbers_line(src, end, &seal))
        .map_err(write_error)?;
    // What follows the last ENDMODULE (edits there too, should any be).
    let rest: Vec<&Edit> = fixed.iter().filter(|e| e.span.start >= end).collect();
    let mut splice = Splice { src, at: end, out };
    let mut rest = rest.into_iter().peekable();
    splice.finish_at(&mut rest, src.len())?;
    out_flush(splice.out)?;
    Ok(changed)
}

/// The marker of a file this run writes (`cold`: its cold original's
/// fingerprint).
fn file_marker(pass: &Pass, basis: &str, cold: &str) -> marker::Marker {
    marker::for_run_printed(
        basis,
        &pass.run.options.model_label,
        pass.run.options.split_shared,
        cold.to_string(),
    )
}

fn out_flush(out: &mut dyn Write) -> Result<()> {
    out.flush().map_err(write_error)
}

/// A writer that reads the numbers of what it writes: what is written
/// (a number's new text, the bytes between two) is read a piece of
/// [`PRINT_PIECE`] at a time, so that few tokens are cut between pieces.
struct Printed<'w> {
    out: &'w mut (dyn Write + Send),
    print: NumberPrint,
    held: Vec<u8>,
}

/// How much the fingerprint reads at a time.
const PRINT_PIECE: usize = 1 << 16;

impl Printed<'_> {
    /// A chunk's bytes, whose tokens were read on its core where given:
    /// whether they were taken (else the bytes were read here).
    fn chunk(&mut self, bytes: &[u8], tokens: Option<&[u8]>) -> std::io::Result<bool> {
        self.out.write_all(bytes)?;
        self.print.feed(&self.held);
        self.held.clear();
        let taken = tokens.is_some_and(|t| self.print.absorb(t));
        if !taken {
            self.print.feed(bytes);
        }
        Ok(taken)
    }
}

impl Write for Printed<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.out.write(buf)?;
        self.held.extend_from_slice(&buf[..n]);
        if self.held.len() >= PRINT_PIECE {
            self.print.feed(&self.held);
            self.held.clear();
        }
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}

/// The file's bytes up to `end` (the numbers' line's place) with the
/// marker and the new numbers.
fn write_numbers(
    pass: &Pass,
    (f, basis, cold): (usize, &str, &str),
    fixed: &mut Vec<Edit>,
    out: &mut Printed,
    end: usize,
    (found, progress): (&mut Found, &mut Progress),
) -> Result<bool> {
    let run = pass.run;
    let program = run.program;
    let src = program.source(f);
    let targets = program.targets();
    let changed_before = !fixed.is_empty();
    fixed.sort_by_key(|e| (e.span.start, e.span.end));
    // The file's targets: its stretch of the numbering (targets are in
    // file order).
    let file_of = |i: usize| targets.place(i).map_or(usize::MAX, |p| p.0);
    let (lo, hi) = (
        first_where(targets.len(), |i| file_of(i) >= f),
        first_where(targets.len(), |i| file_of(i) > f),
    );
    let place = |i: usize| targets.place(i).map_or(src.len(), |p| p.1);
    let head_end = if lo < hi { place(lo) } else { end };
    let mut changed = changed_before;
    let put_head = |out: &mut Printed, fixed: &[Edit]| -> Result<()> {
        let m = file_marker(pass, basis, cold);
        let mark = marker::insert(program, f, &m);
        // The marker goes into the module's header, before every target.
        if mark.as_ref().is_some_and(|e| e.span.start > head_end) {
            return Err(Error::input(
                "internal: the marker's place lies after the file's first target",
            ));
        }
        let mut edits: Vec<&Edit> = fixed
            .iter()
            .take_while(|x| x.span.start < head_end)
            .chain(&mark)
            .collect();
        edits.sort_by_key(|e| (e.span.start, e.span.end));
        let mut splice = Splice { src, at: 0, out };
        let mut edits = edits.into_iter().peekable();
        splice.finish_at(&mut edits, head_end)
    };
    put_head(out, fixed)?;
    // The file's targets a chunk at a time, corrected on every core and
    // written here in order as they come.
    let chunks: Vec<std::ops::Range<usize>> = (lo..hi)
        .step_by(CHUNK)
        .map(|c| c..(c + CHUNK).min(hi))
        .collect();
    let fixed_ref = &*fixed;
    in_order(
        chunks.len(),
        rayon::current_num_threads(),
        AHEAD,
        |k| {
            let c = chunks[k].clone();
            let last = c.end >= hi;
            let to = if last { end } else { place(c.end) };
            pass.chunk(src, c.clone(), (place(c.start)..to, last), fixed_ref)
        },
        |_, done| -> Result<()> {
            let (c, steps) = put_out(out, done, (found, &pass.buffers))?;
            changed |= c;
            progress.add(steps);
            Ok(())
        },
    )?;
    if let Some(from) = found.tail_from.take() {
        write_tail(src, (from, end), fixed, out)?;
    }
    out.flush().map_err(write_error)?;
    Ok(changed)
}

/// A piece of a file's tail: its bytes (the file's own where no edit
/// falls in it) and their tokens for the fingerprint.
type Piece<'s> = (Cow<'s, [u8]>, Option<Vec<u8>>);

/// How much of a file's tail is read for the fingerprint at a time.
const TAIL_PIECE: usize = 1 << 20;

/// After the last target, the file's bytes from `from` to `end` with the
/// edits there, straight from the file: a RobotStudio export's million
/// moves by name. Cut after line ends into pieces whose numbers are read
/// on every core (a line end ends any token but a string, which
/// [`NumberPrint::absorb`] refuses: such a piece is read in order) and
/// written in order; the first piece, which may continue the last
/// target's token, and any piece an edit crosses into, in order. How
/// many pieces were read on every core.
fn write_tail(
    src: &[u8],
    (from, end): (usize, usize),
    fixed: &[Edit],
    out: &mut Printed,
) -> Result<usize> {
    use rayon::prelude::*;
    let edits: Vec<&Edit> = fixed.iter().filter(|e| e.span.start >= from).collect();
    let mut cuts = vec![from];
    let mut at = from;
    while end - at > TAIL_PIECE {
        // A line's start (after LF, CRLF or a lone CR) is no token's middle.
        let Some(cut) = crate::error::next_line_start(src, at + TAIL_PIECE).filter(|&c| c <= end)
        else {
            break;
        };
        // The edit starting last before the cut must end by it.
        let before = edits.partition_point(|e| e.span.start < cut);
        if cut >= end || before > 0 && edits[before - 1].span.end > cut {
            break;
        }
        cuts.push(cut);
        at = cut;
    }
    cuts.push(end);
    let piece = |a: usize, b: usize| -> Result<Piece> {
        let (lo, hi) = (
            edits.partition_point(|e| e.span.start < a),
            edits.partition_point(|e| e.span.start < b),
        );
        let bytes = match lo == hi {
            true => Cow::Borrowed(&src[a..b]),
            false => {
                let mut v = Vec::with_capacity(b - a + (b - a) / 64);
                let mut splice = Splice {
                    src,
                    at: a,
                    out: &mut v,
                };
                splice.finish_at(&mut edits[lo..hi].iter().copied().peekable(), b)?;
                Cow::Owned(v)
            }
        };
        let tokens = NumberPrint::tokens_of(&bytes);
        Ok((bytes, tokens))
    };
    // The first piece through the writer that reads as it writes.
    let first_end = cuts[1];
    let mut first = edits
        .iter()
        .copied()
        .take_while(|e| e.span.start < first_end)
        .peekable();
    Splice { src, at: from, out }.finish_at(&mut first, first_end)?;
    let pieces: Vec<(usize, usize)> = cuts[1..].windows(2).map(|w| (w[0], w[1])).collect();
    let mut taken = 0;
    for batch in pieces.chunks(4 * rayon::current_num_threads()) {
        let done: Vec<Result<_>> = batch.par_iter().map(|&(a, b)| piece(a, b)).collect();
        for d in done {
            let (bytes, tokens) = d?;
            taken += usize::from(out.chunk(&bytes, tokens.as_deref()).map_err(write_error)?);
        }
    }
    Ok(taken)
}

/// The first of `0..n` where `pred`, which holds from there on.
fn first_where(n: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0, n);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if pred(mid) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

/// Put a chunk out (chunks come in file order), keeping what it found;
/// whether it changes the file, and how many targets it solved.
fn put_out(
    out: &mut Printed,
    done: Result<Done>,
    (found, buffers): (&mut Found, &Buffers),
) -> Result<(bool, usize)> {
    let mut d = done?;
    out.chunk(&d.bytes, d.tokens.as_deref())
        .map_err(write_error)?;
    buffers.give(&mut d);
    found.rows.extend(d.rows);
    for t in d.tally {
        found.tally.add(t);
    }
    found.left.extend(d.left);
    found.derived.extend(d.derived);
    found.errors.extend(d.errors);
    if d.tail_from.is_some() {
        found.tail_from = d.tail_from;
    }
    Ok((d.changed, d.steps))
}

/// The jointtargets' corrections, done before the robtargets' (their
/// rows come after theirs in the report).
#[derive(Default)]
struct Joints {
    rows: Vec<Correction>,
    residuals: Vec<Residual>,
    left: Vec<LeftAlone>,
    errors: Vec<(usize, Error)>,
    /// Edits of their numbers, by file.
    edits: Vec<(usize, Edit)>,
}

fn correct_joints(run: &Run, progress: &mut Progress) -> Joints {
    let mut j = Joints::default();
    for (index, jt) in run.program.jointtargets().iter().enumerate() {
        if jt.kind == TargetKind::Derived {
            continue;
        }
        progress.step();
        match correct_jointtarget(run, index, jt) {
            Ok(JointSolved::Corrected(c, r)) => {
                j.edits
                    .extend(c.edits.iter().map(|e| (c.file_index, e.clone())));
                j.rows.push(*c);
                j.residuals.extend(r);
            }
            Ok(JointSolved::LeftAlone(s)) => j.left.push(s),
            Err(e) => j.errors.push((usize::MAX, e)),
        }
    }
    j
}

/// The robtargets moved to with several tools or work objects, solved
/// before the pass: what their other uses come to (and, asked for, their
/// copies) decides edits anywhere in the program.
#[derive(Default)]
struct Early {
    /// By target: its row, then its copies'.
    rows: HashMap<usize, Vec<Correction>>,
    lines: Vec<crate::correct::SharedUse>,
    splits: Vec<crate::correct::SplitTarget>,
    /// Edits beyond the numbers (copies, renamed arguments), by file.
    more: Vec<(usize, Edit)>,
    /// Why the copies could not be made, where they could not (said
    /// when no target is refused).
    error: Option<Error>,
}

fn solve_shared(run: &Run, errors: &mut Vec<(usize, Error)>) -> Result<Early> {
    let program = run.program;
    let targets = program.targets();
    let mut pending = Vec::new();
    let mut corrections: Vec<Correction> = Vec::new();
    let mut owners: Vec<usize> = Vec::new();
    for i in run.set.uses.of_several_frames() {
        let t = targets.at(i);
        if t.kind == TargetKind::Derived && !t.written_with_expressions() {
            continue;
        }
        match correct_robtarget(run, i, &t) {
            Ok(Solved::Corrected(found)) => match with_others(run, i, &t, &found) {
                Ok((c, pairs)) => {
                    if !pairs.is_empty() {
                        pending.push(shared::Pending {
                            correction: corrections.len(),
                            pairs,
                        });
                    }
                    corrections.push(c);
                    owners.push(i);
                }
                Err(e) => errors.push((i, e)),
            },
            // Left alone, it is the pass's to report.
            Ok(Solved::LeftAlone(_)) => {}
            Err(e) => errors.push((i, e)),
        }
    }
    let mut early = Early::default();
    if corrections.is_empty() {
        return Ok(early);
    }
    let originals: Vec<String> = corrections.iter().map(|c| c.id.clone()).collect();
    let done = match shared::finish(run, pending, &mut corrections) {
        Ok(d) => d,
        Err(e) => {
            early.error = Some(e);
            return Ok(early);
        }
    };
    // Each copy follows its original in `corrections` (a copy has a name
    // of its own).
    let (mut k, mut owner) = (0, None);
    for c in corrections {
        if originals.get(k) == Some(&c.id) {
            owner = owners.get(k).copied();
            k += 1;
        }
        if let Some(o) = owner {
            early.rows.entry(o).or_default().push(c);
        }
    }
    early.lines = done.lines;
    early.splits = done.splits;
    early.more = done.edits;
    Ok(early)
}

/// The targets whose rows a derived target's residual reads: its bases.
fn derived_bases(run: &Run) -> HashSet<usize> {
    let program = run.program;
    let derived: Vec<String> = program
        .targets()
        .one_by_one_all()
        .filter(|(_, t)| t.kind == TargetKind::Derived && !t.written_with_expressions())
        .flat_map(|(_, t)| {
            t.derived
                .iter()
                .flat_map(|d| d.bases.clone())
                .collect::<Vec<_>>()
        })
        .collect();
    if derived.is_empty() {
        return HashSet::new();
    }
    let index = program.target_index(|t| t.kind != TargetKind::Inline);
    derived.iter().filter_map(|b| index.get(b)).collect()
}

/// The summary of the corrections tallied (in the report's order), and
/// the counts of the rest. Every row counts in the largest and RMS
/// correction: a jointtarget's at the flange, as its row shows it.
fn summary(
    tally: &Tally,
    derived: usize,
    left_alone: usize,
    (shared, split): (usize, usize),
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
    let line_start = crate::error::start_of_line(src, loc.line);
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

    /// A tail of five pieces, with comments, strings (holding a `[` and
    /// a quote) and numbers, edits in its first piece and in a later one:
    /// the bytes are the file's with the edits, the fingerprint is the
    /// whole text's read in order, and the pieces after the first were
    /// read on the cores, but the two a string runs across (left open in
    /// the third piece, closed in the fourth), read in order.
    #[test]
    fn a_long_tail_is_read_in_pieces_as_in_order() {
        let mut src = b"MODULE M\r\n  CONST robtarget p:=[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\r\n".to_vec();
        let from = src.len() - 2;
        let mut k = 0;
        let mut line = |src: &mut Vec<u8>, strings: bool| {
            let l = match k % 4 {
                0 => format!("  MoveL Target_{k},v1000,z1,tool1\\WObj:=wobj1;\r\n"),
                1 if strings => format!("  WaitTime 0.{k}; ! {k}.5 mm \"\r\n"),
                1 => format!("  WaitTime 0.{k}; ! {k}.5 mm\r\n"),
                2 if strings => format!("  TPWrite \"a[{k} \"\"{k}\"\" 1E3\";\r\n"),
                _ => format!("  n:=-{k}E-2+1THEN;\r\n"),
            };
            src.extend_from_slice(l.as_bytes());
            k += 1;
        };
        let mib = TAIL_PIECE;
        while src.len() < 2 * mib + mib / 2 {
            let strings = src.len() < mib + mib / 2;
            line(&mut src, strings);
        }
        src.extend_from_slice(b"  s:=\"open\r\n");
        while src.len() < 3 * mib + mib / 2 {
            line(&mut src, false);
        }
        src.extend_from_slice(b"  closed\";\r\n");
        while src.len() < 5 * mib - 1000 {
            line(&mut src, true);
        }
        src.extend_from_slice(b"ENDMODULE\r\n");
        let end = src.len() - b"ENDMODULE\r\n".len();
        let edit = |at: usize, len: usize, new: &[u8]| Edit {
            span: at..at + len,
            expected_old: src[at..at + len].to_vec(),
            new: new.to_vec(),
        };
        let later = 4 * mib + 5000;
        let later = later + memchr::memchr(b'\n', &src[later..]).unwrap() + 1;
        let fixed = vec![edit(from + 40, 3, b"12345"), edit(later, 2, b" ")];
        let mut want = src[from..end].to_vec();
        for e in fixed.iter().rev() {
            let (a, b) = (e.span.start - from, e.span.end - from);
            want.splice(a..b, e.new.iter().copied());
        }
        let mut written = Vec::new();
        let mut printed = Printed {
            out: &mut written,
            print: NumberPrint::new(),
            held: Vec::new(),
        };
        let taken = write_tail(&src, (from, end), &fixed, &mut printed).unwrap();
        let Printed {
            mut print, held, ..
        } = printed;
        print.feed(&held);
        assert_eq!(written, want);
        assert_eq!(print.finish(), NumberPrint::of(&want));
        assert_eq!(taken, 2);
    }

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
