//! Routines called: from outside (`call_func`, `call_proc`, arguments
//! bound to parameters) and from the program, each in a frame of its own,
//! a FUNC's value coerced to its return type.

use super::place::Slot;
use super::state::{CallArg, Flow, Frame, Interp, Ops, MAX_DEPTH};
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::{Param, Routine, RoutineKind};
use std::collections::HashMap;

impl Interp {
    /// Calls FUNC `name` with `args`: its value and what the call counted.
    pub fn call_func(&mut self, name: &str, args: &[CallArg]) -> Result<(Value, Ops)> {
        let before = self.ops;
        let (m, k) = self.routine_named(name, None)?;
        let v = self.invoke_outside(m, k, args)?;
        let v = v.ok_or_else(|| Error::input(format!("`{name}` returned no value")))?;
        Ok((v, self.ops.since(&before)))
    }

    /// Calls PROC `name` with `args`: what the call counted.
    pub fn call_proc(&mut self, name: &str, args: &[CallArg]) -> Result<Ops> {
        let before = self.ops;
        let (m, k) = self.routine_named(name, None)?;
        self.invoke_outside(m, k, args)?;
        Ok(self.ops.since(&before))
    }

    pub(super) fn invoke_outside(
        &mut self,
        m: usize,
        k: usize,
        args: &[CallArg],
    ) -> Result<Option<Value>> {
        self.frames.clear();
        // A RAPID error a call left unhandled is no error of this one's.
        self.raised = None;
        self.call_began = self.ops.statements;
        let program = self.program.clone();
        let routine = &program.modules[m].routines[k];
        let mut vars = HashMap::new();
        let mut positional = args.iter().filter_map(|a| match a {
            CallArg::Value(v) => Some(v),
            CallArg::Named(..) => None,
        });
        for p in &routine.params {
            let given = if p.optional {
                args.iter().find_map(|a| match a {
                    CallArg::Named(n, v) if n.eq_ignore_ascii_case(&p.name) => Some(v),
                    _ => None,
                })
            } else {
                Some(positional.next().ok_or_else(|| {
                    Error::input(format!("`{}` needs argument `{}`", routine.name, p.name))
                })?)
            };
            if let Some(v) = given {
                let v = self.param_value(p, v.clone())?;
                vars.insert(p.name.to_ascii_lowercase(), Slot::Value(v));
            }
        }
        let out = self.run_routine(m, k, vars);
        self.frames.clear();
        self.raised = None;
        out
    }

    /// A value given for parameter `p`, as the parameter holds it.
    pub(super) fn param_value(&self, p: &Param, v: Value) -> Result<Value> {
        let v = if p.array_dims > 0 || p.type_name.eq_ignore_ascii_case("switch") {
            v
        } else {
            self.types.coerce_to(v, &p.type_name)?
        };
        Ok(self.stored(v))
    }

    /// Runs `routine` of module `m` with its parameters bound in `vars`.
    pub(super) fn run_routine(
        &mut self,
        m: usize,
        k: usize,
        vars: HashMap<String, Slot>,
    ) -> Result<Option<Value>> {
        if self.frames.len() >= MAX_DEPTH {
            return Err(self.locate(Error::input(format!(
                "routines nest deeper than {MAX_DEPTH} (a recursion?)"
            ))));
        }
        self.frames.push(Frame {
            module: m,
            routine: Some((m, k)),
            vars,
            handling: None,
        });
        let program = self.program.clone();
        let out = self.run_body(m, &program.modules[m].routines[k]);
        self.frames.pop();
        out
    }

    pub(super) fn run_body(&mut self, m: usize, routine: &Routine) -> Result<Option<Value>> {
        let file = self.program.modules[m].file;
        for d in &routine.data {
            self.at = Some((file, d.pos));
            let v = self.declared_value(d).map_err(|e| self.locate(e))?;
            self.frame()
                .vars
                .insert(d.name.to_ascii_lowercase(), Slot::Value(v));
        }
        let flow = self.exec_block(file, &routine.body)?;
        match (flow, routine.kind) {
            (Flow::Return(Some(v)), RoutineKind::Func) => {
                let ty = routine.return_type.as_deref().unwrap_or("num");
                let v = self.types.coerce_to(v, ty).map_err(|e| self.locate(e))?;
                Ok(Some(self.stored(v)))
            }
            (_, RoutineKind::Func) => Err(self.locate(Error::input(format!(
                "FUNC `{}` ended without RETURN of a value",
                routine.name
            )))),
            _ => Ok(None),
        }
    }

    /// The routine `name` as seen from module `from` (its LOCAL ones
    /// first).
    pub(super) fn routine_named(&self, name: &str, from: Option<usize>) -> Result<(usize, usize)> {
        let all = self
            .routines
            .get(&name.to_ascii_lowercase())
            .ok_or_else(|| Error::input(format!("no routine `{name}`")))?;
        let local = |&&(m, k): &&(usize, usize)| self.program.modules[m].routines[k].local;
        all.iter()
            .find(|e| Some(e.0) == from && local(e))
            .or_else(|| all.iter().find(|e| !local(e)))
            .copied()
            .ok_or_else(|| Error::input(format!("no routine `{name}` seen from here")))
    }
}
