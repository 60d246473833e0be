//! The pass over a file's robtargets in file order, a chunk at a time on
//! every core: each target solved, its new numbers written straight into
//! the chunk's bytes (the file's bytes from the chunk's first target to
//! the next chunk's, with the edits decided before the pass spliced in
//! where they fall), its report row kept where the run keeps rows (or a
//! derived target needs it), and what the summary adds up of it.

use super::context::Run;
use super::outcome::{Correction, LeftAlone};
use super::solve::{row, written_in_world, Rewrite};
use super::splice::Splice;
use super::target::{correct_robtarget, Solved};
use crate::error::{Error, Result};
use crate::rapid::numprint::NumberPrint;
use crate::rapid::rewrite::{robtarget_changes, Edit};
use crate::rapid::{Target, TargetKind};
use std::collections::{HashMap, HashSet};
use std::ops::Range;

/// What the pass shares between its chunks.
pub(super) struct Pass<'r, 'a> {
    pub run: &'r Run<'a>,
    /// Keep every target's report row (else only those `bases` names).
    pub keep_rows: bool,
    /// Write the file's bytes (else only count what changes).
    pub write: bool,
    /// Targets solved before the pass (moved to with several tools or
    /// work objects): their rows, the original's then its copies'; their
    /// edits are among the edits decided before.
    pub early: &'r HashMap<usize, Vec<Correction>>,
    /// Targets whose rows the derived targets' residuals need.
    pub bases: &'r HashSet<usize>,
    /// Buffers of chunks written out, made again by the next chunks.
    pub buffers: Buffers,
}

/// Chunks' byte and token buffers, handed back once written: a fresh
/// buffer of a megabyte is fresh pages from the system (a million
/// targets' chunks faulted in 300 MB of zeroed pages, 5 % of the run).
#[derive(Default)]
pub(super) struct Buffers(std::sync::Mutex<Vec<Vec<u8>>>);

impl Buffers {
    /// An empty buffer with room for at least `len` bytes.
    fn take(&self, len: usize) -> Vec<u8> {
        let got = self.0.lock().ok().and_then(|mut all| all.pop());
        let mut buf = got.unwrap_or_default();
        buf.clear();
        buf.reserve(len);
        buf
    }

    /// A chunk's buffers, done with.
    pub fn give(&self, done: &mut Done) {
        if let Ok(mut all) = self.0.lock() {
            all.push(std::mem::take(&mut done.bytes));
            all.extend(done.tokens.take());
        }
    }
}

/// What the summary adds up of a correction.
#[derive(Debug, Clone, Copy)]
pub(super) struct Tallied {
    pub norm: f64,
    pub drift: f64,
    pub rewritten: bool,
}

/// One chunk done.
#[derive(Default)]
pub(super) struct Done {
    pub bytes: Vec<u8>,
    /// The tokens of `bytes` for the fingerprint of the file's numbers,
    /// read here, on the chunk's core ([`NumberPrint::tokens_of`]).
    pub tokens: Option<Vec<u8>>,
    pub rows: Vec<Correction>,
    pub tally: Vec<Tallied>,
    pub left: Vec<(usize, LeftAlone)>,
    pub derived: Vec<usize>,
    pub errors: Vec<(usize, Error)>,
    pub steps: usize,
    pub changed: bool,
    /// Where the file's bytes after the chunk's last target start, where
    /// the chunk leaves them to be written straight from the file (the
    /// last chunk of a file: a program's declared targets come first, and
    /// the million moves after them were copied whole into its buffer).
    pub tail_from: Option<usize>,
}

/// The most a last chunk's buffer reserves at once (it grows as needed).
const CHUNK_BYTES_HINT: usize = 1 << 22;

