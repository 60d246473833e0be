//! FOR loops in the walk: a loop whose bounds the program fixes runs in
//! full, its variable set in place at each turn; others run once.

use super::value::{Flow, Value};
use super::walker::{Frame, Walker};
use crate::error::{Error, ErrorKind, Remedy, Result};
use crate::rapid::{Block, Expr, Statement};
use crate::schedule::bounds::STEP_BUDGET;

/// A FOR statement's parts: `FOR var FROM from TO to [STEP step] DO
/// body ENDFOR`.
pub(super) struct ForLoop<'p> {
    pub(super) var: &'p str,
    pub(super) from: &'p Expr,
    pub(super) to: &'p Expr,
    pub(super) step: Option<&'p Expr>,
    pub(super) body: &'p Block,
}

impl<'p> Walker<'p> {
    pub(super) fn exec_for(
        &mut self,
        for_loop: ForLoop<'p>,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        let ForLoop {
            var,
            from,
            to,
            step,
            body,
        } = for_loop;
        let key = var.to_ascii_lowercase();
        let a = self.eval(from, frame)?.num();
        let b = self.eval(to, frame)?.num();
        let st = match step {
            Some(e) => self.eval(e, frame)?.num(),
            None => match (a, b) {
                (Some(a), Some(b)) => Some(if b < a { -1.0 } else { 1.0 }),
                _ => None,
            },
        };
        let saved = frame.vars.remove(&key);
        self.rescope();
        let flow = match (a, b, st) {
            (Some(a), Some(b), Some(st)) if st != 0.0 => {
                let mut v = a;
                let mut flow = Flow::Normal;
                let turns = ((b - a) / st).floor() + 1.0;
                let mut first = true;
                while (st > 0.0 && v <= b) || (st < 0.0 && v >= b) {
                    let before = self.steps;
                    self.count_step(frame, s)?;
                    // The loop's variable set in place: a million turns
                    // made a million copies of its name.
                    match frame.vars.get_mut(&key) {
                        Some(slot) => *slot = Value::Num(v),
                        None => {
                            frame.vars.insert(key.clone(), Value::Num(v));
                            self.rescope();
                        }
                    }
                    match self.exec_list(body, frame)? {
                        Flow::Normal => {}
                        other => {
                            flow = other;
                            break;
                        }
                    }
                    // Every turn walks about what the first did: a loop
                    // the budget cannot hold is refused now, not after
                    // minutes.
                    if first {
                        first = false;
                        let left = (self.steps - before) as f64 * (turns - 1.0);
                        if self.steps as f64 + left > STEP_BUDGET as f64 {
                            return Err(Error::new(
                                ErrorKind::Unsupported,
                                format!(
                                    "FOR {var}: {turns} turns of {} statements each would pass the walk's limit of {STEP_BUDGET} statements",
                                    self.steps - before
                                ),
                            )
                            .with_remedy(Remedy::GiveSchedule)
                            .at(self.location(frame, s)));
                        }
                    }
                    v += st;
                }
                flow
            }
            _ => {
                let why = if st == Some(0.0) {
                    "STEP 0"
                } else {
                    "bounds known only at run time"
                };
                self.note(
                    frame,
                    s.pos.line,
                    format!("FOR {var}: {why}, body timed once"),
                );
                frame.vars.insert(key.clone(), Value::Unknown);
                self.rescope();
                self.exec_list(body, frame)?
            }
        };
        frame.vars.remove(&key);
        if let Some(v) = saved {
            frame.vars.insert(key, v);
        }
        self.rescope();
        Ok(flow)
    }
}
