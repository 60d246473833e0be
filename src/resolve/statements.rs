//! Walks of a program's statement lists, nested ones included, for the
//! passes of this layer that look at statements one at a time.

use crate::rapid::visit::{walk_statement, Visit};
use crate::rapid::{self, Block, Call, Expr, Listed, Program, Statement, StatementKind};

/// Every statement of a list of `program`'s, nested ones included, in
/// source order: the statement part of [`rapid::visit`], for passes that
/// look at statements one at a time; moves the fast lane read one after
/// another given at once ([`Listed::Batch`]).
pub fn walk_items<'a>(
    program: &'a Program,
    statements: &'a Block,
    visit: &mut impl FnMut(Listed<'a>),
) {
    Each {
        program: Some(program),
        visit,
    }
    .visit_block(statements);
}

/// [`walk_items`] for passes that look for what a run of the fast lane
/// never holds (a procedure call, an assignment, a function call: a run
/// holds moves to literals and to names): the statements held as the
/// grammar makes them.
pub fn walk_statements<'a>(statements: &'a Block, visit: &mut impl FnMut(&'a Statement)) {
    let mut only = |item: Listed<'a>| {
        if let Listed::Statement(s) = item {
            visit(s);
        }
    };
    Each {
        program: None,
        visit: &mut only,
    }
    .visit_block(statements);
}

struct Each<'a, 'f, F> {
    program: Option<&'a Program>,
    visit: &'f mut F,
}

impl<'a, F: FnMut(Listed<'a>)> Visit<'a> for Each<'a, '_, F> {
    fn program(&self) -> Option<&'a Program> {
        self.program
    }
    fn visit_statement(&mut self, s: &'a Statement) {
        (self.visit)(Listed::Statement(s));
        walk_statement(self, s);
    }
    fn visit_moves(&mut self, b: rapid::MoveBatch<'a>) {
        (self.visit)(Listed::Batch(b));
    }
    // Statements only: no statement is nested in an expression.
    fn visit_expr(&mut self, _: &'a Expr) {}
    fn visit_call(&mut self, _: &'a Call) {}
}

/// Every procedure call in a statement list, nested ones included, with
/// its line.
pub fn walk_calls(statements: &Block, visit: &mut impl FnMut(&Call, u32)) {
    walk_statements(statements, &mut |s| {
        if let StatementKind::Call(call) = &s.kind {
            visit(call, s.pos.line);
        }
    });
}

/// A routine's statement lists: its body, and its backward, undo and
/// error handlers.
pub(super) fn routine_bodies(routine: &rapid::Routine) -> impl Iterator<Item = &Block> {
    [
        Some(&routine.body),
        routine.backward.as_ref(),
        routine.undo.as_ref(),
        routine.error.as_ref().map(|(_, s)| s),
    ]
    .into_iter()
    .flatten()
}
