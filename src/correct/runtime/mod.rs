//! The correction on the controller (`correct --runtime`): a RAPID system
//! module that carries the arm's heating state through the day and
//! corrects any target for it when the program reaches it.
//!
//! [`spec`] takes what the module needs from the arm and the model (and
//! refuses what it cannot carry); [`module`] writes the RAPID; [`mirror`]
//! is the same arithmetic in Rust, which tests hold to the project's warm
//! arm and heating curves; [`job`] runs it on tasks and [`write`] puts
//! what it made where the plan says.

pub mod from_robot;
pub mod job;
pub mod mirror;
pub mod module;
pub mod names;
pub mod rewrite;
pub mod spec;
pub mod write;

pub use module::{module_text, ModuleOptions};
pub use spec::{Refusal, RuntimeSpec};
