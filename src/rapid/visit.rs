//! One traversal of the syntax tree, for every pass that needs to reach
//! nested statements and expressions (as `syn::visit` and
//! `toml_edit::visit` do): override the `visit_*` methods of interest and
//! call the matching `walk_*` function from them to keep descending.
//!
//! The walk goes in source order: a module's data, then its routines; a
//! routine's data, body, BACKWARD, ERROR (its numbers, then its
//! statements) and UNDO; a statement's expressions before its nested
//! blocks, as they are written.
//!
//! The walk is complete: the moves the fast lane holds in runs are
//! visited too, as a batch ([`Visit::visit_moves`]) and one by one
//! ([`Visit::visit_move`], a [`MoveRef`] with the move's names and
//! targets, its call made on demand), in their place among the
//! statements; it reads them through the program the visitor names
//! ([`Visit::program`]). A pass that needs every call as a [`Call`]
//! borrowed from the tree walks [`Program::expanded`], the program as the
//! grammar alone makes it.
//!
//! Context such as the module or routine a statement is in is kept by the
//! visitor itself, set in `visit_module` / `visit_routine` before walking:
//!
//! ```
//! use rapidtherm::rapid::visit::{walk_module, walk_routine, Visit};
//! use rapidtherm::rapid::{self, Call, Module, Routine};
//!
//! /// Every procedure call, with the routine it is in.
//! #[derive(Default)]
//! struct Calls<'a> {
//!     program: Option<&'a rapid::Program>,
//!     routine: &'a str,
//!     found: Vec<(&'a str, &'a str)>,
//! }
//!
//! impl<'a> Visit<'a> for Calls<'a> {
//!     fn program(&self) -> Option<&'a rapid::Program> {
//!         self.program
//!     }
//!     fn visit_routine(&mut self, r: &'a Routine) {
//!         self.routine = &r.name;
//!         walk_routine(self, r);
//!     }
//!     fn visit_call(&mut self, c: &'a Call) {
//!         self.found.push((self.routine, &c.name));
//!     }
//! }
//!
//! let src = b"MODULE m\nPROC main()\nIF TRUE THEN\nMoveL p10, v100, fine, tool0;\nENDIF\nENDPROC\nENDMODULE\n";
//! let program = rapid::parse("m.mod", src)?.expanded();
//! let mut v = Calls {
//!     program: Some(&program),
//!     ..Calls::default()
//! };
//! v.visit_program(&program);
//! assert_eq!(v.found, [("main", "MoveL")]);
//! # Ok::<(), rapidtherm::Error>(())
//! ```

use super::view::{DeclBatch, Listed, MoveBatch};
use super::StatementKind as S;
use super::{
    Arg, Block, Call, DataDecl, Expr, FunctionCall, Module, MoveRef, Program, Routine, Statement,
};

