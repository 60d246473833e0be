//! Integration tests of the `rapid` layer, one binary (one link) for all
//! of them: a test binary per file made the clean build minutes longer.

mod backups;
mod field;
mod lane;
mod limits;
mod proptest;
mod rewrite;
mod samples;
mod task;
#[path = "../common/ways.rs"]
mod ways;
