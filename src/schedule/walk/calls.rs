//! Calls: routines of the program found, their arguments bound and
//! their bodies walked, and the instructions that take time without
//! moving (waits, synchronisation, VelSet).

use super::instant::is_instant_builtin;
use super::value::{Flow, Value};
use super::walker::{Frame, Walker};
use crate::error::Result;
use crate::rapid::{Arg, Call, Routine, RoutineKind, Statement};
use crate::schedule::bounds::MAX_DEPTH;

impl<'p> Walker<'p> {
    pub(super) fn find_routine(&self, module: usize, name: &str) -> Option<(usize, &'p Routine)> {
        let list = self.routines.get(&name.to_ascii_lowercase())?;
        list.iter()
            .find(|(m, _)| *m == module)
            .or_else(|| list.iter().find(|(_, r)| !r.local))
            .copied()
    }

    pub(crate) fn call_routine(
        &mut self,
        module: usize,
        routine: &'p Routine,
        vars: Vec<(String, Value)>,
        line: u32,
    ) -> Result<Flow> {
        self.rescope();
        let mut frame = Frame {
            module,
            routine: Some(routine),
            vars: vars.into_iter().collect(),
        };
        let why = if self.stack.contains(&std::ptr::from_ref(routine)) {
            Some("recursive call")
        } else if self.stack.len() >= MAX_DEPTH {
            Some("calls nested too deep: call")
        } else {
            None
        };
        if let Some(why) = why {
            self.note(
                &frame,
                line,
                format!("{why} of {} not followed", routine.name),
            );
            return Ok(Flow::Normal);
        }
        self.stack.push(std::ptr::from_ref(routine));
        let flow = self.exec_list(&routine.body, &mut frame);
        self.stack.pop();
        Ok(match flow? {
            Flow::Goto(label) => {
                self.note(
                    &frame,
                    routine.pos.line,
                    format!("GOTO {label}: no such label, ignored"),
                );
                Flow::Normal
            }
            other => other,
        })
    }

    /// Bind a call's arguments (evaluated in the caller's frame) to the
    /// routine's parameters.
    pub(super) fn bind(
        &mut self,
        routine: &Routine,
        args: &[Arg],
        caller: &mut Frame<'p>,
    ) -> Result<Vec<(String, Value)>> {
        let mut out = Vec::new();
        let mut required = routine.params.iter().filter(|p| !p.optional);
        for a in args {
            let param = if a.optional {
                a.name.as_deref().and_then(|n| {
                    routine
                        .params
                        .iter()
                        .find(|p| p.optional && p.name.eq_ignore_ascii_case(n))
                })
            } else {
                required.next()
            };
            let Some(param) = param else { continue };
            let value = match &a.value {
                Some(e) => self.eval(e, caller)?,
                None => Value::Bool(true),
            };
            out.push((param.name.to_ascii_lowercase(), value));
        }
        Ok(out)
    }

    pub(super) fn exec_call(
        &mut self,
        call: &'p Call,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        let line = s.pos.line;
        if self.exec_settled(call, s, frame)? {
            return Ok(Flow::Normal);
        }
        let name = call.name.to_ascii_lowercase();
        if call.late_bound {
            return self.exec_late_bound(call, line, frame);
        }
        if let Some(flow) = self.exec_timing(&name, call, line, frame)? {
            return Ok(flow);
        }
        match self.find_routine(frame.module, &call.name) {
            Some((mi, r)) if r.kind == RoutineKind::Proc => {
                let vars = self.bind(r, &call.args, frame)?;
                Ok(match self.call_routine(mi, r, vars, line)? {
                    Flow::Exit => Flow::Exit,
                    _ => Flow::Normal,
                })
            }
            _ => {
                if !is_instant_builtin(&name) {
                    self.note(
                        frame,
                        line,
                        format!(
                            "{}: not a procedure of the program, taken as instantaneous",
                            call.name
                        ),
                    );
                }
                Ok(Flow::Normal)
            }
        }
    }

