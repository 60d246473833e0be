//! rapidtherm: thermal drift correction of ABB RAPID programs and diagnosis
//! of the gap between a robot model and a real robot.
//!
//! The library never prints or exits: every function returns values or an
//! [`error::Error`]; the `rapidtherm` binary is a thin layer over it.
//!
//! Modules, one idea each: [`rapid`] (reading and rewriting RAPID),
//! [`robot`] (the IRB 140: URDF, kinematics, thermal expansion, frames),
//! [`thermal`] (heating curves), [`schedule`] (when targets are reached),
//! [`correct`] (the corrected program, and diffs), [`diagnose`] (the
//! sim-to-real gap), [`model`] (the model file), [`report`] (tables).
//!
//! The main job in a few lines:
//!
//! ```
//! use rapidtherm::model::warm::{Moment, WarmRobot};
//! use rapidtherm::correct::{correct, Options, When};
//! use rapidtherm::{model::Model, rapid, robot::Robot, schedule::Visit};
//!
//! let src = b"MODULE m\n  PROC main()\n    MoveL [[450,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";
//! let program = rapid::parse("m.mod", src)?;
//! let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 60.0)?;
//! let at = |m| Options { when: When::At(Moment::Minute(m)), visit: Visit::Mean };
//! let warm_run = correct(&program, &[src], &warm, &at(60.0), &mut |_, _| {})?;
//! assert!(warm_run.summary.max_mm > 0.1); // the flange drifts by tenths of a mm
//! assert_ne!(warm_run.outputs[0], src);
//! let cold_run = correct(&program, &[src], &warm, &at(0.0), &mut |_, _| {})?;
//! assert_eq!(cold_run.outputs[0], src); // at the reference temperature: every byte kept
//! # Ok::<(), rapidtherm::Error>(())
//! ```

pub mod compare;
pub mod correct;
pub mod csv_table;
pub mod diagnose;
pub mod error;
pub mod model;
pub mod rapid;
pub mod report;
pub mod resolve;
pub mod robot;
pub mod schedule;
pub mod thermal;

pub use error::{Error, ErrorKind, Result};
