//! From a program's RAPID values to robot frames: its tooldata and
//! wobjdata as [`ToolData`]/[`WobjData`], each robtarget as a pose with its
//! robconf, and for each target the tool and work object the program moves
//! to it with.
//!
//! Owns what a program means by its targets, shared by `schedule`,
//! `correct` and `diagnose` (programs as pose sets). May import `rapid`,
//! `robot` and the shared `error`; never `model`, `schedule` or the jobs.

pub mod arm;
mod by_name;
mod calls;
pub mod dataflow;
mod each_move;
mod frame_vars;
mod frames;
mod glob;
pub mod listing;
pub mod monitoring;
mod moves;
mod params;
mod per_call;
mod refs;
mod statements;
mod usage;
mod usages;
mod uses;

pub use by_name::ByName;
pub use dataflow::root_name;
pub use frame_vars::frame_variables;
pub use frames::{
    frames_for, frames_for_in, frames_named, frames_named_in, frames_of, robconf_of, target_pose,
    unsupported, Frames, FramesFound,
};
pub use moves::{each_move_instruction, each_move_instruction_with, Move, Point};
pub use params::settled_parameters;
pub use per_call::unsettled_frame_parameters;
pub use statements::{walk_calls, walk_items, walk_statements};
pub use usage::{uses_by_frames, Through, Usage};
pub use usages::{declared_derived_usages, usages, uses, uses_with, MoveLookup};
pub use uses::{UseRef, Uses};
