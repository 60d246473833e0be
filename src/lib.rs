//! rapidtherm: thermal drift correction of ABB RAPID programs and diagnosis
//! of the gap between a robot model and a real robot.
//!
//! The library never prints, exits, writes files or names a command-line
//! flag: every function returns values or an [`error::Error`]; the
//! `rapidtherm` binary is a thin layer over it.
//!
//! # Layers
//!
//! Each module imports only the modules below it (checked by
//! `tests/layers.rs`):
//!
//! | layer | modules | owns |
//! |---|---|---|
//! | 5 | [`correct`], [`compare`], [`diagnose`] | the two jobs: corrected programs, program diffs, the sim-to-real gap |
//! | 4 | [`resolve`], [`schedule`], [`interp`] | what a program means by its targets (tools, work objects, poses); when each target is reached; running RAPID as the controller would (the run-time module's tests) |
//! | 3 | [`model`] | the warm robot both jobs share: model file, expansion, effects, perturbed chain, `WarmRobot` |
//! | 2 | [`rapid`], [`robot`], [`thermal`] | the language; geometry (URDF, ABB arms by name, chain, OPW FK/IK, robconf, frames); temperatures over time and the thermal lag |
//! | 1 | [`error`], [`input`], [`digest`], [`csv_table`], [`report`], [`plot`], [`writes`] | shared foundations: errors with locations, bounded reading of inputs, the rule every write of a run goes through, fingerprints and their byte encodings, CSV tables, number and table formatting, the SVG pictures' canvas |
//!
//! The main job's data flow: `rapid::parse` → `resolve` (the flange pose
//! each target means) → `schedule` (when) → `model::WarmRobot` (where the
//! warm arm goes) → `correct` (the nominal pose that lands warm where the
//! cold program meant) → `rapid::rewrite` (new bytes).
//!
//! The main job in a few lines:
//!
//! ```
//! use rapidtherm::correct::{correct, Options, When};
//! use rapidtherm::model::{Model, Moment, WarmRobot};
//! use rapidtherm::{rapid, robot::Robot};
//!
//! let src = b"MODULE m\n  PROC main()\n    MoveL [[450,100,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";
//! let program = rapid::parse("m.mod", src)?;
//! let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 60.0)?;
//! let at = |m| Options::new(When::At(Moment::Minute(m)));
//! let warm_run = correct(&program, &warm, &at(60.0), &mut |_, _| {})?;
//! assert!(warm_run.summary.max_mm > 0.02); // the flange drifts by hundredths of a mm
//! assert_ne!(warm_run.outputs[0], src);
//! let cold_run = correct(&program, &warm, &at(0.0), &mut |_, _| {})?;
//! assert_eq!(cold_run.outputs[0], src); // at the reference temperature: every byte kept
//! # Ok::<(), rapidtherm::Error>(())
//! ```

#![deny(clippy::print_stdout, clippy::print_stderr)]

pub mod compare;
pub mod correct;
pub mod csv_table;
pub mod diagnose;
pub mod digest;
pub mod error;
pub mod input;
pub mod interp;
pub mod model;
pub mod plot;
pub mod rapid;
pub mod report;
pub mod resolve;
pub mod robot;
pub mod schedule;
pub mod thermal;
pub mod writes;

pub use error::{Error, ErrorKind, Result};
