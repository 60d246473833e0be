//! Statements: a list walked with its GOTOs, and each kind of statement
//! (assignments followed for robtargets, conditions known only at run
//! time taken one way with a note), each counted against the budget.

use super::for_loop::ForLoop;
use super::value::{Flow, Value};
use super::walker::{Frame, Walker};
use crate::error::{Error, ErrorKind, Remedy, Result};
use crate::rapid::{Block, Expr, Listed, Statement, StatementKind};
use crate::schedule::bounds::{STACK_RED_ZONE, STACK_SEGMENT, STEP_BUDGET};

impl<'p> Walker<'p> {
    pub(super) fn exec_list(&mut self, stmts: &'p Block, frame: &mut Frame<'p>) -> Result<Flow> {
        let program = self.program;
        let mut items = program.items(stmts);
        // The statement held one by one being walked (labels are).
        let mut pc = 0;
        while let Some(item) = items.next() {
            let s = match item {
                Listed::Statement(s) => s,
                Listed::Batch(b) => {
                    self.exec_moves(b, frame)?;
                    continue;
                }
            };
            match self.exec(s, frame)? {
                Flow::Normal => pc += 1,
                Flow::Goto(label) => {
                    let at = stmts.iter().position(|s| {
                        matches!(&s.kind, StatementKind::Label(l) if l.eq_ignore_ascii_case(&label))
                    });
                    match at {
                        Some(j) if j > pc => {
                            pc = j;
                            items = program.items_from(stmts, j);
                        }
                        Some(_) => {
                            self.note(
                                frame,
                                s.pos.line,
                                format!("GOTO {label} jumps back: not taken (the loop it makes is timed once)"),
                            );
                            pc += 1;
                        }
                        None => return Ok(Flow::Goto(label)),
                    }
                }
                other => return Ok(other),
            }
        }
        Ok(Flow::Normal)
    }

