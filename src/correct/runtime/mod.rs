//! The correction on the controller (`correct --runtime`): a RAPID system
//! module that carries the arm's heating state through the day and
//! corrects any target for it when the program reaches it.
//!
//! [`spec`] takes what the module needs from the arm and the model (and
//! refuses what it cannot carry); [`table`] works out the rows of the
//! targets the program names; [`module`] writes the RAPID ([`body`] its
//! routines) under the names [`names`] checks; [`mirror`] is the same
//! arithmetic in Rust, which tests hold to the project's warm arm and
//! heating curves; [`rewrite`] wraps the moves (leaving what
//! [`from_robot`] finds read back from the robot), [`unwrap`] gives the
//! cold original back; [`job`] runs it on tasks, [`write`] puts what it
//! made where the plan says, and [`gate`] is the CI's check of it.

pub mod body;
pub mod from_robot;
pub mod gate;
pub mod job;
pub mod mirror;
pub mod module;
pub mod names;
pub mod rewrite;
pub mod spec;
pub mod table;
pub mod unwrap;
pub mod write;

pub use module::{module_text, ModuleOptions};
pub use spec::{Refusal, RuntimeSpec};
