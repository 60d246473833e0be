//! A program with its runs made into what the grammar makes of them:
//! every move a call statement, every declaration a data declaration,
//! every array's value an aggregate of targets, every target in the
//! program's list. What the fast lane reads is held to this (it must be
//! what the grammar reads, `tests/rapid/lane.rs`), and a caller that
//! walks the syntax tree its own way may take it.

use super::program::Program;
use super::syntax::{Block, DataDecl, Routine, StatementKind};
use super::view::Listed;

impl Program {
    /// The program the grammar would have read: runs made into
    /// statements, declarations and targets (see the module doc).
    pub fn expanded(&self) -> Program {
        let mut p = self.clone();
        p.targets = self.targets().iter().map(|t| t.into_owned()).collect();
        p.segments = Vec::new();
        for m in &mut p.modules {
            let mut data: Vec<DataDecl> = Vec::new();
            for b in self.declaration_batches(m) {
                data.extend(b.declarations());
            }
            m.decl_runs.clear();
            data.append(&mut m.data);
            data.sort_by_key(|d| d.pos.offset);
            for d in &mut data {
                expand_decl(self, d);
            }
            m.data = data;
            for r in &mut m.routines {
                expand_routine(self, r);
            }
        }
        p.runs = Default::default();
        p
    }
}

/// An array's value the lane holds made into the grammar's aggregate.
fn expand_decl(program: &Program, d: &mut DataDecl) {
    if d.elements.is_some() {
        d.init = program.value_of(d).map(std::borrow::Cow::into_owned);
        d.elements = None;
    }
}

fn expand_routine(program: &Program, r: &mut Routine) {
    for d in &mut r.data {
        expand_decl(program, d);
    }
    for list in [
        Some(&mut r.body),
        r.backward.as_mut(),
        r.undo.as_mut(),
        r.error.as_mut().map(|(_, s)| s),
    ]
    .into_iter()
    .flatten()
    {
        expand_list(program, list);
    }
}

/// A list of statements with its runs of moves made into calls, nested
/// lists too.
fn expand_list(program: &Program, list: &mut Block) {
    let mut out = Vec::with_capacity(list.len());
    for item in program.items(list) {
        match item {
            Listed::Statement(s) => out.push(s.clone()),
            Listed::Batch(b) => out.extend(b.moves().filter_map(|m| m.statement())),
        }
    }
    for s in &mut out {
        match &mut s.kind {
            StatementKind::If {
                branches,
                otherwise,
            } => {
                for (_, b) in branches {
                    expand_list(program, b);
                }
                if let Some(o) = otherwise {
                    expand_list(program, o);
                }
            }
            StatementKind::For { body, .. } | StatementKind::While { body, .. } => {
                expand_list(program, body);
            }
            StatementKind::Test { cases, default, .. } => {
                for (_, b) in cases {
                    expand_list(program, b);
                }
                if let Some(d) = default {
                    expand_list(program, d);
                }
            }
            _ => {}
        }
    }
    *list = Block::from(out);
}
