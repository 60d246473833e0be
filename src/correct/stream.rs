//! The main job at the speed of the disk. A CAM program of a million
//! inline moves is read as a skeleton (everything but the moves
//! [`fastmove`](crate::rapid::fastmove) recognises, parsed and corrected
//! whole as ever) and the moves themselves, read again where they were,
//! corrected a batch at a time on every core by the same solve, and
//! written out in order as they come: memory holds a batch, not the
//! program. Timed by a schedule, each cut target is corrected for its own
//! moment, worked out beforehand ([`CutTimes`], the first of two passes).
//!
//! Whatever the fast path could not say exactly as the whole-program path
//! does (an error with its place, a target left alone, a note, a program
//! already corrected) sends the caller back to [`correct`](super::correct),
//! which then says it: the fast path either writes the same bytes or
//! declines.

use super::context::Run;
use super::outcome::Summary;
use super::program::{evaluate, Findings};
use super::solve::{corrected_numbers, Meant};
use super::{marker, CutTimes, Options, Outcome, When};
use crate::error::{Error, Result};
use crate::model::{Moment, State, WarmRobot};
use crate::rapid::fastmove::Skeleton;
use crate::rapid::rewrite::{robtarget_changes, Edit};
use crate::rapid::{Origin, Pos, Program, RobTargetValue, Target, TargetKind};
use crate::resolve::target_pose;
use crate::robot::{RobConf, ToolData, WobjData};
use nalgebra::Isometry3;
use rayon::prelude::*;
use std::collections::HashMap;
use std::io::Write;
use std::ops::Range;
use std::sync::Arc;

/// Moves corrected between two writes: what memory holds at once.
const BATCH: usize = 65_536;
/// Moves one core takes at a time (each sets up its own view of the run).
const CHUNK: usize = 4_096;

/// A streamed run.
pub struct Streamed {
    /// The summary and the skeleton's reports; no per-target rows
    /// (`corrections` is empty: a million rows is what streaming avoids).
    pub outcome: Outcome,
    /// Whether the program changes. When it does not, what was written is
    /// not the output: the file stays byte for byte as it is (and gets no
    /// marker), as the whole-program path leaves it.
    pub changed: bool,
}

