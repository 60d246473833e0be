//! The one view of a program's statements and declarations, whatever the
//! reader holds them as: one by one as the grammar makes them, or in the
//! fast lane's compact runs (`runs`, private to the reader). As
//! `toml_edit` keeps its raw storage behind its accessors and
//! rust-analyzer its compact tree behind typed iterators, every pass
//! outside the reader sees statements through [`Program::statements`]
//! (each one, a move of a run as a [`MoveRef`] that makes its call on
//! demand) or [`Program::items`] (the same, a run's moves given at once,
//! for passes that do a stretch of moves in bulk), and declarations
//! through [`Program::module_data`] (each one) or
//! [`Program::declaration_batches`] (a run's names and targets at once).

use super::build::aggregate_of;
use super::program::Program;
use super::runs::{DeclRun, MoveRef, MoveRun, Runs};
use super::source::Source;
use super::syntax::{Block, DataDecl, Expr, Module, Statement};
use super::values::{Pos, Scope};
use std::borrow::Cow;
use std::ops::Range;

/// One statement of a list, whatever its storage.
#[derive(Clone, Copy)]
pub enum StatementRef<'p> {
    /// A statement held as the grammar makes it.
    Statement(&'p Statement),
    /// A move the fast lane read: its names and targets at hand, its
    /// call made on demand ([`MoveRef::statement`]).
    Move(MoveRef<'p>),
}

impl<'p> StatementRef<'p> {
    /// The statement as the grammar makes it (`None` only where a move's
    /// file no longer reads as it did).
    pub fn statement(&self) -> Option<Cow<'p, Statement>> {
        match self {
            StatementRef::Statement(s) => Some(Cow::Borrowed(*s)),
            StatementRef::Move(m) => m.statement().map(Cow::Owned),
        }
    }
}

/// One item of a list: a statement, or moves the fast lane read one after
/// another, given at once.
#[derive(Clone, Copy)]
pub enum Listed<'p> {
    Statement(&'p Statement),
    Batch(MoveBatch<'p>),
}

/// The items of a list ([`Program::items`]).
pub struct Items<'p> {
    program: &'p Program,
    list: &'p Block,
    /// The next run, and the next statement held one by one.
    run: usize,
    stmt: usize,
}

impl<'p> Iterator for Items<'p> {
    type Item = Listed<'p>;
    fn next(&mut self) -> Option<Listed<'p>> {
        loop {
            if let Some(&(before, r)) = self.list.runs.get(self.run) {
                // A run after the statements before it, before the next.
                if before <= self.stmt {
                    self.run += 1;
                    match self.program.batch(r) {
                        Some(b) => return Some(Listed::Batch(b)),
                        None => continue,
                    }
                }
            }
            let s = self.list.stmts.get(self.stmt)?;
            self.stmt += 1;
            return Some(Listed::Statement(s));
        }
    }
}

/// Moves one after another in one list of statements of one routine,
/// all of one kind (to literals, or to targets by name), that the reader
/// holds together: for passes that do a stretch of moves at once.
#[derive(Clone, Copy)]
pub struct MoveBatch<'p> {
    runs: &'p Runs,
    sources: &'p [Source],
    run: &'p MoveRun,
    number: usize,
}

impl<'p> MoveBatch<'p> {
    /// Its moves, in order.
    pub fn moves(&self) -> impl ExactSizeIterator<Item = MoveRef<'p>> + 'p {
        let (runs, sources, run) = (self.runs, self.sources, self.run);
        (0..run.items.len()).map(move |m| MoveRef::new(runs, sources, run, m))
    }
    pub fn len(&self) -> usize {
        self.run.items.len()
    }
    pub fn is_empty(&self) -> bool {
        self.run.items.is_empty()
    }
    /// Where its moves start: the file, the first move's offset and the
    /// last's (`None` for a batch of none).
    pub fn span(&self) -> Option<(usize, usize, usize)> {
        let (first, last) = (self.run.items.first()?, self.run.items.last()?);
        Some((self.run.file, first.at as usize, last.at as usize))
    }
    /// Its number among the program's batches (`0..`[`Program::move_batches`]),
    /// for a pass that keeps something per batch.
    pub fn number(&self) -> usize {
        self.number
    }
}