    /// One statement. Deeply nested programs (blocks in routines in
    /// blocks...) grow the stack on the heap instead of overflowing it.
    pub(super) fn exec(&mut self, s: &'p Statement, frame: &mut Frame<'p>) -> Result<Flow> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_SEGMENT, || self.exec_inner(s, frame))
    }

    pub(super) fn exec_inner(&mut self, s: &'p Statement, frame: &mut Frame<'p>) -> Result<Flow> {
        self.count_step(frame, s)?;
        let line = s.pos.line;
        match &s.kind {
            StatementKind::Call(call) => self.exec_call(call, s, frame),
            StatementKind::Assign { target, value } => self.exec_assign(target, value, frame),
            StatementKind::If {
                branches,
                otherwise,
            } => self.exec_if(branches, otherwise.as_ref(), line, frame),
            StatementKind::CompactIf { cond, then } => {
                self.exec_compact_if(cond, then, line, frame)
            }
            StatementKind::For {
                var,
                from,
                to,
                step,
                body,
            } => {
                let for_loop = ForLoop {
                    var,
                    from,
                    to,
                    step: step.as_deref(),
                    body,
                };
                self.exec_for(for_loop, s, frame)
            }
            StatementKind::While { cond, body } => match self.eval(cond, frame)?.boolean() {
                Some(false) => Ok(Flow::Normal),
                _ => {
                    self.note(frame, line, "WHILE: body timed once");
                    self.exec_list(body, frame)
                }
            },
            StatementKind::Test {
                value,
                cases,
                default,
            } => self.exec_test(value, cases, default.as_ref(), line, frame),
            StatementKind::Goto(label) => Ok(Flow::Goto(label.clone())),
            StatementKind::Return(value) => Ok(Flow::Return(match value {
                Some(e) => self.eval(e, frame)?,
                None => Value::Unknown,
            })),
            StatementKind::Exit => {
                self.note(frame, line, "EXIT: the program ends here");
                Ok(Flow::Exit)
            }
            StatementKind::Raise(_) => {
                self.note(
                    frame,
                    line,
                    "RAISE: error handlers are not walked, carried on",
                );
                Ok(Flow::Normal)
            }
            StatementKind::Label(_)
            | StatementKind::Retry
            | StatementKind::TryNext
            | StatementKind::Connect { .. }
            | StatementKind::Placeholder(_) => Ok(Flow::Normal),
        }
    }

    /// `target := value`: a robtarget or jointtarget followed in the
    /// variable it is assigned to, anything else taken as known only at
    /// run time.
    fn exec_assign(&mut self, target: &Expr, value: &Expr, frame: &mut Frame<'p>) -> Result<Flow> {
        let v = self.eval(value, frame)?;
        if let Some(name) = target.as_name() {
            let key = name.to_ascii_lowercase();
            let local = frame.vars.contains_key(&key)
                || frame
                    .routine
                    .is_some_and(|r| r.data.iter().any(|d| d.name.eq_ignore_ascii_case(name)));
            // Numbers are run-time values; robtargets are followed.
            let v = match v {
                Value::Rob(_) | Value::Joint(_) => v,
                _ => Value::Unknown,
            };
            let new = if local {
                frame.vars.insert(key, v)
            } else {
                self.globals.insert(key, v)
            };
            if new.is_none() {
                self.rescope();
            }
        }
        Ok(Flow::Normal)
    }

    /// IF/ELSEIF/ELSE: the first branch whose condition holds; a
    /// condition known only at run time takes its branch, with a note
    /// (unless the branch ends the program).
    fn exec_if(
        &mut self,
        branches: &'p [(Expr, Block)],
        otherwise: Option<&'p Block>,
        line: u32,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        for (i, (cond, body)) in branches.iter().enumerate() {
            match self.eval(cond, frame)?.boolean() {
                Some(false) => continue,
                Some(true) => return self.exec_list(body, frame),
                None => {
                    let which = if i == 0 {
                        "IF".to_string()
                    } else {
                        format!("ELSEIF #{i}")
                    };
                    if self.list_ends(body, frame.module, 0) {
                        self.note(
                            frame,
                            line,
                            format!(
                                "IF: condition known only at run time; the {which} branch ends the program (EXIT), so the walk takes its condition as false"
                            ),
                        );
                        continue;
                    }
                    self.note(
                        frame,
                        line,
                        format!("IF: condition known only at run time, took the {which} branch"),
                    );
                    return self.exec_list(body, frame);
                }
            }
        }
        match otherwise {
            Some(body) => self.exec_list(body, frame),
            None => Ok(Flow::Normal),
        }
    }

    /// `IF cond statement;`: taken where the condition holds or is known
    /// only at run time (with a note), unless the statement ends the
    /// program.
    fn exec_compact_if(
        &mut self,
        cond: &Expr,
        then: &'p Statement,
        line: u32,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        match self.eval(cond, frame)?.boolean() {
            Some(false) => Ok(Flow::Normal),
            Some(true) => self.exec(then, frame),
            None if self.ends_program(then, frame.module) => {
                self.note(
                        frame,
                        line,
                        "IF: condition known only at run time; the statement ends the program (EXIT), so the walk carries on past it",
                    );
                Ok(Flow::Normal)
            }
            None => {
                self.note(
                    frame,
                    line,
                    "IF: condition known only at run time, statement taken",
                );
                self.exec(then, frame)
            }
        }
    }

    /// TEST: the CASE whose value equals the tested one, else DEFAULT; a
    /// value known only at run time takes the first CASE, with a note.
    fn exec_test(
        &mut self,
        value: &Expr,
        cases: &'p [(Vec<Expr>, Block)],
        default: Option<&'p Block>,
        line: u32,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        let v = self.eval(value, frame)?;
        let mut unknown = v.num().is_none() && v.boolean().is_none();
        if !unknown {
            for (values, body) in cases {
                for e in values {
                    let c = self.eval(e, frame)?;
                    match (&v, &c) {
                        (Value::Num(a), Value::Num(b)) if a == b => {
                            return self.exec_list(body, frame)
                        }
                        (Value::Bool(a), Value::Bool(b)) if a == b => {
                            return self.exec_list(body, frame)
                        }
                        (_, Value::Num(_) | Value::Bool(_)) => {}
                        _ => unknown = true,
                    }
                }
                if unknown {
                    break;
                }
            }
        }
        if unknown {
            self.note(
                frame,
                line,
                "TEST: value known only at run time, took the first CASE",
            );
            return match cases.first() {
                Some((_, body)) => self.exec_list(body, frame),
                None => match default {
                    Some(body) => self.exec_list(body, frame),
                    None => Ok(Flow::Normal),
                },
            };
        }
        match default {
            Some(body) => self.exec_list(body, frame),
            None => Ok(Flow::Normal),
        }
    }

    /// One more statement (or loop turn) walked: refuse walks that would
    /// run for hours.
    pub(super) fn count_step(&mut self, frame: &Frame, s: &Statement) -> Result<()> {
        self.steps += 1;
        if self.steps > STEP_BUDGET {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!("the walk of the program passed {STEP_BUDGET} statements (a loop with a very large count?)"),
            )
            .with_remedy(Remedy::GiveSchedule)
            .at(self.location(frame, s)));
        }
        Ok(())
    }

    pub(super) fn location(&self, frame: &Frame, s: &Statement) -> crate::error::Location {
        let file = self
            .program
            .modules
            .get(frame.module)
            .map(|m| m.file)
            .unwrap_or(0);
        crate::error::Location {
            file: self.program.files.get(file).cloned().unwrap_or_default(),
            line: s.pos.line as usize,
            col: s.pos.col as usize,
            line_text: Box::default(),
        }
    }
}