/// Correct the file `src`, read as `skeleton` (its kept bytes parsed as
/// `program`) and its cut moves, writing the corrected file to `out` as
/// it goes. Where `options` time the targets by a schedule, `times` are
/// its moments for the skeleton's targets and the cut ones
/// ([`CutTimes`]); at one moment they are not needed. `Ok(None)`: the
/// fast path declines (see the module doc); what it wrote is to be
/// thrown away.
pub fn correct_streamed(
    program: &Program,
    skeleton: &Skeleton,
    src: &[u8],
    warm: &WarmRobot,
    (options, times): (&Options, Option<&CutTimes>),
    out: &mut (dyn Write + Send),
) -> Result<Option<Streamed>> {
    // The skeleton's targets are corrected for the schedule by their own
    // identifiers; the cut ones each for its moment.
    let (skeleton_options, moment, moments) = match (&options.when, times) {
        (When::At(m), _) => (options, *m, None),
        (When::Schedule { .. }, Some(t)) => (&t.options, Moment::Steady, Some(t)),
        (When::Schedule { .. }, None) => return Ok(None),
    };
    if program.files.len() != 1
        || marker::find(program).is_some()
        || skeleton.cuts_before_declarations(program)
    {
        return Ok(None);
    }
    let Ok(findings) = evaluate(program, warm, skeleton_options, &mut |_, _| {}) else {
        return Ok(None);
    };
    let Ok(state) = warm.states().at(moment) else {
        return Ok(None);
    };
    if !said_alike(&findings) {
        return Ok(None);
    }
    let moved = |e: &Edit| Edit {
        span: skeleton.file_offset(e.span.start)..skeleton.file_offset(e.span.end),
        ..e.clone()
    };
    let mut fixed: Vec<Edit> = findings
        .corrections
        .iter()
        .flat_map(|c| c.edits.iter())
        .chain(findings.more.iter().map(|(_, e)| e))
        .map(moved)
        .collect();
    let mut changed = !fixed.is_empty();
    fixed.sort_by_key(|e| (e.span.start, e.span.end));
    let mut tally = Tally::of_skeleton(program, skeleton, &findings);
    let cuts = &skeleton.cuts;
    // The bytes before the first cut move here, with the marker, whose
    // fingerprint of the file (a tenth of a second for a tenth of a
    // gigabyte) is taken while the first batch is corrected; from there
    // on each chunk of moves is written, with the skeleton's edits among
    // them, by the thread that corrects it, up to the next chunk's first
    // move: what is left is putting the chunks' bytes out in order, a
    // batch behind.
    let first = cuts.first().map_or(src.len(), |c| c.start);
    let head = fixed.partition_point(|x| x.span.start < first);
    let mut splice = Splice { src, at: 0, out };
    let put_head = |splice: &mut Splice| -> Result<bool> {
        let basis = match moments {
            Some(t) => t.basis(options),
            None => options.when.basis(),
        };
        let m = marker::for_run(&basis, &options.model_label, options.split_shared, src);
        let mark = marker::insert(program, 0, &m).map(|e| moved(&e));
        // The marker goes into the module's header, before every routine
        // and so before every cut move: anywhere else the whole path
        // writes it.
        if mark.as_ref().is_some_and(|e| e.span.start >= first) {
            return Ok(false);
        }
        let mut edits: Vec<&Edit> = fixed[..head].iter().chain(&mark).collect();
        edits.sort_by_key(|e| (e.span.start, e.span.end));
        for x in edits {
            splice.edit(x)?;
        }
        splice.write(first)?;
        Ok(true)
    };
    // Each batch is put out while the next is corrected: the writing
    // (a tenth of a gigabyte through this thread) keeps no core waiting.
    let mut ready: Vec<Result<Option<Done>>> = Vec::new();
    // The number of the first literal of the next chunk.
    let mut literal = 0;
    for lo in (0..cuts.len()).step_by(BATCH) {
        let hi = (lo + BATCH).min(cuts.len());
        let chunks: Vec<(Range<usize>, Range<usize>)> = (lo..hi)
            .step_by(CHUNK)
            .map(|k| {
                let k = k..(k + CHUNK).min(hi);
                let first = literal;
                literal += skeleton.literals[k.clone()]
                    .iter()
                    .map(|&n| usize::from(n))
                    .sum::<usize>();
                (k, first..literal)
            })
            .collect();
        let previous = std::mem::take(&mut ready);
        let (done, put) = rayon::join(
            || {
                chunks
                    .into_par_iter()
                    .map(|(k, own)| {
                        let to = cuts.get(k.end).map_or(src.len(), |c| c.start);
                        correct_chunk(
                            (program, warm, skeleton_options),
                            (src, skeleton, &fixed),
                            k.clone(),
                            cuts[k.start].start..to,
                            (moment, &state, moments.map(|t| t.moments.get(own))),
                        )
                    })
                    .collect::<Vec<_>>()
            },
            || match lo {
                0 => put_head(&mut splice),
                _ => put_out(&mut *splice.out, previous, &mut tally, &mut changed),
            },
        );
        if !put? {
            return Ok(None);
        }
        ready = done;
    }
    if cuts.is_empty() && !put_head(&mut splice)? {
        return Ok(None);
    }
    if !put_out(&mut *splice.out, ready, &mut tally, &mut changed)? {
        return Ok(None);
    }
    splice.out.flush().map_err(write_error)?;
    let summary = tally.summary(&findings);
    let mut outcome = findings.into_outcome(Vec::new());
    outcome.corrections.clear();
    outcome.summary = summary;
    Ok(Some(Streamed { outcome, changed }))
}

/// Put a batch's corrected chunks out in file order, counting their
/// targets; `false`: one of them declined.
fn put_out(
    out: &mut (dyn Write + Send),
    done: Vec<Result<Option<Done>>>,
    tally: &mut Tally,
    changed: &mut bool,
) -> Result<bool> {
    for d in done {
        let Some(d) = d? else {
            return Ok(false);
        };
        for (at, norm, drift, rewritten) in d.rows {
            tally.add(at, norm, drift, rewritten);
        }
        *changed |= d.changed;
        out.write_all(&d.bytes).map_err(write_error)?;
    }
    Ok(true)
}

