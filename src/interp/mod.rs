//! An interpreter of RAPID as the generated controller module uses it
//! (and a program around it that moves to run-time targets): module data
//! (`CONST`/`PERS`/`VAR`, arrays, records), `FUNC`/`PROC` with `IN`,
//! `INOUT` and `PERS` parameters and optional ones (`Present`), control
//! flow, record arithmetic, the math, pose and string functions, the
//! controller clock (a simulated [`Clock`] the caller sets) and
//! `CalcJointT`/`CalcRobT` on the project's own kinematics.
//!
//! It runs the project's own parse of the program (no second parser).
//! Not a general RAPID machine: what it does not know (an instruction, a
//! function, a construct) is a typed error naming the file, line and
//! column, never a guess. It counts the operations of each call
//! (expression nodes evaluated, statements executed, built-in calls), the
//! module's cost per correction.
//!
//! Split by concern: values and record types ([`value`]), the clock
//! ([`clock`]), data and routine calls (here), places that can be written
//! (`place`), expressions (`expr`), statements (`stmt`), built-in
//! functions (`builtins`) and the robot's (`kin`).

mod bounds;
mod builtins;
pub mod clock;
mod expr;
pub mod kin;
mod place;
mod stmt;
pub mod value;

pub use clock::Clock;
pub use kin::Kinematics;
pub use value::{Types, Value};

use crate::error::{Error, ErrorKind, Result};
use crate::rapid::{self, DataDecl, Param, Pos, Program, Routine, RoutineKind, Storage};
use place::Slot;
use std::collections::HashMap;
use std::rc::Rc;

/// How the interpreter keeps `num`: as the project computes (f64), or as
/// the controller does (IEEE single precision), each value rounded when it
/// is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    #[default]
    Double,
    Single,
}

/// What a run counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Ops {
    pub expressions: u64,
    pub statements: u64,
    pub builtins: u64,
}

impl Ops {
    pub fn total(&self) -> u64 {
        self.expressions + self.statements + self.builtins
    }
    fn since(&self, before: &Ops) -> Ops {
        Ops {
            expressions: self.expressions - before.expressions,
            statements: self.statements - before.statements,
            builtins: self.builtins - before.builtins,
        }
    }
}

/// An argument given to a routine from outside the program.
#[derive(Debug, Clone)]
pub enum CallArg {
    /// The next required parameter.
    Value(Value),
    /// An optional parameter by name (`\WObj:=...`).
    Named(String, Value),
}

/// A move instruction executed: its name and its targets' values.
#[derive(Debug, Clone, PartialEq)]
pub struct Moved {
    pub instruction: String,
    pub targets: Vec<Value>,
}

/// A module datum.
#[derive(Debug, Clone)]
struct Global {
    module: usize,
    local: bool,
    storage: Storage,
    value: Value,
}

/// One routine's data while it runs.
#[derive(Debug, Default)]
struct Frame {
    module: usize,
    /// The routine running: (module, index), none for a datum's
    /// initialisation.
    routine: Option<(usize, usize)>,
    vars: HashMap<String, Slot>,
}

/// What a statement leaves the routine to do.
enum Flow {
    Normal,
    Return(Option<Value>),
    Exit,
}

/// Routines nest deeper than this: an error, not a stack overflow.
const MAX_DEPTH: usize = 64;

pub struct Interp {
    program: Rc<Program>,
    types: Types,
    /// Module data by lower-case name (a LOCAL datum per module).
    globals: HashMap<String, Vec<Global>>,
    /// Routines by lower-case name: (module, routine).
    routines: HashMap<String, Vec<(usize, usize)>>,
    frames: Vec<Frame>,
    kin: Kinematics,
    clock: Clock,
    precision: Precision,
    ops: Ops,
    /// The statement count when the call from outside began: a call
    /// runs at most the walker's budget of statements (a WHILE that never
    /// ends is an error, not a hang).
    call_began: u64,
    /// Statements one call may run ([`Interp::set_step_budget`]).
    pub(super) step_budget: u64,
    moves: Vec<Moved>,
    /// The statement being executed: (file, place), for errors.
    at: Option<(usize, Pos)>,
}

