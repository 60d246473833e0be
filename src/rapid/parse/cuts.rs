//! The moves a [`Skeleton`] cut out, put back as the statements the whole
//! parse makes of them: a file read as its skeleton parses into the same
//! program as the file (see [`parse_skeleton`](super::parse_skeleton)).
//!
//! A cut move lies between two pieces of the skeleton. The list of
//! statements being assembled when the next piece is met (a statement, or
//! the `ELSE`, `ENDIF`, `ERROR`, `ENDPROC` that closes the list) is the
//! list the move was written in: the assembly's own descent places it, in
//! whatever block it was. For a walk, a run of them is put back unread,
//! as one [`StatementKind::CutMoves`].

use super::*;
use crate::rapid::fastmove::{FastMove, Skeleton};
use std::fmt::Write as _;

/// The cut moves of the file being parsed, in file order.
pub(super) struct CutFeed<'a> {
    skeleton: &'a Skeleton,
    /// The file the moves were cut from.
    file: &'a [u8],
    /// The next move to put back.
    next: usize,
    /// Names met in the cut moves, interned: a CAM program repeats its
    /// instruction, speed, zone, tool and work object a million times.
    names: Vec<(&'a [u8], Arc<str>)>,
    /// Moves read ahead, on every core.
    ahead: std::collections::VecDeque<Option<FastMove>>,
    /// The line of the last move put back (lines of the skeleton are
    /// counted on from it: the moves come in order).
    line: usize,
    /// Whether the moves are put back as runs, unread
    /// ([`StatementKind::CutMoves`]).
    runs: bool,
}

/// Names [`CutFeed`] keeps.
const NAMES: usize = 16;
/// Moves read ahead at once.
const AHEAD: usize = 4096;

impl<'a> CutFeed<'a> {
    /// The cuts of `skeleton`, cut from `file`.
    pub(super) fn new(skeleton: &'a Skeleton, file: &'a [u8], runs: bool) -> CutFeed<'a> {
        CutFeed {
            runs,
            skeleton,
            file,
            next: 0,
            names: Vec::new(),
            ahead: std::collections::VecDeque::new(),
            line: 0,
        }
    }

    /// Cut move `k` (the next) read again with its values; the moves
    /// after it are read ahead in parallel, a batch at a time.
    fn read(&mut self, k: usize) -> Option<FastMove> {
        if self.ahead.is_empty() {
            use rayon::prelude::*;
            let (skeleton, file) = (self.skeleton, self.file);
            let end = (k + AHEAD).min(skeleton.cuts.len());
            let read: Vec<Option<FastMove>> = (k..end)
                .into_par_iter()
                .map(|k| skeleton.reread(file, k))
                .collect();
            self.ahead.extend(read);
        }
        self.ahead.pop_front().flatten()
    }
}

impl FileParser<'_, '_> {
    /// [`pos`](Self::pos) of `place`, a cut move's, found from the last
    /// one's line on (not searched for among a million lines).
    fn cut_pos(&mut self, place: usize) -> Pos {
        let lines = self.lines;
        let Some(feed) = self.cuts.as_mut() else {
            return self.pos(place);
        };
        while feed.line < lines.len() && lines[feed.line] <= place {
            feed.line += 1;
        }
        let line = feed.line.max(1);
        let start = lines.get(line - 1).copied().unwrap_or(0).min(place);
        Pos {
            offset: place,
            line: line as u32,
            col: column(&self.src[start..place]),
        }
    }

    /// The name at `r` of the file the moves were cut from, interned.
    fn cut_name(&mut self, r: &Range<usize>) -> Option<Arc<str>> {
        let feed = self.cuts.as_ref()?;
        let bytes = feed.file.get(r.clone())?;
        if let Some((_, a)) = feed.names.iter().find(|(b, _)| *b == bytes) {
            return Some(a.clone());
        }
        let a = self.b.intern(std::str::from_utf8(bytes).ok()?);
        let feed = self.cuts.as_mut()?;
        if feed.names.len() < NAMES {
            feed.names.push((bytes, a.clone()));
        }
        Some(a)
    }
}

impl FileParser<'_, '_> {
    /// Whether a cut move lies before `limit` (an offset of the skeleton).
    pub(super) fn cut_before(&self, limit: usize) -> bool {
        self.cuts.as_ref().is_some_and(|c| {
            c.next < c.skeleton.cuts.len() && c.skeleton.place_of_cut(c.next) < limit
        })
    }

