//! The interpreter's state: the program, its record types, module data
//! and routines, the frames of the routines running, the clock, what a run
//! counted and the moves it made; and what it is told from outside
//! (precision, clock, data, the step budget).

use super::clock::Clock;
use super::commanded::Commanded;
use super::kin::Kinematics;
use super::place::Slot;
use super::raised::Raised;
use super::told::OperatorMessage;
use super::value::{Types, Value};
use crate::error::{Error, ErrorKind, Result};
use crate::rapid::{Pos, Program, Routine, Storage};
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
    pub(super) fn since(&self, before: &Ops) -> Ops {
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
pub(super) struct Global {
    pub(super) module: usize,
    pub(super) local: bool,
    pub(super) storage: Storage,
    pub(super) value: Value,
}

/// One routine's data while it runs.
#[derive(Debug, Default)]
pub(super) struct Frame {
    pub(super) module: usize,
    /// The routine running: (module, index), none for a datum's
    /// initialisation.
    pub(super) routine: Option<(usize, usize)>,
    pub(super) vars: HashMap<String, Slot>,
    /// The RAPID error its ERROR handler is handling, while it runs.
    pub(super) handling: Option<f64>,
}

/// What a statement leaves the routine to do.
pub(super) enum Flow {
    Normal,
    Return(Option<Value>),
    Exit,
    /// An ERROR handler's RETRY and TRYNEXT.
    Retry,
    TryNext,
}

/// Routines nest deeper than this: an error, not a stack overflow.
pub(super) const MAX_DEPTH: usize = 64;

pub struct Interp {
    pub(super) program: Rc<Program>,
    pub(super) types: Types,
    /// Module data by lower-case name (a LOCAL datum per module).
    pub(super) globals: HashMap<String, Vec<Global>>,
    /// Routines by lower-case name: (module, routine).
    pub(super) routines: HashMap<String, Vec<(usize, usize)>>,
    pub(super) frames: Vec<Frame>,
    pub(super) kin: Kinematics,
    pub(super) clock: Clock,
    pub(super) precision: Precision,
    pub(super) ops: Ops,
    /// The statement count when the call from outside began: a call
    /// runs at most the walker's budget of statements (a WHILE that never
    /// ends is an error, not a hang).
    pub(super) call_began: u64,
    /// Statements one call may run ([`Interp::set_step_budget`]).
    pub(super) step_budget: u64,
    pub(super) moves: Vec<Moved>,
    /// The statement being executed: (file, place), for errors.
    pub(super) at: Option<(usize, Pos)>,
    /// The RAPID error on its way to a handler, if the error returned is
    /// one.
    pub(super) raised: Option<Raised>,
    /// The controller's monotonic time (s) since the load: what its
    /// stopwatches (`clock` data) count; [`Interp::advance`] moves it,
    /// [`Interp::set_clock`] (the wall clock an operator sets) does not.
    pub(super) uptime: f64,
    /// Where the robot was last sent.
    pub(super) commanded: Option<Commanded>,
    pub(super) messages: Vec<OperatorMessage>,
    /// The files loaded (name, bytes), for a module's reload.
    pub(super) files: Vec<(String, Vec<u8>)>,
}

impl Interp {
    pub fn set_clock(&mut self, clock: Clock) {
        self.clock = clock;
    }
    pub fn clock(&self) -> Clock {
        self.clock
    }
    /// Moves the clock on by `minutes` (nothing runs): the wall clock and
    /// the controller's own time, which its `clock` data count.
    pub fn advance(&mut self, minutes: f64) {
        self.clock.advance(minutes);
        self.uptime += minutes * 60.0;
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
        let slots = self.globals.get(&name.to_ascii_lowercase())?;
        slots
            .iter()
            .find(|g| !g.local)
            .or_else(|| slots.first())
            .map(|g| &g.value)
    }
    /// Sets a module datum (as a program or an operator would), coerced to
    /// its type.
    pub fn set_global(&mut self, name: &str, value: Value) -> Result<()> {
        let slots = self
            .globals
            .get_mut(&name.to_ascii_lowercase())
            .ok_or_else(|| Error::input(format!("no datum `{name}`")))?;
        let k = slots.iter().position(|g| !g.local).unwrap_or(0);
        let g = &mut slots[k];
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

    /// The routine of the running frame.
    pub(super) fn routine_of_frame(&self) -> Option<&Routine> {
        let (m, k) = self.frames.last()?.routine?;
        self.program.modules.get(m)?.routines.get(k)
    }

    pub(super) fn frame(&mut self) -> &mut Frame {
        if self.frames.is_empty() {
            self.frames.push(Frame::default());
        }
        let n = self.frames.len() - 1;
        &mut self.frames[n]
    }

    /// A value as it is stored: rounded to the controller's precision.
    pub(super) fn stored(&self, mut v: Value) -> Value {
        if self.precision == Precision::Single {
            v.to_single();
        }
        v
    }

    /// `e` located at the statement being executed (where it has no place
    /// yet).
    pub(super) fn locate(&self, e: Error) -> Error {
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
    pub(super) fn unsupported(&self, what: impl Into<String>) -> Error {
        self.locate(Error::new(
            ErrorKind::Unsupported,
            format!("the interpreter does not run {}", what.into()),
        ))
    }
}
