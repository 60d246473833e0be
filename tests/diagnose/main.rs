//! Integration tests of the `diagnose` layer, one binary (one link) for all
//! of them: a test binary per file made the clean build minutes longer.

#[path = "../common/mod.rs"]
mod common;

mod blind;
mod chain;
mod cli;
mod data_rules;
mod eval;
mod fit;
mod general;
mod loop_model;
mod loop_program;
mod nuisance;
mod nuisance_ur5;
mod poses;
mod real_plausible;
mod robust;
mod rules;
mod saved;
mod static_rank;
mod urdf;
mod wide;
mod wide_ci;
mod world;
mod world_ur5;