    /// Every cut move before `limit`, as statements of `out`.
    pub(super) fn put_cuts_back(&mut self, limit: usize, out: &mut Vec<Statement>) -> Result<()> {
        if let Some(feed) = self.cuts.as_mut().filter(|f| f.runs) {
            let (skeleton, first) = (feed.skeleton, feed.next);
            let mut end = first;
            while end < skeleton.cuts.len() && skeleton.place_of_cut(end) < limit {
                end += 1;
            }
            if end > first {
                feed.next = end;
                let literals: usize = skeleton.literals[first..end]
                    .iter()
                    .map(|&n| usize::from(n))
                    .sum();
                let pos = self.cut_pos(skeleton.place_of_cut(first));
                let routine = self.routine.clone().unwrap_or_else(|| Arc::from(""));
                let run = (self.module.clone(), routine.clone());
                if self.b.cut_runs.last() != Some(&run) {
                    self.b.cut_runs.push(run);
                }
                out.push(Statement {
                    pos,
                    kind: StatementKind::CutMoves {
                        cuts: first..end,
                        inline: self.inline_k,
                        prefix: routine,
                    },
                });
                self.inline_k += literals;
            }
            return Ok(());
        }
        while self.cut_before(limit) {
            out.push(self.cut_statement()?);
        }
        Ok(())
    }

    /// The next cut move as the whole parse makes it: its literals the
    /// routine's next inline targets, its names interned, its arguments
    /// those of the call.
    fn cut_statement(&mut self) -> Result<Statement> {
        let Some(feed) = self.cuts.as_mut() else {
            return Err(self.err(0, "internal: no cut moves"));
        };
        let (skeleton, k) = (feed.skeleton, feed.next);
        feed.next += 1;
        let m = feed.read(k);
        let place = skeleton.place_of_cut(k);
        let internal = |s: &Self| s.err(place, "internal: a cut move does not read again");
        let Some(m) = m else {
            return Err(internal(self));
        };
        let cut_at = skeleton.cuts[k].start;
        let (Some(name), Some(speed), Some(zone), Some(tool)) = (
            self.cut_name(&m.instruction),
            self.cut_name(&m.speed),
            self.cut_name(&m.zone),
            self.cut_name(&m.tool),
        ) else {
            return Err(internal(self));
        };
        let wobj = match (&m.wobj_word, &m.wobj) {
            (Some(word), Some(w)) => match (self.cut_name(word), self.cut_name(w)) {
                (Some(word), Some(w)) => Some((word, w)),
                _ => return Err(internal(self)),
            },
            _ => None,
        };
        // The cut move was the last statement of its line: the skeleton
        // keeps everything before it there, so its line and column are
        // the file's.
        let pos = self.cut_pos(place);
        let routine = self.routine.clone().unwrap_or_else(|| Arc::from(""));
        let mut args = Vec::with_capacity(m.targets.len() + 4);
        let mut targets = Vec::with_capacity(m.targets.len());
        for (at, value) in m.targets {
            self.inline_k += 1;
            let mut id = String::with_capacity(routine.len() + 8);
            let _ = write!(id, "{routine}#{}", self.inline_k);
            let t = Target {
                id,
                kind: TargetKind::Inline,
                origin: Origin {
                    file: self.file,
                    module: self.module.clone(),
                    routine: self.routine.clone(),
                    // Names and numbers are ASCII: bytes are columns.
                    pos: Pos {
                        col: pos.col + (at - cut_at) as u32,
                        ..pos
                    },
                },
                name: None,
                storage: None,
                value: Some(value),
                instruction: Some(name.clone()),
                tool: Some(tool.clone()),
                wobj: wobj.as_ref().map(|w| w.1.clone()),
                derived: None,
            };
            let i = self.push_target(t);
            targets.push(i);
            args.push(Arg {
                optional: false,
                name: None,
                value: Some(Expr::Target(i)),
            });
        }
        for n in [speed, zone] {
            args.push(Arg {
                optional: false,
                name: None,
                value: Some(Expr::Name(n)),
            });
        }
        args.push(Arg {
            optional: false,
            name: None,
            value: Some(Expr::Name(tool)),
        });
        if let Some((word, w)) = wobj {
            args.push(Arg {
                optional: true,
                name: Some(word),
                value: Some(Expr::Name(w)),
            });
        }
        Ok(Statement {
            pos,
            kind: StatementKind::Call(Call {
                name,
                late_bound: false,
                args,
                targets,
                jointtargets: Vec::new(),
            }),
        })
    }

    /// Every cut move was put back where the skeleton's blocks place it.
    pub(super) fn all_cuts_back(&self) -> Result<()> {
        match &self.cuts {
            Some(c) if c.next < c.skeleton.cuts.len() => {
                let place = c.skeleton.place_of_cut(c.next);
                Err(self.err(place, "internal: a cut move outside every routine"))
            }
            _ => Ok(()),
        }
    }
}