/// A chunk of moves corrected and written: the file's bytes of its span
/// with every edit in it, and each target's numbers for the summary.
struct Done {
    bytes: Vec<u8>,
    rows: Vec<(usize, f64, f64, bool)>,
    changed: bool,
}

/// Whether the skeleton's reports read as the whole program's would: the
/// skeleton numbers its inline literals without the cut ones, so a
/// report naming one (`main#3`) or a note is left to the whole path.
fn said_alike(f: &Findings) -> bool {
    let inline = |id: &str| id.contains('#');
    f.notes.is_empty()
        && !f.left_alone.iter().any(|l| inline(&l.id))
        && !f.derived.iter().any(|d| inline(&d.id))
        && !f.residuals.iter().any(|r| inline(&r.id))
        && !f.shared.iter().any(|u| inline(&u.id))
        && !f.splits.iter().any(|s| inline(&s.id))
}

/// A chunk's cut literals' moments in a scheduled run (`Some(None)`: the
/// passes disagree on them); none at one moment.
type CutLiterals<'a> = Option<Option<&'a [Moment]>>;

/// The names of a move's tool and work object as written, and their data.
type LastFrames<'a> = (Vec<u8>, Option<Vec<u8>>, &'a ToolData, &'a WobjData);

/// Correct the cut moves `cuts` of `src` and write the bytes of `span`
/// (from the chunk's first move to the next chunk's) with their new
/// numbers and the skeleton's edits `fixed` that fall in it, in file
/// order; `Ok(None)` when one of the moves needs the whole path (an
/// unknown tool, an unreachable target, a note). Its targets are
/// corrected for `moment` (whose state is `state`), read again from
/// `src`; or, given the whole program the first pass read and the
/// chunk's `literals` (each's moment and target there), each for its own
/// moment (no literals: the passes disagree on them).
fn correct_chunk(
    (program, warm, options): (&Program, &WarmRobot, &Options),
    (src, skeleton, fixed): (&[u8], &Skeleton, &[Edit]),
    cuts: Range<usize>,
    span: Range<usize>,
    (moment, state, literals): (Moment, &State, CutLiterals),
) -> Result<Option<Done>> {
    let Ok(run) = Run::new(program, warm, options) else {
        return Ok(None);
    };
    let lo = fixed.partition_point(|x| x.span.start < span.start);
    let hi = fixed.partition_point(|x| x.span.start < span.end);
    let mut fixed = fixed[lo..hi].iter().peekable();
    let mut bytes = Vec::with_capacity(span.len() + span.len() / 8);
    let mut rows = Vec::with_capacity(cuts.len());
    let mut changed = false;
    let mut splice = Splice {
        src,
        at: span.start,
        out: &mut bytes,
    };
    // One target and one meaning, their numbers replaced move by move.
    let mut target = Target {
        id: String::new(),
        kind: TargetKind::Inline,
        origin: Origin {
            file: 0,
            module: Arc::from(""),
            routine: None,
            pos: Pos {
                offset: 0,
                line: 0,
                col: 0,
            },
        },
        name: None,
        storage: None,
        value: None,
        instruction: None,
        tool: None,
        wobj: None,
        derived: None,
    };
    let mut meant = Meant {
        pose: Isometry3::identity(),
        conf: RobConf::default(),
        evaluated: None,
        moments: vec![moment],
        moment,
        state: *state,
    };
    // Where a number's new text is formatted (three million of them).
    let mut text = String::with_capacity(24);
    // One target at `at` (a file offset in its literal, for the summary's
    // order), for its own moment where it has one; `None`: declined.
    let mut correct_one = |at: usize,
                           value: RobTargetValue,
                           frames: (&ToolData, &WobjData),
                           own: Option<Moment>|
     -> Result<Option<()>> {
        // Consecutive moves share no moment, but a target visited by a
        // loop's turns may: its state is worked out once.
        if let Some(m) = own.filter(|&m| m != meant.moment) {
            let Ok(s) = run.states.at(m) else {
                return Ok(None);
            };
            meant.state = s;
            meant.moment = m;
            meant.moments[0] = m;
        }
        target.origin.pos.offset = at;
        target.value = Some(value);
        let Ok(Some((pose, conf))) = target_pose(program, &target) else {
            return Ok(None);
        };
        meant.pose = pose;
        meant.conf = conf;
        let Ok(c) = corrected_numbers(&run, &target, &meant, frames, None) else {
            return Ok(None);
        };
        let Some(value) = &target.value else {
            return Ok(None);
        };
        // The numbers that change, written as they come, with the
        // skeleton's edits before them: the same text as the whole path's
        // edits ([`robtarget_edits`] makes them this way).
        let mut rewritten = false;
        let mut written = Ok(());
        let new = (c.exact.translation.vector.into(), c.turned, None);
        robtarget_changes(src, value, new, &mut text, &mut |at, new| {
            rewritten = true;
            if written.is_ok() {
                written = splice.put_after(&mut fixed, at, new);
            }
        });
        written?;
        changed |= rewritten;
        let norm = (c.exact.translation.vector - pose.translation.vector).norm();
        rows.push((at, norm, c.drift.norm(), rewritten));
        Ok(Some(()))
    };
    // The frames of the last move, by their names: a CAM program names the
    // same pair a million times, and each lookup lower-cased the names
    // into new strings.
    let mut last: Option<LastFrames> = None;
    let mut frames_of = |tool: &'_ [u8], wobj: Option<&'_ [u8]>| match &last {
        Some((t, w, tool_data, wobj_data)) if t == tool && w.as_deref() == wobj => {
            Some((*tool_data, *wobj_data))
        }
        _ => {
            let frames = frames_named(&run, tool, wobj)?;
            last = Some((tool.to_vec(), wobj.map(<[u8]>::to_vec), frames.0, frames.1));
            Some(frames)
        }
    };
    let mut moments = match literals {
        None => None,
        Some(None) => return Ok(None),
        Some(Some(m)) => Some(m.iter()),
    };
    for k in cuts {
        let Some(m) = skeleton.reread(src, k) else {
            return Ok(None);
        };
        let tool = &src[m.tool.clone()];
        let wobj = m.wobj.clone().map(|w| &src[w]);
        let Some(frames) = frames_of(tool, wobj) else {
            return Ok(None);
        };
        for (at, value) in m.targets {
            let own = match moments.as_mut().map(Iterator::next) {
                None => None,
                Some(Some(&m)) => Some(m),
                Some(None) => return Ok(None),
            };
            if correct_one(at, value, frames, own)?.is_none() {
                return Ok(None);
            }
        }
    }
    for x in fixed {
        splice.edit(x)?;
    }
    splice.write(span.end)?;
    if !run.notes.borrow().is_empty() {
        return Ok(None);
    }
    Ok(Some(Done {
        bytes,
        rows,
        changed,
    }))
}

