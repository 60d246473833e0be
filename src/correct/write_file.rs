//! Writing a corrected file: its bytes up to its first target with the
//! marker, its robtargets a chunk at a time, corrected on every core and
//! written in order as they come, its tail, and the marker's seal of the
//! numbers written.

use super::in_order::in_order;
use super::marker;
use super::outcome::{Correction, LeftAlone};
use super::pass::{Buffers, Done, Pass, Tally};
use super::printed::{Printed, PRINT_PIECE};
use super::progress::Progress;
use super::shared_first::Early;
use super::splice::{write_error, Splice};
use super::tail::write_tail;
use crate::error::{Error, Result};
use crate::rapid::numprint::NumberPrint;
use crate::rapid::rewrite::Edit;
use std::io::Write;

/// Targets one core takes at a time.
const CHUNK: usize = 4_096;
/// How many chunks the cores may correct ahead of the writing: what
/// memory holds at once.
const AHEAD: usize = 8;

/// What the pass over the files found, in order.
#[derive(Default)]
pub(super) struct Found {
    pub rows: Vec<Correction>,
    pub tally: Tally,
    pub left: Vec<(usize, LeftAlone)>,
    pub derived: Vec<usize>,
    pub errors: Vec<(usize, Error)>,
    /// Where the last chunk of the file being written left the rest of
    /// it ([`Done::tail_from`]).
    pub tail_from: Option<usize>,
}

/// Every file of the program written through its writer of `outs`, with
/// the edits decided before the pass (`fixed`, by file) and the early
/// targets' rows' edits: whether each file changes. `colds`: each file's
/// cold original's fingerprint, for its marker.
pub(super) fn write_files(
    pass: &Pass,
    early: &Early,
    mut fixed: Vec<Vec<Edit>>,
    outs: &mut [&mut (dyn Write + Send)],
    marks: &Marks,
    found: &mut Found,
    progress: &mut Progress,
) -> Result<Vec<bool>> {
    let (basis, colds) = (marks.basis, marks.colds);
    let mut changed = Vec::with_capacity(pass.run.program.files.len());
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
        let file = OneFile {
            index: f,
            basis,
            cold: &colds[f],
        };
        let findings = Findings {
            found: &mut *found,
            progress: &mut *progress,
        };
        let file_changed = write_file(pass, file, fixed, &mut **out, findings)?;
        changed.push(file_changed);
    }
    Ok(changed)
}

/// The file being written, by its index in the program, and what its
/// marker says: the run's time basis and its cold original's fingerprint.
#[derive(Clone, Copy)]
struct OneFile<'a> {
    index: usize,
    basis: &'a str,
    cold: &'a str,
}

/// Where the pass puts what it finds and how far it has come.
struct Findings<'a, 'p> {
    found: &'a mut Found,
    progress: &'a mut Progress<'p>,
}

/// What every file's marker says: the run's time basis and each file's
/// cold original's fingerprint.
pub(super) struct Marks<'a> {
    pub basis: &'a str,
    pub colds: &'a [String],
}

/// File `f` written through `out`: its bytes up to its first target with
/// the marker (under its module header, written as if the file changes:
/// the caller throws the output away where it does not), then its
/// robtargets a chunk at a time, corrected on every core and written in
/// order as they come ([`in_order`]). Whether the file changes.
fn write_file(
    pass: &Pass,
    file: OneFile,
    mut fixed: Vec<Edit>,
    out: &mut (dyn Write + Send),
    findings: Findings,
) -> Result<bool> {
    let OneFile {
        index: f,
        basis,
        cold,
    } = file;
    // Every byte up to the numbers' line goes through the fingerprint of
    // the numbers, the marker's proof: it is of what is written.
    let src = pass.run.program.source(f);
    let end = marker::numbers_at(src);
    let mut printed = Printed {
        out,
        print: NumberPrint::new(),
        held: Vec::with_capacity(PRINT_PIECE),
    };
    let changed = write_numbers(pass, file, &mut fixed, &mut printed, end, findings)?;
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

/// The file's bytes up to `end` (the numbers' line's place) with the
/// marker and the new numbers.
fn write_numbers(
    pass: &Pass,
    OneFile {
        index: f,
        basis,
        cold,
    }: OneFile,
    fixed: &mut Vec<Edit>,
    out: &mut Printed,
    end: usize,
    Findings { found, progress }: Findings,
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
            pass.chunk(src, c.clone(), place(c.start)..to, last, fixed_ref)
        },
        |_, done| -> Result<()> {
            let (c, steps) = put_out(out, done, found, &pass.buffers)?;
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
    found: &mut Found,
    buffers: &Buffers,
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
