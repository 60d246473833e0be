//! RAPID's predefined error numbers (errnum) the interpreter raises, by
//! name, and an error on its way to a handler. The numbers are the
//! interpreter's own: a program names them (`ERRNO = ERR_ROBLIMIT`), and
//! no program of the project depends on the controller's values.

/// The predefined error numbers (errnum) the interpreter raises.
pub(super) const ERR_ROBLIMIT: f64 = 1101.0;
pub(super) const ERR_OUTSIDE_REACH: f64 = 1102.0;
pub(super) const ERR_DIVZERO: f64 = 1103.0;
pub(super) const ERR_OUTOFBND: f64 = 1104.0;
pub(super) const ERR_OVERFLOW: f64 = 1105.0;
pub(super) const ERR_ILLRAISE: f64 = 1106.0;
pub(super) const ERR_EXCRTYMAX: f64 = 1107.0;

pub(super) const NAMED: &[(&str, f64)] = &[
    ("err_roblimit", ERR_ROBLIMIT),
    ("err_outside_reach", ERR_OUTSIDE_REACH),
    ("err_divzero", ERR_DIVZERO),
    ("err_outofbnd", ERR_OUTOFBND),
    ("err_overflow", ERR_OVERFLOW),
    ("err_illraise", ERR_ILLRAISE),
    ("err_excrtymax", ERR_EXCRTYMAX),
];

/// A RAPID error on its way to a handler.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Raised {
    pub(super) errno: f64,
    /// Frames this deep or deeper do not handle it (passed on by RAISE
    /// from the handler of the frame at this depth).
    pub(super) below: usize,
}
