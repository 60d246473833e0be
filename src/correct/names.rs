//! Where a program's names are declared and read, for a split of its
//! shared targets: how many declarations each name has, where each
//! declared robtarget is declared, where moves name it, and its first
//! other reading.

use crate::rapid::visit::{walk_call, walk_data_decl, walk_expr, walk_routine, Visit};
use crate::rapid::{
    Call, DataDecl, DeclBatch, Expr, Module, MoveRef, Program, Routine, Scope, Statement, Storage,
};
use std::collections::HashMap;

/// Where the program's names are declared and read, for the split: built
/// once per run, and only when a split is asked for and some target has
/// several pairs.
#[derive(Default)]
pub(super) struct Names {
    /// Declarations (data and parameters) per lower-case name.
    pub declared: HashMap<String, usize>,
    /// The declaration of each declared robtarget, by target index.
    pub decl_of: HashMap<usize, DeclAt>,
    /// Per (lower-case name, file, statement offset): how many of the
    /// move's targets (ToPoint, CirPoint) name it.
    pub as_target: HashMap<(String, usize, usize), usize>,
    /// The first other reading of each lower-case name, in words.
    pub other: HashMap<String, String>,
}

pub(super) struct DeclAt {
    pub storage: Storage,
    pub scope: Option<Scope>,
    pub offset: usize,
}

impl Names {
    pub fn of(program: &Program) -> Names {
        let mut c = Collect {
            program,
            names: Names::default(),
            file: 0,
            routine: String::new(),
            line: 0,
            offset: 0,
            passed_to: None,
        };
        c.visit_program(program);
        c.names
    }
}

struct Collect<'p> {
    program: &'p Program,
    names: Names,
    file: usize,
    routine: String,
    line: u32,
    offset: usize,
    /// The procedure whose arguments are being walked.
    passed_to: Option<String>,
}

impl Collect<'_> {
    fn where_(&self) -> String {
        let what = match &self.passed_to {
            Some(p) => format!("passed to {p}"),
            None => "read".to_string(),
        };
        if self.routine.is_empty() {
            format!("{what} in a declaration, line {}", self.line)
        } else {
            format!("{what} in {} line {}", self.routine, self.line)
        }
    }
}

impl<'a> Visit<'a> for Collect<'a> {
    fn program(&self) -> Option<&'a Program> {
        Some(self.program)
    }
    /// The declarations the fast lane read, together.
    fn visit_declarations(&mut self, b: DeclBatch<'a>) {
        for d in b.declarations() {
            *self
                .names
                .declared
                .entry(d.name.to_ascii_lowercase())
                .or_default() += 1;
            if let Some(Expr::Target(i)) = d.init {
                self.names.decl_of.insert(
                    i,
                    DeclAt {
                        storage: d.storage,
                        scope: d.scope,
                        offset: d.pos.offset,
                    },
                );
            }
        }
    }
    /// A move the fast lane read: a target named, and the other names
    /// read, as the move's call gives them.
    fn visit_move(&mut self, mv: MoveRef<'a>) {
        self.line = mv.line();
        self.offset = mv.offset();
        if let Some(n) = mv.named() {
            *self
                .names
                .as_target
                .entry((n.to_ascii_lowercase(), self.file, self.offset))
                .or_default() += 1;
        }
        for name in [mv.speed(), mv.zone(), mv.tool(), mv.wobj()]
            .into_iter()
            .flatten()
        {
            let here = self.where_();
            self.names
                .other
                .entry(name.to_ascii_lowercase())
                .or_insert(here);
        }
    }
    fn visit_module(&mut self, m: &'a Module) {
        self.file = m.file;
        self.routine.clear();
        crate::rapid::visit::walk_module(self, m);
    }
    fn visit_data_decl(&mut self, d: &'a DataDecl) {
        *self
            .names
            .declared
            .entry(d.name.to_ascii_lowercase())
            .or_default() += 1;
        if let Some(Expr::Target(i)) = &d.init {
            self.names.decl_of.insert(
                *i,
                DeclAt {
                    storage: d.storage,
                    scope: d.scope,
                    offset: d.pos.offset,
                },
            );
        }
        self.line = d.pos.line;
        walk_data_decl(self, d);
    }
    fn visit_routine(&mut self, r: &'a Routine) {
        for p in &r.params {
            *self
                .names
                .declared
                .entry(p.name.to_ascii_lowercase())
                .or_default() += 1;
        }
        self.routine = r.name.to_string();
        walk_routine(self, r);
    }
    fn visit_statement(&mut self, s: &'a Statement) {
        self.line = s.pos.line;
        self.offset = s.pos.offset;
        crate::rapid::visit::walk_statement(self, s);
    }
    fn visit_call(&mut self, c: &'a Call) {
        let Some(m) = c.motion() else {
            let outer = self.passed_to.replace(c.name.to_string());
            walk_call(self, c);
            self.passed_to = outer;
            return;
        };
        let targets: Vec<&Expr> = [m.via, m.to].into_iter().flatten().collect();
        for e in &targets {
            if let Expr::Name(n) = e {
                *self
                    .names
                    .as_target
                    .entry((n.to_ascii_lowercase(), self.file, self.offset))
                    .or_default() += 1;
            }
        }
        // Every other argument is a reading (a target named as the tool
        // would be one, too).
        for v in c.args.iter().filter_map(|a| a.value.as_ref()) {
            let counted = matches!(v, Expr::Name(_)) && targets.iter().any(|t| std::ptr::eq(*t, v));
            if !counted {
                self.visit_expr(v);
            }
        }
    }
    fn visit_expr(&mut self, e: &'a Expr) {
        match e {
            Expr::Name(n) => {
                let here = self.where_();
                self.names
                    .other
                    .entry(n.to_ascii_lowercase())
                    .or_insert(here);
            }
            // A derived expression (`Offs(pHome, 0, 0, 50)`) is filed as a
            // target of its own; the names it reads are read here.
            Expr::Target(i) => {
                let program = self.program;
                if let Some(d) = program
                    .targets()
                    .one_by_one(*i)
                    .and_then(|t| t.derived.as_ref())
                {
                    let here = format!("{} {}", d.expr, self.where_());
                    for b in &d.bases {
                        self.names
                            .other
                            .entry(b.to_ascii_lowercase())
                            .or_insert_with(|| here.clone());
                    }
                }
            }
            _ => {}
        }
        walk_expr(self, e);
    }
}
