//! A program with its runs made into what the grammar makes of them:
//! every move a call statement, every declaration a data declaration,
//! every array's value an aggregate of targets, every target in the
//! program's list. What the fast lane reads is held to this (it must be
//! what the grammar reads, `tests/rapid/lane.rs`), and a caller that
//! walks the syntax tree its own way may take it.

use super::program::Program;
use super::syntax::{Aggregate, Expr, Routine, Statement, StatementKind};

impl Program {
    /// The program the grammar would have read: runs made into
    /// statements, declarations and targets (see the module doc).
    pub fn expanded(&self) -> Program {
        let mut p = self.clone();
        p.targets = self.targets().iter().map(|t| t.into_owned()).collect();
        p.segments = Vec::new();
        for m in &mut p.modules {
            let runs = std::mem::take(&mut m.decl_runs);
            let mut data = std::mem::take(&mut m.data);
            for r in runs {
                data.extend(self.declarations(r));
            }
            data.sort_by_key(|d| d.pos.offset);
            for d in &mut data {
                if let Some(init) = &mut d.init {
                    expand_expr(self, init);
                }
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

fn expand_expr(program: &Program, e: &mut Expr) {
    if let Expr::Elements(run) = e {
        let Some(a) = program.runs.arrays.get(*run) else {
            return;
        };
        *e = Expr::Aggregate(Box::new(Aggregate {
            items: program.elements(*run).map(Expr::Target).collect(),
            span: a.span.clone(),
        }));
    }
}

fn expand_routine(program: &Program, r: &mut Routine) {
    for d in &mut r.data {
        if let Some(init) = &mut d.init {
            expand_expr(program, init);
        }
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
fn expand_list(program: &Program, list: &mut Vec<Statement>) {
    let mut out = Vec::with_capacity(list.len());
    for mut s in std::mem::take(list) {
        match &mut s.kind {
            StatementKind::Moves(run) => {
                out.extend(program.moves(*run).filter_map(|m| m.statement()));
                continue;
            }
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
        out.push(s);
    }
    *list = out;
}
