//! The fast lane in the parse: at each statement of a routine and each
//! declaration of a module, the lane reads what it knows before the
//! scanner cuts a piece for pest (`crate::rapid::lane`), and the parse
//! holds it in runs: moves one after another in one list of statements,
//! robtarget declarations one after another in one module, each array's
//! literals. A jointtarget declaration it reads is held as the grammar
//! holds it.

use super::ahead::Kept;
use super::items::{decl_item, in_file, move_item};
use super::*;
use crate::rapid::lane::{Cursor, Decline, Part, Value};
use crate::rapid::runs::{ArrayRun, DeclItem, DeclRun, MoveRun};
use rayon::prelude::*;

impl<'a> FileParser<'a, '_> {
    /// The line of byte `at`.
    fn line_of(&self, at: usize) -> u32 {
        self.lines.partition_point(|&s| s <= at).max(1) as u32
    }

    /// The move the lane reads at the next statement's start, if any,
    /// joined to the run of moves `out` ends with (or starting one).
    pub(super) fn lane_move(&mut self, out: &mut Block) -> Result<bool> {
        if !self.b.lanes {
            return Ok(false);
        }
        // A piece peeked (the first statement after a routine's data) is
        // read again by the lane.
        let at = match self.peeked {
            Some(p) => p.start,
            None => self.scanner.next_start(),
        };
        // Statements are read in routines only; a run of moves belongs to
        // one.
        let Some(routine) = self.routine.clone() else {
            return Ok(false);
        };
        // A move read ahead (on every core) is taken; where none was, the
        // lane reads here, and reads ahead from the move it found.
        let ((item, literals), end) = match self.kept_ahead(at) {
            Some((end, Kept::Move(item, literals))) => {
                self.b.prog.lane.ahead += 1;
                ((item, literals), end)
            }
            _ => {
                let line = self.line_of(at);
                let src = self.src;
                let b = &mut *self.b;
                let read = read_move(src, at, &mut self.seen).and_then(|mv| match mv {
                    Some(mv) => {
                        let mut global = |r: std::ops::Range<usize>| {
                            let name = b.intern(ascii(src, &r));
                            b.run_name(&name).ok_or(Decline::TooManyNames)
                        };
                        Ok(Some((move_item(at, line, &mv, &mut global)?, mv.end)))
                    }
                    None => Ok(None),
                });
                match read {
                    Ok(Some(read)) => {
                        if self.b.ahead {
                            self.ahead.read_from(self.src, self.lines, read.1);
                        }
                        read
                    }
                    Ok(None) => return Ok(false),
                    Err(why) => {
                        self.b.prog.lane.decline(why, self.file, line);
                        return Ok(false);
                    }
                }
            }
        };
        self.b.prog.lane.read += 1;
        // The run the list ends with, if no statement came after it.
        let joins = match out.runs.last() {
            Some(&(before, r)) if before == out.stmts.len() => self
                .b
                .prog
                .runs
                .moves
                .get(r)
                .is_some_and(|run| run.literals == literals)
                .then_some(r),
            _ => None,
        };
        match joins {
            Some(r) => self.b.prog.runs.moves[r].items.push(item),
            None => {
                let r = self.b.prog.runs.moves.len();
                self.b.prog.runs.moves.push(MoveRun {
                    file: self.file,
                    module: self.module.clone(),
                    routine: routine.clone(),
                    prefix: routine,
                    literals,
                    first: u32::try_from(self.inline_k).unwrap_or(u32::MAX),
                    base: 0,
                    items: vec![item],
                });
                out.runs.push((out.stmts.len(), r));
            }
        }
        self.inline_k += usize::from(literals);
        self.peeked = None;
        self.scanner.skip_to(end);
        Ok(true)
    }

    /// What the lane read ahead at `at`, if anything, its names numbered
    /// in the run's table.
    fn kept_ahead(&mut self, at: usize) -> Option<(usize, Kept)> {
        let (src, b) = (self.src, &mut *self.b);
        self.ahead.take(at, |r| {
            let name = b.intern(ascii(src, &r));
            b.run_name(&name)
        })
    }

    /// The declaration the lane reads at the next piece's start of a
    /// module's data, if any: a robtarget joined to the declaration run
    /// open (or starting one), an array as a run of its own, a
    /// jointtarget as the grammar holds it.
    pub(super) fn lane_decl(&mut self, m: &mut Module) -> Result<bool> {
        if !self.b.lanes {
            return Ok(false);
        }
        let at = match self.peeked {
            Some(p) => p.start,
            None => self.scanner.next_start(),
        };
        // A robtarget declaration read ahead is taken.
        if let Some((
            end,
            Kept::Decl {
                item,
                scope,
                storage,
                type_name,
            },
        )) = self.kept_ahead(at)
        {
            let type_name = ascii(self.src, &type_name);
            self.join_decls(item, scope, storage, type_name, m);
            self.b.prog.lane.read += 1;
            self.b.prog.lane.ahead += 1;
            self.peeked = None;
            self.scanner.skip_to(end);
            return Ok(true);
        }
        let line = self.line_of(at);
        let read = read_decl(self.src, at, &mut self.seen).and_then(|d| {
            let Some(d) = d else { return Ok(None) };
            match (&d.value, d.joint) {
                (Value::Literal(lit), false) => self.declared_in_run(at, line, &d, *lit, m),
                (Value::Literal(lit), true) => self.declared_joint_by_lane(at, &d, *lit, m),
                (
                    Value::Array {
                        size,
                        open,
                        close,
                        elements,
                    },
                    _,
                ) => self.declared_array(at, &d, size, *open..*close + 1, elements, m),
            }?;
            Ok(Some(d.end))
        });
        match read {
            Ok(Some(end)) => {
                if self.b.ahead {
                    self.ahead.read_from(self.src, self.lines, end);
                }
                self.b.prog.lane.read += 1;
                self.peeked = None;
                self.scanner.skip_to(end);
                Ok(true)
            }
            Ok(None) => Ok(false),
            Err(why) => {
                self.b.prog.lane.decline(why, self.file, line);
                Ok(false)
            }
        }
    }

    fn declared_in_run(
        &mut self,
        at: usize,
        line: u32,
        d: &LaneDecl,
        lit: usize,
        m: &mut Module,
    ) -> std::result::Result<(), Decline> {
        let item = decl_item(at, line, d, lit)?;
        let type_name = ascii(self.src, &d.type_name);
        self.join_decls(item, d.scope, d.storage, type_name, m);
        Ok(())
    }

    /// A robtarget declaration joined to the declaration run open where
    /// it is alike (else starting one).
    fn join_decls(
        &mut self,
        item: DeclItem,
        scope: Option<Scope>,
        storage: Storage,
        type_name: &str,
        m: &mut Module,
    ) {
        let runs = &mut self.b.prog.runs.decls;
        let open = self.open_decls.filter(|&r| {
            runs.get(r).is_some_and(|run| {
                run.scope == scope && run.storage == storage && &*run.type_name == type_name
            })
        });
        match open {
            Some(r) => runs[r].items.push(item),
            None => {
                let r = runs.len();
                runs.push(DeclRun {
                    file: self.file,
                    module: self.module.clone(),
                    scope,
                    storage,
                    type_name: Arc::from(type_name),
                    base: 0,
                    items: vec![item],
                });
                m.decl_runs.push(r);
                self.open_decls = Some(r);
            }
        }
    }

    fn declared_joint_by_lane(
        &mut self,
        at: usize,
        d: &LaneDecl,
        lit: usize,
        m: &mut Module,
    ) -> std::result::Result<(), Decline> {
        let mut seen = Seen::default();
        let mut c = Cursor {
            s: self.src,
            p: lit,
            values: true,
            lines: false,
            seen: &mut seen,
        };
        // Its numbers' values, read now (the form was checked).
        let Some((_, robax, extax)) = c.jointtarget() else {
            return Err(Decline::At(Part::Value, c.found()));
        };
        let name = ascii(self.src, &d.name);
        let parts = TargetParts::declared(self.place(), self.pos(lit), name, d.storage, false);
        let j = parts.jointtarget(Self::decl_id(name, &[]), (robax, extax));
        self.b.prog.jointtargets.push(j);
        m.data.push(declaration(DeclParts {
            scope: d.scope,
            storage: d.storage,
            type_name: ascii(self.src, &d.type_name),
            name,
            dims: Vec::new(),
            init: Some(Expr::JointTarget(self.b.prog.jointtargets.len() - 1)),
            pos: self.pos(at),
            elements: None,
        }));
        Ok(())
    }

    /// An array the lane read: its size's value and text, its value's
    /// span, each element's `[`.
    fn declared_array(
        &mut self,
        at: usize,
        d: &LaneDecl,
        size: &(usize, std::ops::Range<usize>),
        span: std::ops::Range<usize>,
        elements: &[usize],
        m: &mut Module,
    ) -> std::result::Result<(), Decline> {
        let open = span.start;
        let lines = element_lines(self.src, (open, self.line_of(open)), elements);
        let elements: Vec<u32> = elements
            .par_iter()
            .map(|&e| in_file(e))
            .collect::<std::result::Result<_, _>>()?;
        let name = self.b.intern(ascii(self.src, &d.name));
        let r = self.b.prog.runs.arrays.len();
        self.b.prog.runs.arrays.push(ArrayRun {
            file: self.file,
            module: self.module.clone(),
            routine: self.routine.clone(),
            name: name.clone(),
            prefix: name.clone(),
            storage: d.storage,
            base: 0,
            elements,
            lines,
            span,
        });
        m.data.push(declaration(DeclParts {
            scope: d.scope,
            storage: d.storage,
            type_name: ascii(self.src, &d.type_name),
            name: &name,
            dims: vec![Expr::Num(Number::new(size.0 as f64, size.1.clone()))],
            init: None,
            elements: Some(r),
            pos: self.pos(at),
        }));
        // The array's targets lie between the declarations before it and
        // after: those are another run's.
        self.open_decls = None;
        Ok(())
    }
}

