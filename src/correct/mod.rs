//! Correcting a program for thermal drift: for each target, the
//! coordinates that make the warm robot reach what the cold program meant;
//! and the target-by-target comparison of two programs.
//!
//! For a target T (TCP pose in its work object, robconf C), the program
//! means the flange pose F = frames(T). The controller, with its nominal
//! model, turns a target into joints by inverse kinematics; the warm robot
//! at joints q is at warm(q). The corrected target T' is the one whose
//! nominal joints are the warm joints that reach F:
//!
//! ```text
//! q_warm = IK_warm(F, C)        warm(q_warm) = F
//! F'     = FK_nominal(q_warm)   what the controller must be told
//! T'     = frames⁻¹(F')         in the target's own tool and work object
//! ```
//!
//! For pure link expansion the warm arm has the nominal arm's shape, and
//! `IK_warm` is the closed form on the expanded lengths: exact. Effects that
//! change the shape (bending, joint offsets, ...) are solved by Newton from
//! that start. The robconf is never changed.

//!
//! Owns the orchestration of a run (this file), the per-target solve
//! (`solve`), the moments targets are corrected for (`moments`), the
//! written text (`edits`), derived targets ([`derived`]) and the report
//! (`outcome`). May import `model`, `resolve`, `schedule`, `robot`,
//! `rapid`, `thermal` and the shared `error`; never `diagnose`, `compare`
//! or the CLI.

pub mod check;
mod cold_prints;
mod context;
pub mod derived;
mod derived_rows;
mod edits;
mod expressions;
mod fate;
mod in_order;
pub mod job;
mod joints;
mod marked;
pub mod marker;
mod marker_fields;
mod moments;
mod names;
mod options;
mod outcome;
mod pass;
pub mod plan;
pub mod plot;
mod printed;
mod program;
mod progress;
mod refused;
pub mod runtime;
mod shared;
mod shared_first;
mod solve;
mod splice;
mod tail;
mod target;
mod write_file;
mod writers;

pub use edits::ORIENTATION_CHANGE_RAD;
pub use outcome::{
    Correction, Derived, Fate, Frame, FramesUse, Kind, LeftAlone, MoveCounts, MoveFate, Outcome,
    Reason, Residual, SharedUse, SplitTarget, Summary,
};

pub use options::{OnUntrusted, Options, ScheduleSource, When, ESTIMATE_ENCODING};
pub use program::{correct, correct_into, Corrected};
pub use writers::{ReportRows, Writers};
