//! Integration tests of the `correct` layer, one binary (one link) for all
//! of them: a test binary per file made the clean build minutes longer.

#[path = "../common/mod.rs"]
mod common;

mod backup;
mod cli;
mod plot;
mod samples;
mod shared;
mod streaming;
mod streaming_schedule;
mod trust;
