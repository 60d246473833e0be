//! Whether a statement ends the program whatever the run-time data say:
//! `EXIT`, a call to a procedure that always reaches one, an `IF` whose
//! every branch does. Told from the source alone, without walking.
//!
//! Why: where a condition is known only at run time, a real program's
//! branch that ends it is its error path (`IF errvar=ERR_TP_MAXTIME
//! S_Alarm1;` with `S_Alarm1` stopping the cycle). Taking that branch
//! would time a cycle that stops at its first check and leave every
//! later target "never reached"; the walk takes the branch that carries
//! on instead, and says so.

use super::walker::Walker;
use crate::rapid::{Block, RoutineKind, Statement, StatementKind};

/// How deep the calls are followed: a procedure reached only deeper than
/// this is taken as not ending the program (the walk then takes it).
const ENDS_DEPTH: usize = 16;

impl<'p> Walker<'p> {
    /// Whether `s`, in `module`, certainly ends the program.
    pub(super) fn ends_program(&self, s: &Statement, module: usize) -> bool {
        self.statement_ends(s, module, 0)
    }

    /// Whether a statement list certainly ends the program: one of its
    /// statements does and nothing before it jumps away (a `GOTO` or
    /// `RETURN` before it might).
    pub(super) fn list_ends(&self, list: &Block, module: usize, depth: usize) -> bool {
        // The statements held one by one: a move the fast lane holds in a
        // run neither ends the program nor jumps.
        for s in list.iter() {
            if matches!(
                s.kind,
                StatementKind::Goto(_) | StatementKind::Return(_) | StatementKind::Label(_)
            ) {
                return false;
            }
            if self.statement_ends(s, module, depth) {
                return true;
            }
        }
        false
    }

    fn statement_ends(&self, s: &Statement, module: usize, depth: usize) -> bool {
        if depth > ENDS_DEPTH {
            return false;
        }
        match &s.kind {
            StatementKind::Exit => true,
            StatementKind::Call(call) if !call.late_bound => {
                match self.find_routine(module, &call.name) {
                    Some((m, r)) if r.kind == RoutineKind::Proc => {
                        self.list_ends(&r.body, m, depth + 1)
                    }
                    _ => false,
                }
            }
            StatementKind::If {
                branches,
                otherwise: Some(otherwise),
            } => {
                branches
                    .iter()
                    .all(|(_, body)| self.list_ends(body, module, depth))
                    && self.list_ends(otherwise, module, depth)
            }
            _ => false,
        }
    }
}