    /// A late-bound call (`%"proc"%`): the routine its name is written as,
    /// where it is a string; otherwise taken as instantaneous, with a note.
    fn exec_late_bound(
        &mut self,
        call: &'p Call,
        line: u32,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        let target = call
            .name
            .trim()
            .trim_start_matches('%')
            .trim_end_matches('%');
        let target = target.trim();
        let resolved = target
            .strip_prefix('"')
            .and_then(|t| t.strip_suffix('"'))
            .and_then(|n| self.find_routine(frame.module, n));
        match resolved {
            Some((mi, r)) => {
                let vars = self.bind(r, &call.args, frame)?;
                self.call_routine(mi, r, vars, line).map(|f| match f {
                    Flow::Exit => Flow::Exit,
                    _ => Flow::Normal,
                })
            }
            None => {
                self.note(
                    frame,
                    line,
                    format!("late-bound call %{target}%: procedure known only at run time, taken as instantaneous"),
                );
                Ok(Flow::Normal)
            }
        }
    }

    /// The instructions that take time without moving (waits, MultiMove
    /// synchronisation, VelSet, stops): `None` for any other.
    fn exec_timing(
        &mut self,
        name: &str,
        call: &'p Call,
        line: u32,
        frame: &mut Frame<'p>,
    ) -> Result<Option<Flow>> {
        match name {
            "waittime" => {
                let secs = call
                    .positional()
                    .next()
                    .map(|e| self.eval(e, frame))
                    .transpose()?
                    .and_then(|v| v.num());
                match secs {
                    Some(t) if t.is_finite() && t >= 0.0 => {
                        if call.optional("InPos").is_some() {
                            self.clock = self.clock.max(self.robot_free);
                        }
                        self.clock += t;
                    }
                    _ => self.note(
                        frame,
                        line,
                        "WaitTime: time known only at run time, taken as 0 s",
                    ),
                }
                return Ok(Some(Flow::Normal));
            }
            "waituntil" | "waitdi" | "waitdo" | "waitai" | "waitao" | "waitgi" | "waitgo"
            | "waitsynctask" | "waittestandset" | "waitload" | "waitsensor" | "waitwobj" => {
                if call.optional("InPos").is_some() {
                    self.clock = self.clock.max(self.robot_free);
                }
                self.note(
                    frame,
                    line,
                    format!("{}: waits on a run-time condition, taken as 0 s", call.name),
                );
                return Ok(Some(Flow::Normal));
            }
            // MultiMove: the task waits for the others at its
            // synchronisation point, with its robot at rest (the
            // instructions need a stop point before them); the other
            // tasks' time is not modelled here.
            "syncmoveon" | "syncmoveoff" | "syncmoveundo" | "syncmovesuspend"
            | "syncmoveresume" => {
                self.clock = self.clock.max(self.robot_free);
                self.note(
                    frame,
                    line,
                    format!(
                        "{}: waits for the other motion tasks (MultiMove), taken as 0 s",
                        call.name
                    ),
                );
                return Ok(Some(Flow::Normal));
            }
            "waitrob" => {
                self.clock = self.clock.max(self.robot_free);
                return Ok(Some(Flow::Normal));
            }
            "velset" => {
                let mut pos = call.positional();
                let ov = pos.next().map(|e| self.eval(e, frame)).transpose()?;
                let max = pos.next().map(|e| self.eval(e, frame)).transpose()?;
                match (ov.and_then(|v| v.num()), max.and_then(|v| v.num())) {
                    (Some(o), Some(m)) if o > 0.0 && m > 0.0 => self.velset = (o / 100.0, m),
                    _ => self.note(
                        frame,
                        line,
                        "VelSet: values known only at run time, ignored",
                    ),
                }
                return Ok(Some(Flow::Normal));
            }
            "stop" | "break" => {
                self.note(
                    frame,
                    line,
                    format!(
                        "{}: the time until the operator restarts is not counted",
                        call.name
                    ),
                );
                return Ok(Some(Flow::Normal));
            }
            _ => {}
        }
        Ok(None)
    }
}