impl Interp {
    /// Reads `files` with the project's grammar and loads their modules:
    /// every datum initialised, the clock at 2000-01-01.
    pub fn load(files: &[(&str, &[u8])], kin: Kinematics) -> Result<Interp> {
        let program = rapid::parse_files(files)?;
        let mut types = Types::default();
        let mut routines: HashMap<String, Vec<(usize, usize)>> = HashMap::new();
        for (m, module) in program.modules.iter().enumerate() {
            for r in &module.records {
                types.add_record(
                    &r.name,
                    r.components
                        .iter()
                        .map(|(t, n)| (n.clone(), t.clone()))
                        .collect(),
                );
            }
            for (a, of) in &module.aliases {
                types.add_alias(a, of);
            }
            for (k, r) in module.routines.iter().enumerate() {
                routines
                    .entry(r.name.to_ascii_lowercase())
                    .or_default()
                    .push((m, k));
            }
        }
        let mut interp = Interp {
            program: Rc::new(program),
            types,
            globals: HashMap::new(),
            routines,
            frames: Vec::new(),
            kin,
            clock: Clock::at(2000, 1, 1, 0, 0, 0),
            precision: Precision::Double,
            ops: Ops::default(),
            call_began: 0,
            step_budget: bounds::STEP_BUDGET,
            moves: Vec::new(),
            at: None,
        };
        interp.predefined()?;
        interp.init_data(true)?;
        Ok(interp)
    }

    /// RAPID's predefined data the module and programs name.
    fn predefined(&mut self) -> Result<()> {
        let tool0 = self.types.coerce_to(
            kin::tool_value(&crate::robot::ToolFrame::tool0()),
            "tooldata",
        )?;
        let tool0 = match tool0 {
            Value::Rec(t, mut f) => {
                // tload: a mass of 0.001 kg, as the controller's tool0.
                if let Some(Value::Rec(_, load)) = f.get_mut(2) {
                    load[0] = Value::Num(0.001);
                }
                Value::Rec(t, f)
            }
            v => v,
        };
        let wobj0 = kin::wobj_value(&crate::robot::WobjFrames::wobj0());
        let wobj0 = self.types.coerce_to(wobj0, "wobjdata")?;
        let load0 = self.types.default_of("loaddata")?;
        for (name, value) in [("tool0", tool0), ("wobj0", wobj0), ("load0", load0)] {
            self.globals.insert(
                name.into(),
                vec![Global {
                    module: usize::MAX,
                    local: false,
                    storage: Storage::Pers,
                    value,
                }],
            );
        }
        Ok(())
    }

    /// Initialises the modules' data from their declarations: every datum
    /// at a load, all but `PERS` ones at a program restart.
    fn init_data(&mut self, with_pers: bool) -> Result<()> {
        let program = self.program.clone();
        for (m, module) in program.modules.iter().enumerate() {
            // Every declaration in source order, those the fast lane
            // holds together too.
            for d in program.module_data(module) {
                if d.storage == Storage::Pers && !with_pers {
                    continue;
                }
                self.at = Some((module.file, d.pos));
                self.frames.push(Frame {
                    module: m,
                    routine: None,
                    vars: HashMap::new(),
                });
                let value = self.declared_value(&d);
                self.frames.pop();
                let value = value.map_err(|e| self.locate(e))?;
                let key = d.name.to_ascii_lowercase();
                let local = d.scope == Some(rapid::Scope::Local);
                let slots = self.globals.entry(key).or_default();
                match slots.iter_mut().find(|g| g.module == m) {
                    Some(g) => g.value = value,
                    None => slots.push(Global {
                        module: m,
                        local,
                        storage: d.storage,
                        value,
                    }),
                }
            }
        }
        self.at = None;
        Ok(())
    }

    /// The value a declaration gives its datum (in the current frame).
    fn declared_value(&mut self, d: &DataDecl) -> Result<Value> {
        let mut dims = Vec::with_capacity(d.dims.len());
        for e in &d.dims {
            let n = self
                .eval(e)?
                .num()
                .ok_or_else(|| Error::input("an array size that is not a num"))?;
            if n < 1.0 || n.fract() != 0.0 || n > 1e7 {
                return Err(Error::input(format!("array size {n}")));
            }
            dims.push(n as usize);
        }
        let like = self.types.default_array(&d.type_name, &dims)?;
        let program = self.program.clone();
        let value = match program.value_of(d) {
            Some(e) => {
                let v = self.eval(&e)?;
                self.types.coerce(v, &like)?
            }
            None => like,
        };
        Ok(self.stored(value))
    }

