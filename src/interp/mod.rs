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
//! ([`clock`]), the interpreter's state (`state`), a program loaded
//! (`load`), routine calls (`calls`), places that can be written (`place`)
//! and their reading and writing (`access`), expressions (`expr`),
//! statements (`stmt`), built-in functions (`builtins`) and the robot's
//! (`kin`); RAPID's error recovery (`errors`), the built-in instructions
//! (`instructions`: `messages`, `stopwatch`, `progdisp`), the robot's
//! commanded position (`robot`) and the controller's restarts
//! (`restarts`).

mod access;
mod bounds;
mod builtins;
mod calls;
pub mod clock;
mod commanded;
mod errors;
mod expr;
mod instructions;
pub mod kin;
mod load;
mod messages;
mod place;
mod progdisp;
mod raised;
mod restarts;
mod robot;
mod state;
mod stmt;
mod stopwatch;
mod told;
pub mod value;

pub use clock::Clock;
pub use kin::Kinematics;
pub use state::{CallArg, Interp, Moved, Ops, Precision};
pub use told::{MessageKind, OperatorMessage};
pub use value::{Types, Value};