/// A move's tool and work object by their names as written (`wobj0`
/// where none is).
fn frames_named<'r>(
    run: &'r Run,
    tool: &[u8],
    wobj: Option<&[u8]>,
) -> Option<(&'r ToolData, &'r WobjData)> {
    let tool = run.frames.tool(Some(std::str::from_utf8(tool).ok()?))?;
    let wobj = match wobj {
        Some(w) => run.frames.wobj(Some(std::str::from_utf8(w).ok()?))?,
        None => run.frames.wobj(Some("wobj0"))?,
    };
    Some((tool, wobj))
}

/// The summary's numbers, gathered in the order the whole path sums them
/// (robtargets in source order), so that its RMS is the same to the bit.
struct Tally {
    /// The skeleton's robtarget corrections not yet merged: (file offset,
    /// norm), in order.
    pending: std::vec::IntoIter<(usize, f64)>,
    next: Option<(usize, f64)>,
    norms: Vec<f64>,
    corrected: usize,
    rewritten: usize,
    max_drift: f64,
}

impl Tally {
    fn of_skeleton(program: &Program, skeleton: &Skeleton, f: &Findings) -> Tally {
        let offsets: HashMap<&str, usize> = program
            .targets()
            .iter()
            .map(|t| (t.id.as_str(), skeleton.file_offset(t.origin.pos.offset)))
            .collect();
        let mut pending: Vec<(usize, f64)> = f
            .corrections
            .iter()
            .filter(|c| c.kind.is_robtarget())
            .map(|c| {
                (
                    offsets.get(c.id.as_str()).copied().unwrap_or(usize::MAX),
                    c.correction_norm_mm,
                )
            })
            .collect();
        pending.sort_by_key(|p| p.0);
        let mut pending = pending.into_iter();
        let next = pending.next();
        Tally {
            pending,
            next,
            norms: Vec::new(),
            corrected: f.corrections.len(),
            rewritten: f.corrections.iter().filter(|c| c.rewritten).count(),
            max_drift: f
                .corrections
                .iter()
                .map(|c| c.drift_norm_mm)
                .fold(0.0, f64::max),
        }
    }

