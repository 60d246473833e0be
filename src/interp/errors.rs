//! RAPID's error recovery: the predefined error numbers the interpreter
//! raises (`ERR_ROBLIMIT`, ...), `ERRNO`, a routine's `ERROR` handler and
//! how it ends (`RETURN`, `RAISE`, `RETRY`, `TRYNEXT`).
//!
//! As the RAPID Reference Manual, Basic Characteristics, "Error Recovery"
//! and the instruction RAISE say: an error in a routine without a handler
//! (or passed on by `RAISE` in its handler) is raised again where the
//! routine was called; at the top of the call chain it is the system's
//! (here: the call from outside fails, the error at its place). An error
//! inside an error handler is always the system's. `RAISE n` outside a
//! handler calls the routine's own handler with `ERRNO = n`.

use super::raised::{Raised, ERR_EXCRTYMAX, ERR_ILLRAISE, ERR_OUTSIDE_REACH, ERR_ROBLIMIT, NAMED};
use super::state::{Flow, Global, Interp};
use super::value::Value;
use crate::error::{Error, ErrorKind, Result};
use crate::rapid::{Block, Statement, Storage};

/// How often the handler may RETRY one error before the controller raises
/// ERR_EXCRTYMAX (the system parameter "No Of Retry", 4 by default).
const MAX_RETRIES: u32 = 4;

/// What an error handler leaves the statement that failed to do.
enum Handled {
    Retry,
    TryNext,
    Flow(Flow),
}

impl Interp {
    /// `ERRNO` and the errnum constants, as predefined data.
    pub(super) fn predefined_errors(&mut self) {
        let mut put = |name: &str, storage, v: f64| {
            self.globals.insert(
                name.into(),
                vec![Global {
                    module: usize::MAX,
                    local: false,
                    storage,
                    value: Value::Num(v),
                }],
            );
        };
        put("errno", Storage::Var, 0.0);
        for (name, v) in NAMED {
            put(name, Storage::Const, *v);
        }
        self.types.add_alias("errnum", "num");
    }

    /// `e` as RAPID error `errno`: a handler may take it.
    pub(super) fn raise(&mut self, errno: f64, e: Error) -> Error {
        self.raised = Some(Raised {
            errno,
            below: usize::MAX,
        });
        e
    }

    /// A failed built-in's error as the RAPID error the controller raises
    /// (`None`: not one a handler can take). CalcJointT and CalcRobT: out
    /// of reach is ERR_OUTSIDE_REACH; a joint limit or no solution in the
    /// robtarget's configuration is ERR_ROBLIMIT (the RAPID reference,
    /// CalcJointT, Error handling).
    pub(super) fn raise_from_robot(&mut self, e: Error) -> Error {
        if e.kind != ErrorKind::Unreachable {
            return e;
        }
        let errno = if e.message.starts_with("out of reach") {
            ERR_OUTSIDE_REACH
        } else {
            ERR_ROBLIMIT
        };
        self.raise(errno, e)
    }

    /// `RAISE [n]` executed: in a handler without a number, the error
    /// being handled passed on to the caller; with a number, error `n`
    /// (1..90, else ERR_ILLRAISE) for this routine's handler.
    pub(super) fn exec_raise(&mut self, n: Option<&crate::rapid::Expr>) -> Result<Flow> {
        let depth = self.frames.len();
        let in_handler = self.frames.last().is_some_and(|f| f.handling.is_some());
        let errno = match n {
            Some(e) => {
                let v = self.eval(e)?.num().unwrap_or(0.0);
                let user = (1.0..=90.0).contains(&v) && v.fract() == 0.0;
                if user || NAMED.iter().any(|(_, x)| *x == v) {
                    v
                } else {
                    ERR_ILLRAISE
                }
            }
            None => match self.frames.last().and_then(|f| f.handling) {
                Some(errno) => errno,
                None => {
                    return Err(Error::input(
                        "RAISE without a number outside an ERROR handler",
                    ))
                }
            },
        };
        let e = self.locate(Error::input(format!(
            "RAPID error {errno} raised and not handled"
        )));
        self.raised = Some(Raised {
            errno,
            below: if in_handler { depth } else { usize::MAX },
        });
        Err(e)
    }

    /// Runs statement `s` (of a routine's body, in `file`) with the
    /// routine's ERROR handler taking the RAPID errors it raises:
    /// re-run (RETRY), the next statement (TRYNEXT), the routine's end
    /// (RETURN), or the error passed on.
    pub(super) fn exec_handled(&mut self, file: usize, s: &Statement) -> Result<Flow> {
        let mut retries = 0;
        loop {
            let e = match self.exec(file, s) {
                Ok(flow) => return Ok(flow),
                Err(e) => e,
            };
            let Some(handler) = self.handler_for() else {
                return Err(e);
            };
            let errno = self.raised.take().map_or(0.0, |r| r.errno);
            match self.run_handler(file, &handler, errno)? {
                Handled::Retry if retries < MAX_RETRIES => retries += 1,
                Handled::Retry => {
                    // Raised where the handler gave up: for the caller.
                    self.raised = Some(Raised {
                        errno: ERR_EXCRTYMAX,
                        below: self.frames.len(),
                    });
                    return Err(e.with_note("retried more often than the controller's 4 times"));
                }
                Handled::TryNext => return Ok(Flow::Normal),
                Handled::Flow(f) => return Ok(f),
            }
        }
    }

    /// The running routine's handler for the RAPID error raised, if it
    /// takes it here (not from its own handler, not passed on from here).
    fn handler_for(&self) -> Option<Block> {
        let r = self.raised?;
        let depth = self.frames.len();
        let f = self.frames.last()?;
        if depth >= r.below || f.handling.is_some() {
            return None;
        }
        let (numbers, body) = self.routine_of_frame()?.error.as_ref()?;
        // `ERROR (n1, n2)`: those numbers only (the list read once more,
        // constants and data alike).
        if !numbers.is_empty() {
            return Some(body.clone()).filter(|_| self.lists(numbers, r.errno));
        }
        Some(body.clone())
    }

    fn lists(&self, numbers: &[crate::rapid::Expr], errno: f64) -> bool {
        numbers.iter().any(|e| match e {
            crate::rapid::Expr::Num(n) => n.value == errno,
            e => e
                .as_name()
                .and_then(|n| self.place_of_name(n).ok())
                .and_then(|p| self.read(&p).ok().and_then(Value::num))
                .is_some_and(|v| v == errno),
        })
    }

    fn run_handler(&mut self, file: usize, body: &Block, errno: f64) -> Result<Handled> {
        self.set_errno(errno);
        let n = self.frames.len() - 1;
        self.frames[n].handling = Some(errno);
        let flow = self.exec_block(file, body);
        self.frames[n].handling = None;
        let flow = match flow {
            Ok(f) => f,
            Err(e) => {
                // Only RAISE passes an error on from a handler; any other
                // is the system's.
                if self.raised.is_some_and(|r| r.below != n + 1) {
                    self.raised = None;
                }
                return Err(e);
            }
        };
        Ok(match flow {
            Flow::Retry => Handled::Retry,
            Flow::TryNext => Handled::TryNext,
            // The handler's end reached: the routine ends as at RETURN.
            Flow::Normal => Handled::Flow(Flow::Return(None)),
            f => Handled::Flow(f),
        })
    }

    fn set_errno(&mut self, errno: f64) {
        if let Some(g) = self.globals.get_mut("errno").and_then(|g| g.first_mut()) {
            g.value = Value::Num(errno);
        }
    }
}
