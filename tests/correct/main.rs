//! Integration tests of the `correct` layer, one binary (one link) for all
//! of them: a test binary per file made the clean build minutes longer.

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/ways.rs"]
mod ways;

mod accounted;
mod backup;
mod cli;
mod data_rules;
mod idle;
mod interp;
mod interp_controller;
mod interp_rules;
mod interp_targets;
mod lanes;
mod line_ends;
mod marker;
mod named;
mod named_elsewhere;
mod plot;
mod robot_types;
mod runtime;
mod samples;
mod seal;
mod shared;
mod streaming;
mod trust;

use std::path::Path;
use std::process::{Command, Output};

/// The binary run with `args` in `dir`.
fn rapidtherm<S: AsRef<std::ffi::OsStr>>(args: &[S], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// The run exited with `code` (its messages shown where it did not).
fn assert_exit(out: &Output, code: i32) {
    assert_eq!(
        out.status.code(),
        Some(code),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