/// A read-only traversal; every method's default descends with the
/// matching `walk_*` function.
pub trait Visit<'a> {
    /// The program the visited tree is of, through which the walk reads
    /// the moves and declarations the fast lane holds compactly; `None`
    /// for a tree being read (whose runs are not yet the program's): the
    /// walk then visits what is held one by one alone.
    fn program(&self) -> Option<&'a Program>;
    fn visit_program(&mut self, p: &'a Program) {
        walk_program(self, p);
    }
    fn visit_module(&mut self, m: &'a Module) {
        walk_module(self, m);
    }
    fn visit_data_decl(&mut self, d: &'a DataDecl) {
        walk_data_decl(self, d);
    }
    /// Robtarget declarations the fast lane read one after another, at
    /// once (after the module's other data): each a literal, no
    /// expression of theirs is held.
    fn visit_declarations(&mut self, _b: DeclBatch<'a>) {}
    fn visit_routine(&mut self, r: &'a Routine) {
        walk_routine(self, r);
    }
    /// A statement list: a routine's body or handler, a branch of a block.
    fn visit_block(&mut self, b: &'a Block) {
        walk_block(self, b);
    }
    /// Moves the fast lane read one after another, at once.
    fn visit_moves(&mut self, b: MoveBatch<'a>) {
        walk_moves(self, b);
    }
    /// One move the fast lane read: no expression of its is held (its
    /// targets are numbers, its other arguments names).
    fn visit_move(&mut self, _m: MoveRef<'a>) {}
    fn visit_statement(&mut self, s: &'a Statement) {
        walk_statement(self, s);
    }
    /// A procedure call statement (MoveL, user PROCs).
    fn visit_call(&mut self, c: &'a Call) {
        walk_call(self, c);
    }
    fn visit_arg(&mut self, a: &'a Arg) {
        walk_arg(self, a);
    }
    fn visit_expr(&mut self, e: &'a Expr) {
        walk_expr(self, e);
    }
    /// A function call inside an expression (`Offs(p10, 0, 0, 50)`).
    fn visit_function_call(&mut self, c: &'a FunctionCall) {
        walk_function_call(self, c);
    }
}

pub fn walk_program<'a, V: Visit<'a> + ?Sized>(v: &mut V, p: &'a Program) {
    for m in &p.modules {
        v.visit_module(m);
    }
}

pub fn walk_module<'a, V: Visit<'a> + ?Sized>(v: &mut V, m: &'a Module) {
    for d in &m.data {
        v.visit_data_decl(d);
    }
    if let Some(p) = v.program() {
        for b in p.declaration_batches(m) {
            v.visit_declarations(b);
        }
    }
    for r in &m.routines {
        v.visit_routine(r);
    }
}

pub fn walk_data_decl<'a, V: Visit<'a> + ?Sized>(v: &mut V, d: &'a DataDecl) {
    for e in &d.dims {
        v.visit_expr(e);
    }
    if let Some(e) = &d.init {
        v.visit_expr(e);
    }
}

pub fn walk_routine<'a, V: Visit<'a> + ?Sized>(v: &mut V, r: &'a Routine) {
    for d in &r.data {
        v.visit_data_decl(d);
    }
    v.visit_block(&r.body);
    if let Some(b) = &r.backward {
        v.visit_block(b);
    }
    if let Some((numbers, b)) = &r.error {
        for e in numbers {
            v.visit_expr(e);
        }
        v.visit_block(b);
    }
    if let Some(b) = &r.undo {
        v.visit_block(b);
    }
}

pub fn walk_block<'a, V: Visit<'a> + ?Sized>(v: &mut V, b: &'a Block) {
    match v.program() {
        Some(p) => {
            for item in p.items(b) {
                match item {
                    Listed::Statement(s) => v.visit_statement(s),
                    Listed::Batch(moves) => v.visit_moves(moves),
                }
            }
        }
        None => {
            for s in b.iter() {
                v.visit_statement(s);
            }
        }
    }
}

pub fn walk_moves<'a, V: Visit<'a> + ?Sized>(v: &mut V, b: MoveBatch<'a>) {
    for m in b.moves() {
        v.visit_move(m);
    }
}

pub fn walk_statement<'a, V: Visit<'a> + ?Sized>(v: &mut V, s: &'a Statement) {
    match &s.kind {
        S::Call(c) => v.visit_call(c),
        S::Assign { target, value } => {
            v.visit_expr(target);
            v.visit_expr(value);
        }
        S::If {
            branches,
            otherwise,
        } => {
            for (c, b) in branches {
                v.visit_expr(c);
                v.visit_block(b);
            }
            if let Some(b) = otherwise {
                v.visit_block(b);
            }
        }
        S::CompactIf { cond, then } => {
            v.visit_expr(cond);
            v.visit_statement(then);
        }
        S::For {
            from,
            to,
            step,
            body,
            ..
        } => {
            v.visit_expr(from);
            v.visit_expr(to);
            if let Some(e) = step {
                v.visit_expr(e);
            }
            v.visit_block(body);
        }
        S::While { cond, body } => {
            v.visit_expr(cond);
            v.visit_block(body);
        }
        S::Test {
            value,
            cases,
            default,
        } => {
            v.visit_expr(value);
            for (values, b) in cases {
                for e in values {
                    v.visit_expr(e);
                }
                v.visit_block(b);
            }
            if let Some(b) = default {
                v.visit_block(b);
            }
        }
        S::Return(Some(e)) | S::Raise(Some(e)) => v.visit_expr(e),
        S::Connect { interrupt, .. } => v.visit_expr(interrupt),
        S::Goto(_)
        | S::Label(_)
        | S::Return(None)
        | S::Raise(None)
        | S::Exit
        | S::Retry
        | S::TryNext
        | S::Placeholder(_) => {}
    }
}

pub fn walk_call<'a, V: Visit<'a> + ?Sized>(v: &mut V, c: &'a Call) {
    for a in &c.args {
        v.visit_arg(a);
    }
}

pub fn walk_arg<'a, V: Visit<'a> + ?Sized>(v: &mut V, a: &'a Arg) {
    if let Some(e) = &a.value {
        v.visit_expr(e);
    }
}

pub fn walk_expr<'a, V: Visit<'a> + ?Sized>(v: &mut V, e: &'a Expr) {
    match e {
        Expr::Component(b) => v.visit_expr(&b.0),
        Expr::Index(b) => {
            v.visit_expr(&b.0);
            for i in &b.1 {
                v.visit_expr(i);
            }
        }
        Expr::Call(c) => v.visit_function_call(c),
        Expr::Aggregate(a) => {
            for x in &a.items {
                v.visit_expr(x);
            }
        }
        Expr::Unary(_, x) => v.visit_expr(x),
        Expr::Binary(b) => {
            v.visit_expr(&b.1);
            v.visit_expr(&b.2);
        }
        Expr::Num(_)
        | Expr::Str(_)
        | Expr::Bool(_)
        | Expr::Placeholder(_)
        | Expr::Name(_)
        | Expr::Target(_)
        | Expr::JointTarget(_) => {}
    }
}

pub fn walk_function_call<'a, V: Visit<'a> + ?Sized>(v: &mut V, c: &'a FunctionCall) {
    for a in &c.args {
        v.visit_arg(a);
    }
}

/// [`Visit`] with mutable access, for passes that rewrite the tree in
/// place (the reader's renumbering of targets once they are sorted).
pub trait VisitMut {
    fn visit_module_mut(&mut self, m: &mut Module) {
        walk_module_mut(self, m);
    }
    fn visit_data_decl_mut(&mut self, d: &mut DataDecl) {
        walk_data_decl_mut(self, d);
    }
    fn visit_routine_mut(&mut self, r: &mut Routine) {
        walk_routine_mut(self, r);
    }
    fn visit_block_mut(&mut self, b: &mut [Statement]) {
        walk_block_mut(self, b);
    }
    fn visit_statement_mut(&mut self, s: &mut Statement) {
        walk_statement_mut(self, s);
    }
    fn visit_call_mut(&mut self, c: &mut Call) {
        walk_call_mut(self, c);
    }
    fn visit_arg_mut(&mut self, a: &mut Arg) {
        walk_arg_mut(self, a);
    }
    fn visit_expr_mut(&mut self, e: &mut Expr) {
        walk_expr_mut(self, e);
    }
    fn visit_function_call_mut(&mut self, c: &mut FunctionCall) {
        walk_function_call_mut(self, c);
    }
}

pub fn walk_module_mut<V: VisitMut + ?Sized>(v: &mut V, m: &mut Module) {
    for d in &mut m.data {
        v.visit_data_decl_mut(d);
    }
    for r in &mut m.routines {
        v.visit_routine_mut(r);
    }
}

pub fn walk_data_decl_mut<V: VisitMut + ?Sized>(v: &mut V, d: &mut DataDecl) {
    for e in &mut d.dims {
        v.visit_expr_mut(e);
    }
    if let Some(e) = &mut d.init {
        v.visit_expr_mut(e);
    }
}

pub fn walk_routine_mut<V: VisitMut + ?Sized>(v: &mut V, r: &mut Routine) {
    for d in &mut r.data {
        v.visit_data_decl_mut(d);
    }
    v.visit_block_mut(&mut r.body);
    if let Some(b) = &mut r.backward {
        v.visit_block_mut(b);
    }
    if let Some((numbers, b)) = &mut r.error {
        for e in numbers {
            v.visit_expr_mut(e);
        }
        v.visit_block_mut(b);
    }
    if let Some(b) = &mut r.undo {
        v.visit_block_mut(b);
    }
}

pub fn walk_block_mut<V: VisitMut + ?Sized>(v: &mut V, b: &mut [Statement]) {
    for s in b {
        v.visit_statement_mut(s);
    }
}

pub fn walk_statement_mut<V: VisitMut + ?Sized>(v: &mut V, s: &mut Statement) {
    match &mut s.kind {
        S::Call(c) => v.visit_call_mut(c),
        S::Assign { target, value } => {
            v.visit_expr_mut(target);
            v.visit_expr_mut(value);
        }
        S::If {
            branches,
            otherwise,
        } => {
            for (c, b) in branches {
                v.visit_expr_mut(c);
                v.visit_block_mut(b);
            }
            if let Some(b) = otherwise {
                v.visit_block_mut(b);
            }
        }
        S::CompactIf { cond, then } => {
            v.visit_expr_mut(cond);
            v.visit_statement_mut(then);
        }
        S::For {
            from,
            to,
            step,
            body,
            ..
        } => {
            v.visit_expr_mut(from);
            v.visit_expr_mut(to);
            if let Some(e) = step {
                v.visit_expr_mut(e);
            }
            v.visit_block_mut(body);
        }
        S::While { cond, body } => {
            v.visit_expr_mut(cond);
            v.visit_block_mut(body);
        }
        S::Test {
            value,
            cases,
            default,
        } => {
            v.visit_expr_mut(value);
            for (values, b) in cases {
                for e in values {
                    v.visit_expr_mut(e);
                }
                v.visit_block_mut(b);
            }
            if let Some(b) = default {
                v.visit_block_mut(b);
            }
        }
        S::Return(Some(e)) | S::Raise(Some(e)) => v.visit_expr_mut(e),
        S::Connect { interrupt, .. } => v.visit_expr_mut(interrupt),
        S::Goto(_)
        | S::Label(_)
        | S::Return(None)
        | S::Raise(None)
        | S::Exit
        | S::Retry
        | S::TryNext
        | S::Placeholder(_) => {}
    }
}

pub fn walk_call_mut<V: VisitMut + ?Sized>(v: &mut V, c: &mut Call) {
    for a in &mut c.args {
        v.visit_arg_mut(a);
    }
}

pub fn walk_arg_mut<V: VisitMut + ?Sized>(v: &mut V, a: &mut Arg) {
    if let Some(e) = &mut a.value {
        v.visit_expr_mut(e);
    }
}

pub fn walk_expr_mut<V: VisitMut + ?Sized>(v: &mut V, e: &mut Expr) {
    match e {
        Expr::Component(b) => v.visit_expr_mut(&mut b.0),
        Expr::Index(b) => {
            v.visit_expr_mut(&mut b.0);
            for i in &mut b.1 {
                v.visit_expr_mut(i);
            }
        }
        Expr::Call(c) => v.visit_function_call_mut(c),
        Expr::Aggregate(a) => {
            for x in &mut a.items {
                v.visit_expr_mut(x);
            }
        }
        Expr::Unary(_, x) => v.visit_expr_mut(x),
        Expr::Binary(b) => {
            v.visit_expr_mut(&mut b.1);
            v.visit_expr_mut(&mut b.2);
        }
        Expr::Num(_)
        | Expr::Str(_)
        | Expr::Bool(_)
        | Expr::Placeholder(_)
        | Expr::Name(_)
        | Expr::Target(_)
        | Expr::JointTarget(_) => {}
    }
}

pub fn walk_function_call_mut<V: VisitMut + ?Sized>(v: &mut V, c: &mut FunctionCall) {
    for a in &mut c.args {
        v.visit_arg_mut(a);
    }
}