/// Robtarget declarations one after another in one module, alike in
/// scope and storage, that the reader holds together: their names and
/// targets at once.
#[derive(Clone, Copy)]
pub struct DeclBatch<'p> {
    run: &'p DeclRun,
    src: &'p [u8],
}

impl<'p> DeclBatch<'p> {
    pub fn len(&self) -> usize {
        self.run.items.len()
    }
    pub fn is_empty(&self) -> bool {
        self.run.items.is_empty()
    }
    pub fn scope(&self) -> Option<Scope> {
        self.run.scope
    }
    /// The number of the first declaration's target (the others' follow
    /// in order).
    pub fn first_target(&self) -> usize {
        self.run.base
    }
    /// The name of declaration `k`, as written.
    pub fn name(&self, k: usize) -> Option<&'p str> {
        self.run.name_of(self.src, self.run.items.get(k)?)
    }
    /// Each declaration's name as written, with its target's number.
    pub fn names(&self) -> impl Iterator<Item = (&'p str, usize)> + 'p {
        let (run, src) = (self.run, self.src);
        (run.items.iter().enumerate())
            .filter_map(move |(k, item)| Some((run.name_of(src, item)?, run.base + k)))
    }
    /// Each declaration as the grammar makes it.
    pub fn declarations(&self) -> impl Iterator<Item = DataDecl> + 'p {
        let (run, src) = (self.run, self.src);
        (0..run.items.len()).filter_map(move |k| run.declaration(src, k))
    }
}

impl Program {
    /// Every statement of `list` in order, those the fast lane holds in
    /// runs too (nested lists are the statements' own).
    pub fn statements<'p>(&'p self, list: &'p Block) -> impl Iterator<Item = StatementRef<'p>> {
        self.items(list).flat_map(|item| {
            let (one, batch) = match item {
                Listed::Statement(s) => (Some(StatementRef::Statement(s)), None),
                Listed::Batch(b) => (None, Some(b.moves().map(StatementRef::Move))),
            };
            one.into_iter().chain(batch.into_iter().flatten())
        })
    }

    /// [`Program::statements`], the moves the reader holds together given
    /// at once.
    pub fn items<'p>(&'p self, list: &'p Block) -> Items<'p> {
        Items {
            program: self,
            list,
            run: 0,
            stmt: 0,
        }
    }

    /// [`Program::items`] from the statement the list derefs to at `k`
    /// on (a label a GOTO jumps to): moves before it are not given.
    pub fn items_from<'p>(&'p self, list: &'p Block, k: usize) -> Items<'p> {
        Items {
            program: self,
            list,
            run: list.runs.partition_point(|&(before, _)| before <= k),
            stmt: k,
        }
    }

    /// How many batches of moves the program holds
    /// ([`MoveBatch::number`] is below this).
    pub fn move_batches(&self) -> usize {
        self.runs.moves.len()
    }

    fn batch(&self, run: usize) -> Option<MoveBatch<'_>> {
        Some(MoveBatch {
            runs: &self.runs,
            sources: &self.sources,
            run: self.runs.moves.get(run)?,
            number: run,
        })
    }

    /// Every declaration of module `m`'s data in source order, those the
    /// fast lane holds in runs made as the grammar makes them.
    pub fn module_data<'p>(&'p self, m: &'p Module) -> impl Iterator<Item = Cow<'p, DataDecl>> {
        let mut made = (self.declaration_batches(m))
            .flat_map(|b| b.declarations())
            .peekable();
        let mut held = m.data.iter().peekable();
        std::iter::from_fn(move || {
            let made_first = match (held.peek(), made.peek()) {
                (Some(h), Some(d)) => d.pos.offset < h.pos.offset,
                (h, _) => h.is_none(),
            };
            match made_first {
                true => made.next().map(Cow::Owned),
                false => held.next().map(Cow::Borrowed),
            }
        })
    }

    /// The declarations of module `m` the fast lane holds together, batch
    /// by batch in order.
    pub fn declaration_batches<'p>(&'p self, m: &'p Module) -> impl Iterator<Item = DeclBatch<'p>> {
        (m.decl_runs.iter()).filter_map(move |&r| {
            let run = self.runs.decls.get(r)?;
            Some(DeclBatch {
                run,
                src: self.source(run.file),
            })
        })
    }

    /// The value declaration `d` gives, as the grammar makes it: its
    /// initialiser, or the aggregate of targets of an array the fast
    /// lane holds compactly.
    pub fn value_of<'p>(&'p self, d: &'p DataDecl) -> Option<Cow<'p, Expr>> {
        if let Some(e) = &d.init {
            return Some(Cow::Borrowed(e));
        }
        let a = self.runs.arrays.get(d.elements?)?;
        let items = self.elements_of(d)?.map(Expr::Target).collect();
        Some(Cow::Owned(aggregate_of(items, a.span.clone())))
    }

    /// The numbers of the targets of an array of robtarget literals the
    /// fast lane holds compactly (its elements in order), without making
    /// its value; `None` for any other declaration.
    pub fn elements_of(&self, d: &DataDecl) -> Option<Range<usize>> {
        let a = self.runs.arrays.get(d.elements?)?;
        Some(a.base..a.base + a.elements.len())
    }
}

