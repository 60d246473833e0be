//! Statements: assignment, IF (and its one-line form), FOR, WHILE, TEST,
//! RETURN, EXIT, calls of PROCs, of the few built-in instructions the
//! module and a cell's program use, and of move instructions (whose
//! targets are evaluated and kept, the robot's moving being no business
//! of the interpreter's).

use super::place::Slot;
use super::state::{Flow, Interp, Moved};
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::{motion_signature, Block, Call, RoutineKind, Statement, StatementKind};

/// Instructions that change nothing the interpreter models: run as no
/// operation (their arguments are not evaluated).
const NO_EFFECT: &[&str] = &[
    "TPErase", "WaitTime", "Stop", "Break", "ConfL", "ConfJ", "SingArea", "AccSet", "VelSet",
];

impl Interp {
    pub(super) fn exec_block(&mut self, file: usize, body: &Block) -> Result<Flow> {
        // Every statement, the moves the reader holds in runs made as the
        // grammar makes them.
        let program = self.program.clone();
        for s in program.statements(body) {
            let Some(s) = s.statement() else {
                return Err(Error::input(
                    "a move whose file no longer reads as it was read",
                ));
            };
            match self.exec_handled(file, &s)? {
                Flow::Normal => {}
                other => return Ok(other),
            }
        }
        Ok(Flow::Normal)
    }

    pub(super) fn exec(&mut self, file: usize, s: &Statement) -> Result<Flow> {
        self.ops.statements += 1;
        self.at = Some((file, s.pos));
        if self.ops.statements - self.call_began > self.step_budget {
            return Err(self.locate(Error::input(format!(
                "the call ran {} statements without ending (a loop that never ends?)",
                self.step_budget
            ))));
        }
        self.exec_kind(file, s).map_err(|e| self.locate(e))
    }

    fn exec_kind(&mut self, file: usize, s: &Statement) -> Result<Flow> {
        match &s.kind {
            StatementKind::Assign { target, value } => {
                let v = self.eval(value)?;
                let p = self.place_of(target)?;
                self.write(&p, v)?;
            }
            StatementKind::If {
                branches,
                otherwise,
            } => {
                for (cond, body) in branches {
                    if self.condition(cond)? {
                        return self.exec_block(file, body);
                    }
                }
                if let Some(body) = otherwise {
                    return self.exec_block(file, body);
                }
            }
            StatementKind::CompactIf { cond, then } => {
                if self.condition(cond)? {
                    return self.exec(file, then);
                }
            }
            StatementKind::For {
                var,
                from,
                to,
                step,
                body,
            } => return self.exec_for(file, var, from, to, step.as_deref(), body),
            StatementKind::While { cond, body } => {
                while self.condition(cond)? {
                    match self.exec_block(file, body)? {
                        Flow::Normal => {}
                        other => return Ok(other),
                    }
                }
            }
            StatementKind::Test {
                value,
                cases,
                default,
            } => {
                let v = self.eval(value)?;
                for (values, body) in cases {
                    for c in values {
                        if self.eval(c)? == v {
                            return self.exec_block(file, body);
                        }
                    }
                }
                if let Some(body) = default {
                    return self.exec_block(file, body);
                }
            }
            StatementKind::Return(e) => {
                let v = match e {
                    Some(e) => Some(self.eval(e)?),
                    None => None,
                };
                return Ok(Flow::Return(v));
            }
            StatementKind::Exit => return Ok(Flow::Exit),
            StatementKind::Raise(n) => return self.exec_raise(n.as_ref()),
            StatementKind::Retry | StatementKind::TryNext
                if self.frames.last().is_some_and(|f| f.handling.is_some()) =>
            {
                return Ok(match s.kind {
                    StatementKind::Retry => Flow::Retry,
                    _ => Flow::TryNext,
                })
            }
            StatementKind::Call(c) => return self.exec_call(c),
            other => {
                let what = format!("{other:?}");
                let word = what.split(['(', ' ', '{']).next().unwrap_or("");
                return Err(self.unsupported(format!("the statement {word}")));
            }
        }
        Ok(Flow::Normal)
    }

    fn condition(&mut self, e: &crate::rapid::Expr) -> Result<bool> {
        let v = self.eval(e)?;
        v.boolean()
            .ok_or_else(|| Error::input(format!("a condition that is a {}", v.kind())))
    }

    fn exec_for(
        &mut self,
        file: usize,
        var: &str,
        from: &crate::rapid::Expr,
        to: &crate::rapid::Expr,
        step: Option<&crate::rapid::Expr>,
        body: &Block,
    ) -> Result<Flow> {
        let num = |v: Value| {
            v.num()
                .ok_or_else(|| Error::input("a FOR bound that is not a num"))
        };
        let from = num(self.eval(from)?)?;
        let to = num(self.eval(to)?)?;
        let step = match step {
            Some(e) => num(self.eval(e)?)?,
            None if to >= from => 1.0,
            None => -1.0,
        };
        if step == 0.0 {
            return Err(Error::input("a FOR loop with STEP 0"));
        }
        let key = var.to_ascii_lowercase();
        // The loop variable is the loop's own: it hides a datum of its
        // name, and is gone after the loop.
        let hidden = self.frame().vars.remove(&key);
        let mut i = from;
        let mut flow = Flow::Normal;
        while (step > 0.0 && i <= to) || (step < 0.0 && i >= to) {
            self.frame()
                .vars
                .insert(key.clone(), Slot::Value(Value::Num(i)));
            match self.exec_block(file, body)? {
                Flow::Normal => {}
                other => {
                    flow = other;
                    break;
                }
            }
            i += step;
        }
        self.frame().vars.remove(&key);
        if let Some(h) = hidden {
            self.frame().vars.insert(key, h);
        }
        Ok(flow)
    }

    fn exec_call(&mut self, c: &Call) -> Result<Flow> {
        if c.late_bound {
            return Err(self.unsupported("a late-bound call"));
        }
        if self.routines.contains_key(&c.name.to_ascii_lowercase()) {
            self.call_routine(&c.name, &c.args, RoutineKind::Proc)?;
            return Ok(Flow::Normal);
        }
        self.ops.builtins += 1;
        if let Some(sig) = motion_signature(&c.name) {
            let positional: Vec<&crate::rapid::Expr> = c.positional().collect();
            let mut targets = Vec::new();
            for &i in sig.robtargets.iter().chain(sig.jointtargets) {
                if let Some(e) = positional.get(i) {
                    targets.push(self.eval(e)?);
                }
            }
            self.command(c, &targets)?;
            self.moves.push(Moved {
                instruction: c.name.to_string(),
                targets,
            });
            return Ok(Flow::Normal);
        }
        if NO_EFFECT.iter().any(|n| n.eq_ignore_ascii_case(&c.name)) {
            return Ok(Flow::Normal);
        }
        if self.instruction(c)? {
            return Ok(Flow::Normal);
        }
        Err(self.unsupported(format!("the instruction `{}`", c.name)))
    }
}
