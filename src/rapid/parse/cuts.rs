//! The moves a [`Skeleton`] cut out, put back as the statements the whole
//! parse makes of them: a file read as its skeleton parses into the same
//! program as the file (see [`parse_skeleton`](super::parse_skeleton)).
//!
//! A cut move lies between two pieces of the skeleton. The list of
//! statements being assembled when the next piece is met (a statement, or
//! the `ELSE`, `ENDIF`, `ERROR`, `ENDPROC` that closes the list) is the
//! list the move was written in: the assembly's own descent places it, in
//! whatever block it was.

use super::*;
use crate::rapid::fastmove::Skeleton;

/// The cut moves of the file being parsed, in file order.
pub(super) struct CutFeed<'a> {
    pub(super) skeleton: &'a Skeleton,
    /// The file the moves were cut from.
    pub(super) file: &'a [u8],
    /// The next move to put back.
    pub(super) next: usize,
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
        let (skeleton, file, k) = (feed.skeleton, feed.file, feed.next);
        feed.next += 1;
        let place = skeleton.place_of_cut(k);
        let internal = |s: &Self| s.err(place, "internal: a cut move does not read again");
        let Some(m) = skeleton.reread(file, k) else {
            return Err(internal(self));
        };
        let cut_at = skeleton.cuts[k].start;
        let text = |r: &Range<usize>| std::str::from_utf8(&file[r.clone()]).ok();
        let (Some(name), Some(speed), Some(zone), Some(tool)) = (
            text(&m.instruction),
            text(&m.speed),
            text(&m.zone),
            text(&m.tool),
        ) else {
            return Err(internal(self));
        };
        let wobj = match (&m.wobj_word, &m.wobj) {
            (Some(word), Some(w)) => match (text(word), text(w)) {
                (Some(word), Some(w)) => Some((self.b.intern(word), self.b.intern(w))),
                _ => return Err(internal(self)),
            },
            _ => None,
        };
        let name = self.b.intern(name);
        let tool = self.b.intern(tool);
        // The cut move was the last statement of its line: the skeleton
        // keeps everything before it there, so its line and column are
        // the file's.
        let pos = self.pos(place);
        let routine = self.routine.clone().unwrap_or_else(|| Arc::from(""));
        let mut args = Vec::with_capacity(m.targets.len() + 4);
        let mut targets = Vec::with_capacity(m.targets.len());
        for (at, value) in m.targets {
            self.inline_k += 1;
            let mut t = self.new_target(
                format!("{routine}#{}", self.inline_k),
                TargetKind::Inline,
                place,
                Some(value),
            );
            // Names and numbers are ASCII: bytes are columns.
            t.origin.pos.col += (at - cut_at) as u32;
            t.instruction = Some(name.clone());
            t.tool = Some(tool.clone());
            t.wobj = wobj.as_ref().map(|w| w.1.clone());
            let i = self.push_target(t);
            targets.push(i);
            args.push(Arg {
                optional: false,
                name: None,
                value: Some(Expr::Target(i)),
            });
        }
        for n in [speed, zone] {
            let n = self.b.intern(n);
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