impl StatementRef<'_> {
    /// Where the statement starts.
    pub fn pos(&self) -> Pos {
        match self {
            StatementRef::Statement(s) => s.pos,
            StatementRef::Move(m) => m.pos(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse::{parse_read, Reading};
    use super::super::visit::{walk_module, Visit};
    use super::*;

    const SRC: &str = "MODULE m\n  CONST robtarget pA := [[1,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  CONST robtarget pB := [[2,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  CONST num n := 2;\n  CONST robtarget pS{2} := [\n    [[3,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],\n    [[4,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]];\n  PROC main()\n    MoveL [[5,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n    MoveL [[6,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n    WaitTime 1;\n    MoveL pA, v100, fine, tool0;\n    MoveL pB, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";

    fn read(way: Reading) -> Program {
        parse_read(vec![("m.mod".into(), Source::copied(SRC.as_bytes()))], way).unwrap()
    }

    /// Through the view, the program the lane holds compactly is the one
    /// the grammar holds one by one: every statement, declaration and
    /// value.
    #[test]
    fn the_view_gives_what_the_grammar_holds() {
        let (lane, grammar) = (read(Reading::Lane), read(Reading::Grammar));
        assert!(
            lane.targets().in_runs() == 6,
            "the lane holds the six literals"
        );
        let (l, g) = (&lane.modules[0], &grammar.modules[0]);
        let statements = |p: &Program, b: &Block| -> Vec<String> {
            (p.statements(b))
                .map(|s| format!("{:?}", s.statement().unwrap()))
                .collect()
        };
        let body = statements(&grammar, &g.routines[0].body);
        assert_eq!(body.len(), 5);
        assert_eq!(statements(&lane, &l.routines[0].body), body);
        let data = |p: &Program, m: &Module| -> Vec<String> {
            (p.module_data(m))
                .map(|d| format!("{:?} {:?}", d.name, p.value_of(&d)))
                .collect()
        };
        assert_eq!(data(&lane, l), data(&grammar, g));
        assert_eq!(data(&grammar, g).len(), 4);
    }

    /// The visitor goes into the runs: every move and declaration the lane
    /// holds is visited.
    #[test]
    fn the_visitor_visits_what_the_runs_hold() {
        struct Count<'a>(&'a Program, usize, usize);
        impl<'a> Visit<'a> for Count<'a> {
            fn program(&self) -> Option<&'a Program> {
                Some(self.0)
            }
            fn visit_module(&mut self, m: &'a Module) {
                walk_module(self, m);
            }
            fn visit_move(&mut self, _: MoveRef<'a>) {
                self.1 += 1;
            }
            fn visit_declarations(&mut self, b: DeclBatch<'a>) {
                self.2 += b.len();
            }
        }
        let lane = read(Reading::Lane);
        let mut c = Count(&lane, 0, 0);
        c.visit_program(&lane);
        assert_eq!(
            (c.1, c.2),
            (4, 2),
            "four moves and two declarations in runs"
        );
    }
}