    /// A program restart (PP to Main): every `VAR` and `CONST` datum set
    /// from its declaration again, `PERS` data kept, nothing running.
    pub fn restart(&mut self) -> Result<()> {
        self.frames.clear();
        self.init_data(false)
    }

    pub fn set_clock(&mut self, clock: Clock) {
        self.clock = clock;
    }
    pub fn clock(&self) -> Clock {
        self.clock
    }
    /// Moves the clock on by `minutes` (nothing runs).
    pub fn advance(&mut self, minutes: f64) {
        self.clock.advance(minutes);
    }
    pub fn set_precision(&mut self, precision: Precision) -> Result<()> {
        self.precision = precision;
        // The data already held are rounded too: the controller reads
        // the module's numbers into single precision.
        if precision == Precision::Single {
            for g in self.globals.values_mut().flatten() {
                g.value.to_single();
            }
        }
        Ok(())
    }
    /// Everything counted since the interpreter was loaded.
    pub fn ops(&self) -> Ops {
        self.ops
    }
    /// The moves executed so far, in order.
    pub fn moves(&self) -> &[Moved] {
        &self.moves
    }
    pub fn types(&self) -> &Types {
        &self.types
    }
    /// A module datum's value (a global one, or the first module's).
    pub fn global(&self, name: &str) -> Option<&Value> {
        self.globals
            .get(&name.to_ascii_lowercase())
            .and_then(|g| g.first())
            .map(|g| &g.value)
    }
    /// Sets a module datum (as a program or an operator would), coerced to
    /// its type.
    pub fn set_global(&mut self, name: &str, value: Value) -> Result<()> {
        let g = self
            .globals
            .get_mut(&name.to_ascii_lowercase())
            .and_then(|g| g.first_mut())
            .ok_or_else(|| Error::input(format!("no datum `{name}`")))?;
        let mut v = self.types.coerce(value, &g.value)?;
        if self.precision == Precision::Single {
            v.to_single();
        }
        g.value = v;
        Ok(())
    }

    /// How many statements one call from outside may run before it is an
    /// error (the estimate walk's 50 million unless set).
    pub fn set_step_budget(&mut self, statements: u64) {
        self.step_budget = statements;
    }

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

    fn invoke_outside(&mut self, m: usize, k: usize, args: &[CallArg]) -> Result<Option<Value>> {
        self.frames.clear();
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
        out
    }

    /// A value given for parameter `p`, as the parameter holds it.
    fn param_value(&self, p: &Param, v: Value) -> Result<Value> {
        let v = if p.array_dims > 0 || p.type_name.eq_ignore_ascii_case("switch") {
            v
        } else {
            self.types.coerce_to(v, &p.type_name)?
        };
        Ok(self.stored(v))
    }

    /// Runs `routine` of module `m` with its parameters bound in `vars`.
    fn run_routine(
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
        });
        let program = self.program.clone();
        let out = self.run_body(m, &program.modules[m].routines[k]);
        self.frames.pop();
        out
    }

    fn run_body(&mut self, m: usize, routine: &Routine) -> Result<Option<Value>> {
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
    fn routine_named(&self, name: &str, from: Option<usize>) -> Result<(usize, usize)> {
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

    /// The routine of the running frame.
    fn routine_of_frame(&self) -> Option<&Routine> {
        let (m, k) = self.frames.last()?.routine?;
        self.program.modules.get(m)?.routines.get(k)
    }

    fn frame(&mut self) -> &mut Frame {
        if self.frames.is_empty() {
            self.frames.push(Frame::default());
        }
        let n = self.frames.len() - 1;
        &mut self.frames[n]
    }

    /// A value as it is stored: rounded to the controller's precision.
    fn stored(&self, mut v: Value) -> Value {
        if self.precision == Precision::Single {
            v.to_single();
        }
        v
    }

    /// `e` located at the statement being executed (where it has no place
    /// yet).
    fn locate(&self, e: Error) -> Error {
        if e.location.is_some() {
            return e;
        }
        match self.at {
            Some((file, pos)) => {
                let name = self.program.file_name(file);
                let src = self.program.source(file);
                e.at(crate::error::Location::from_offset(name, src, pos.offset))
            }
            None => e,
        }
    }

    /// An error of a construct the interpreter does not run.
    fn unsupported(&self, what: impl Into<String>) -> Error {
        self.locate(Error::new(
            ErrorKind::Unsupported,
            format!("the interpreter does not run {}", what.into()),
        ))
    }
}