    fn add(&mut self, at: usize, norm: f64, drift: f64, rewritten: bool) {
        while let Some((_, n)) = self.next.filter(|(o, _)| *o < at) {
            self.norms.push(n);
            self.next = self.pending.next();
        }
        self.norms.push(norm);
        self.corrected += 1;
        self.rewritten += usize::from(rewritten);
        self.max_drift = self.max_drift.max(drift);
    }

    fn summary(mut self, f: &Findings) -> Summary {
        while let Some((_, n)) = self.next {
            self.norms.push(n);
            self.next = self.pending.next();
        }
        let n = self.norms.len();
        let sum_sq: f64 = self.norms.iter().map(|c| c.powi(2)).sum();
        Summary {
            corrected: self.corrected,
            rewritten: self.rewritten,
            max_mm: self.norms.iter().copied().fold(0.0, f64::max),
            rms_mm: if n > 0 {
                (sum_sq / n as f64).sqrt()
            } else {
                0.0
            },
            max_drift_mm: self.max_drift,
            derived: f.derived.len(),
            left_alone: f.left_alone.len(),
            shared: f.shared.len(),
            split: f.splits.len(),
        }
    }
}

/// The file's bytes with edits spliced in, written as they come (edits in
/// order, each checked against the bytes it replaces, as
/// [`apply_edits`](crate::rapid::rewrite::apply_edits) checks them).
struct Splice<'a> {
    src: &'a [u8],
    at: usize,
    out: &'a mut (dyn Write + Send),
}

impl Splice<'_> {
    fn edit(&mut self, e: &Edit) -> Result<()> {
        let old = self.src.get(e.span.clone());
        if e.span.start < self.at || old != Some(e.expected_old.as_slice()) {
            return Err(Error::input(format!(
                "internal: a streamed edit at byte {} does not fit the file",
                e.span.start
            )));
        }
        self.write(e.span.start)?;
        self.out.write_all(&e.new).map_err(write_error)?;
        self.at = e.span.end;
        Ok(())
    }

    /// A number's new text over `span` of the file, after the edits of
    /// `fixed` that come before it.
    fn put_after<'e>(
        &mut self,
        fixed: &mut std::iter::Peekable<impl Iterator<Item = &'e Edit>>,
        span: Range<usize>,
        new: &[u8],
    ) -> Result<()> {
        while let Some(x) = fixed.next_if(|x| x.span.start < span.start) {
            self.edit(x)?;
        }
        self.put(span, new)
    }

    /// A number's new text over `span` of the file.
    fn put(&mut self, span: Range<usize>, new: &[u8]) -> Result<()> {
        if span.start < self.at || span.end > self.src.len() {
            return Err(Error::input(format!(
                "internal: a streamed number at byte {} does not fit the file",
                span.start
            )));
        }
        self.write(span.start)?;
        self.out.write_all(new).map_err(write_error)?;
        self.at = span.end;
        Ok(())
    }

    fn write(&mut self, to: usize) -> Result<()> {
        self.out
            .write_all(&self.src[self.at..to])
            .map_err(write_error)?;
        self.at = to;
        Ok(())
    }
}

fn write_error(e: std::io::Error) -> Error {
    Error::new(
        crate::error::ErrorKind::Io,
        format!("writing the corrected program: {e}"),
    )
}