impl Pass<'_, '_> {
    /// Targets `targets` of the file `src`: the bytes of `span` with their
    /// new numbers and the edits of `fixed` that fall in it. `last`: the
    /// file's last chunk, whose span runs to the file's end.
    pub fn chunk(
        &self,
        src: &[u8],
        targets: Range<usize>,
        span: Range<usize>,
        last: bool,
        fixed: &[Edit],
    ) -> Result<Done> {
        let run = self.run;
        let all = run.program.targets();
        let mut done = Done {
            // The last chunk's span runs to the file's end, which it does
            // not copy: room for its targets' share only.
            bytes: match self.write {
                true => {
                    let len = if last {
                        span.len().min(CHUNK_BYTES_HINT)
                    } else {
                        span.len()
                    };
                    self.buffers.take(len + len / 8)
                }
                false => Vec::new(),
            },
            ..Done::default()
        };
        let mut bytes = std::mem::take(&mut done.bytes);
        let lo = fixed.partition_point(|x| x.span.start < span.start);
        let hi = fixed.partition_point(|x| x.span.start < span.end);
        let mut fixed = fixed[lo..hi].iter().peekable();
        let mut sink = std::io::sink();
        let mut splice = Splice {
            src,
            at: span.start,
            out: if self.write {
                &mut bytes as &mut dyn std::io::Write
            } else {
                &mut sink
            },
        };
        // One target made at a time where it is in a run, into this.
        let mut slot = crate::rapid::targets::blank();
        // Where a number's new text is formatted.
        let mut text = String::with_capacity(24);
        for i in targets {
            let t: &Target = match all.one_by_one(i) {
                Some(t) => t,
                None if all.fill(i, &mut slot) => &slot,
                None => {
                    done.errors.push((i, internal(i)));
                    continue;
                }
            };
            if t.kind == TargetKind::Derived && !t.written_with_expressions() {
                done.derived.push(i);
                continue;
            }
            done.steps += 1;
            if let Some(rows) = self.early.get(&i) {
                for r in rows {
                    done.tally.push(tallied(r));
                    if self.keep_rows || self.bases.contains(&i) {
                        done.rows.push(r.clone());
                    }
                }
                continue;
            }
            match correct_robtarget(run, i, t) {
                Ok(Solved::Corrected(found)) => {
                    let n = &found.numbers;
                    let new = n.exact.translation.vector;
                    let mut rewritten = false;
                    let mut written = Ok(());
                    match (&t.value, &found.evaluated) {
                        (Some(value), _) => {
                            let mut put = |at: Range<usize>, new: &[u8]| {
                                rewritten = true;
                                if written.is_ok() {
                                    written = splice.put_after(&mut fixed, at, new);
                                }
                            };
                            robtarget_changes(
                                src,
                                value,
                                new.into(),
                                n.turned,
                                None,
                                &mut text,
                                &mut put,
                            );
                        }
                        (None, Some(e)) => {
                            for edit in e.edits(src, new.into(), n.turned) {
                                rewritten = true;
                                if written.is_ok() {
                                    written = splice
                                        .finish_at(&mut fixed, edit.span.start)
                                        .and_then(|_| splice.edit(&edit));
                                }
                            }
                        }
                        (None, None) => {}
                    }
                    written?;
                    done.changed |= rewritten;
                    let meant = found.meant();
                    done.tally.push(Tallied {
                        norm: (new - found.pose.translation.vector).norm(),
                        drift: n.drift.norm(),
                        rewritten,
                    });
                    if self.keep_rows || self.bases.contains(&i) {
                        let mut r = row(
                            run,
                            t,
                            &meant,
                            found.frames,
                            [&found.names[0], &found.names[1]],
                            n,
                            Rewrite::unkept(rewritten),
                        );
                        if let Some(order) = found.order {
                            r.order = order;
                        }
                        done.rows.push(r);
                    }
                }
                Ok(Solved::LeftAlone(l)) => {
                    let world_mm = written_in_world(run, i, t);
                    done.left.push((i, LeftAlone { world_mm, ..l }));
                }
                Err(e) => done.errors.push((i, e)),
            }
        }
        if last && self.write {
            // The rest of the file is written from it, with its edits,
            // once this chunk's bytes are out.
            done.tail_from = Some(splice.at);
        } else {
            splice.finish_at(&mut fixed, span.end)?;
        }
        if self.write {
            let room = bytes.len() + bytes.len() / 2;
            done.tokens = NumberPrint::tokens_into(&bytes, self.buffers.take(room));
        }
        done.bytes = bytes;
        Ok(done)
    }
}

/// What the summary adds up, added up as the corrections come in (in
/// the report's order): a million targets' tallies were once kept whole
/// until the end, 24 MB for four numbers.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Tally {
    pub corrected: usize,
    pub rewritten: usize,
    pub sum_sq: f64,
    pub max_mm: f64,
    pub max_drift_mm: f64,
}

impl Tally {
    pub fn add(&mut self, t: Tallied) {
        self.corrected += 1;
        self.rewritten += usize::from(t.rewritten);
        self.sum_sq += t.norm.powi(2);
        self.max_mm = self.max_mm.max(t.norm);
        self.max_drift_mm = self.max_drift_mm.max(t.drift);
    }

    /// The root mean square of the corrections added (0 for none).
    pub fn rms_mm(&self) -> f64 {
        if self.corrected > 0 {
            (self.sum_sq / self.corrected as f64).sqrt()
        } else {
            0.0
        }
    }
}

/// What the summary adds up of a report row.
pub(super) fn tallied(r: &Correction) -> Tallied {
    Tallied {
        norm: r.correction_norm_mm,
        drift: r.drift_norm_mm,
        rewritten: r.rewritten,
    }
}

fn internal(i: usize) -> Error {
    Error::input(format!(
        "internal: target {i} of the program does not read again"
    ))
}
