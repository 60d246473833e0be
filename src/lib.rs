//! rapidtherm: thermal drift correction of ABB RAPID programs and diagnosis
//! of the gap between a robot model and a real robot.
//!
//! The library never prints or exits: every function returns values or an
//! [`error::Error`]; the `rapidtherm` binary is a thin layer over it.

pub mod correct;
pub mod csv_table;
pub mod diagnose;
pub mod error;
pub mod model;
pub mod output;
pub mod rapid;
pub mod report;
pub mod robot;
pub mod schedule;
pub mod thermal;

pub use error::{Error, ErrorKind, Result};
