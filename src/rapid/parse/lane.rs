//! The fast lane in the parse: at each statement of a routine and each
//! declaration of a module, the lane reads what it knows before the
//! scanner cuts a piece for pest (`crate::rapid::lane`), and the parse
//! holds it in runs: moves one after another in one list of statements,
//! robtarget declarations one after another in one module, each array's
//! literals. A jointtarget declaration it reads is held as the grammar
//! holds it.

use super::*;
use crate::rapid::lane::{Cursor, Value};
use crate::rapid::runs::{ArrayRun, DeclItem, DeclRun, MoveItem, MoveRun, NONE};

impl<'a> FileParser<'a, '_> {
    /// The line of byte `at`.
    fn line_of(&self, at: usize) -> u32 {
        self.lines.partition_point(|&s| s <= at).max(1) as u32
    }

    /// The text of `r` of the file (the lane reads ASCII only).
    fn ascii(&self, r: &std::ops::Range<usize>) -> &'a str {
        std::str::from_utf8(&self.src[r.clone()]).unwrap_or("")
    }

    /// The move the lane reads at the next statement's start, if any,
    /// joined to the run of moves `out` ends with (or starting one).
    pub(super) fn lane_move(&mut self, out: &mut Vec<Statement>) -> Result<bool> {
        if !self.b.lanes {
            return Ok(false);
        }
        // A piece peeked (the first statement after a routine's data) is
        // read again by the lane.
        let at = match self.peeked {
            Some(p) => p.start,
            None => self.scanner.next_start(),
        };
        let Some(mv) = read_move(self.src, at, &mut self.seen) else {
            return Ok(false);
        };
        let Some((item, literals)) = self.move_item(at, &mv) else {
            return Ok(false);
        };
        let Some(routine) = self.routine.clone() else {
            return Ok(false);
        };
        let joins = match out.last().map(|s| &s.kind) {
            Some(StatementKind::Moves(r)) => self
                .b
                .prog
                .runs
                .moves
                .get(*r)
                .is_some_and(|run| run.literals == literals)
                .then_some(*r),
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
                out.push(Statement {
                    pos: self.pos(at),
                    kind: StatementKind::Moves(r),
                });
            }
        }
        self.inline_k += usize::from(literals);
        self.peeked = None;
        self.scanner.skip_to(mv.end);
        Ok(true)
    }

    /// A move the lane read, as a run holds it; `None` where it cannot
    /// (a statement too long, too many names).
    fn move_item(&mut self, at: usize, mv: &LaneMove) -> Option<(MoveItem, u8)> {
        let rel = |x: usize| u16::try_from(x.checked_sub(at)?).ok();
        let (literals, parts) = match &mv.named {
            Some(n) => (0, [rel(n.start)?, u16::try_from(n.len()).ok()?]),
            None => {
                let mut parts = [0u16; 2];
                for (p, &l) in parts.iter_mut().zip(&mv.literals) {
                    *p = rel(l)?;
                }
                (u8::try_from(mv.literals.len()).ok()?, parts)
            }
        };
        let mut names = [NONE; 6];
        let wobj = mv.wobj.clone();
        let ranges = [
            Some(mv.instruction.clone()),
            Some(mv.speed.clone()),
            Some(mv.zone.clone()),
            Some(mv.tool.clone()),
            wobj.as_ref().map(|w| w.0.clone()),
            wobj.map(|w| w.1),
        ];
        for (slot, r) in names.iter_mut().zip(ranges) {
            if let Some(r) = r {
                let name = self.b.intern(self.ascii(&r));
                *slot = self.b.run_name(&name)?;
            }
        }
        let item = MoveItem {
            at: u32::try_from(at).ok()?,
            line: self.line_of(at),
            names,
            parts,
        };
        Some((item, literals))
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
        let Some(d) = read_decl(self.src, at, &mut self.seen) else {
            return Ok(false);
        };
        let read = match (&d.value, d.joint) {
            (Value::Literal(lit), false) => self.declared_in_run(at, &d, *lit, m),
            (Value::Literal(lit), true) => self.declared_joint_by_lane(at, &d, *lit, m),
            (Value::Array { .. }, _) => self.declared_array(at, &d, m),
        };
        if read.is_some() {
            self.peeked = None;
            self.scanner.skip_to(d.end);
        }
        Ok(read.is_some())
    }

    fn declared_in_run(
        &mut self,
        at: usize,
        d: &LaneDecl,
        lit: usize,
        m: &mut Module,
    ) -> Option<()> {
        let rel = |x: usize| u16::try_from(x.checked_sub(at)?).ok();
        let item = DeclItem {
            at: u32::try_from(at).ok()?,
            line: self.line_of(at),
            name: (rel(d.name.start)?, u8::try_from(d.name.len()).ok()?),
            literal: rel(lit)?,
            qualified: false,
        };
        let type_name = self.ascii(&d.type_name);
        let runs = &mut self.b.prog.runs.decls;
        let open = self.open_decls.filter(|&r| {
            runs.get(r).is_some_and(|run| {
                run.scope == d.scope && run.storage == d.storage && &*run.type_name == type_name
            })
        });
        match open {
            Some(r) => runs[r].items.push(item),
            None => {
                let r = runs.len();
                runs.push(DeclRun {
                    file: self.file,
                    module: self.module.clone(),
                    scope: d.scope,
                    storage: d.storage,
                    type_name: Arc::from(type_name),
                    base: 0,
                    items: vec![item],
                });
                m.decl_runs.push(r);
                self.open_decls = Some(r);
            }
        }
        Some(())
    }

    fn declared_joint_by_lane(
        &mut self,
        at: usize,
        d: &LaneDecl,
        lit: usize,
        m: &mut Module,
    ) -> Option<()> {
        let mut seen = Seen::default();
        let mut c = Cursor {
            s: self.src,
            p: lit,
            values: true,
            lines: false,
            seen: &mut seen,
        };
        let (_, robax, extax) = c.jointtarget()?;
        let name = self.ascii(&d.name).to_string();
        let j = JointTarget {
            id: name.clone(),
            kind: TargetKind::Declared,
            origin: self.origin(lit),
            name: Some(name.clone()),
            storage: Some(d.storage),
            robax,
            extax,
            instruction: None,
            tool: None,
            wobj: None,
        };
        self.b.prog.jointtargets.push(j);
        m.data.push(DataDecl {
            scope: d.scope,
            storage: d.storage,
            type_name: self.ascii(&d.type_name).to_string(),
            name,
            dims: Vec::new(),
            init: Some(Expr::JointTarget(self.b.prog.jointtargets.len() - 1)),
            pos: self.pos(at),
        });
        Some(())
    }

    fn declared_array(&mut self, at: usize, d: &LaneDecl, m: &mut Module) -> Option<()> {
        let Value::Array {
            size,
            open,
            close,
            elements,
        } = &d.value
        else {
            return None;
        };
        let mut lines = Vec::with_capacity(elements.len());
        let mut line = self.line_of(*open);
        let mut from = *open;
        for &e in elements {
            line += memchr::memchr_iter(b'\n', &self.src[from..e]).count() as u32;
            from = e;
            lines.push(line);
        }
        let elements: Vec<u32> = elements
            .iter()
            .map(|&e| u32::try_from(e).ok())
            .collect::<Option<_>>()?;
        let name = self.b.intern(self.ascii(&d.name));
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
            span: *open..*close + 1,
        });
        m.data.push(DataDecl {
            scope: d.scope,
            storage: d.storage,
            type_name: self.ascii(&d.type_name).to_string(),
            name: name.to_string(),
            dims: vec![Expr::Num(Number::new(size.0 as f64, size.1.clone()))],
            init: Some(Expr::Elements(r)),
            pos: self.pos(at),
        });
        // The array's targets lie between the declarations before it and
        // after: those are another run's.
        self.open_decls = None;
        Some(())
    }
}