/// The text of `r` of the file (the lane reads ASCII only).
fn ascii<'a>(src: &'a [u8], r: &std::ops::Range<usize>) -> &'a str {
    std::str::from_utf8(&src[r.clone()]).unwrap_or("")
}

/// Elements' lines counted at once: a chunk each on every core.
const LINES_CHUNK: usize = 1 << 14;

/// The line of each element's `[` (`elements`, ascending), counted from
/// the value's `[` at `open` on line `line`: on every core, each chunk of
/// elements from the last element before it (a million elements counted
/// one after another were a fiftieth of a second with a core idle).
fn element_lines(src: &[u8], (open, line): (usize, u32), elements: &[usize]) -> Vec<u32> {
    let mut lines = vec![0u32; elements.len()];
    lines
        .par_chunks_mut(LINES_CHUNK)
        .enumerate()
        .for_each(|(k, out)| {
            let first = k * LINES_CHUNK;
            let mut from = match first {
                0 => open,
                _ => elements[first - 1],
            };
            let mut n = 0u32;
            for (slot, &e) in out.iter_mut().zip(&elements[first..]) {
                n += crate::error::breaks_in(src, from..e) as u32;
                from = e;
                *slot = n;
            }
        });
    // Each chunk's counts start at its own first element: the lines
    // before the chunk added.
    let mut before = line;
    for chunk in lines.chunks_mut(LINES_CHUNK) {
        let own = chunk.last().copied().unwrap_or(0);
        for l in chunk.iter_mut() {
            *l += before;
        }
        before += own;
    }
    lines
}

#[cfg(test)]
mod element_line_tests {
    use super::*;

    #[test]
    fn lines_counted_in_chunks_are_those_counted_in_order() {
        // More elements than a chunk holds, on lines of one, two and no
        // line ends apart.
        let mut src = String::from("[");
        let mut elements = Vec::new();
        for k in 0..3 * LINES_CHUNK + 7 {
            src.push_str(["\n", "\r\n\n", " "][k % 3]);
            elements.push(src.len());
            src.push_str("[1],");
        }
        let bytes = src.as_bytes();
        let mut want = Vec::new();
        let mut line = 5u32;
        let mut from = 0;
        for &e in &elements {
            line += bytes[from..e].iter().filter(|&&b| b == b'\n').count() as u32;
            from = e;
            want.push(line);
        }
        assert_eq!(element_lines(bytes, (0, 5), &elements), want);
        // Three line ends every three elements, and one for the last.
        assert_eq!(want.last(), Some(&(5 + 3 * LINES_CHUNK as u32 + 7)));
    }
}
