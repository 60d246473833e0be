//! `.pre-commit-hooks.yaml`: the hook a RAPID repository adds runs as
//! pre-commit runs it (`entry`, then `args`, then the staged file names)
//! and passes on a corrected program, fails on an uncorrected one. A flag
//! renamed in the CLI and not in the hook breaks this test.

use std::path::Path;
use std::process::Command;
use yaml_rust2::{Yaml, YamlLoader};

const BIN: &str = env!("CARGO_BIN_EXE_rapidtherm");

fn hook() -> Yaml {
    let text = std::fs::read_to_string(".pre-commit-hooks.yaml").unwrap();
    let docs = YamlLoader::load_from_str(&text).unwrap();
    let hooks = docs[0].as_vec().expect("a list of hooks");
    hooks
        .iter()
        .find(|h| h["id"].as_str() == Some("rapidtherm-check"))
        .expect("the hook rapidtherm-check")
        .clone()
}

/// The hook's command line for `files`, with the binary cargo built in
/// place of the name on PATH that `language: rust` installs.
fn hook_command(hook: &Yaml, files: &[&Path]) -> Command {
    let entry: Vec<&str> = hook["entry"].as_str().unwrap().split_whitespace().collect();
    assert_eq!(
        entry[0], "rapidtherm",
        "the binary cargo install puts on PATH"
    );
    let mut c = Command::new(BIN);
    c.args(&entry[1..]);
    for a in hook["args"].as_vec().expect("args: a list") {
        c.arg(a.as_str().expect("args are strings"));
    }
    c.args(files);
    c
}

#[test]
fn the_hook_is_built_with_cargo_and_takes_rapid_files() {
    let h = hook();
    assert_eq!(h["language"].as_str(), Some("rust"));
    assert!(h["name"].as_str().is_some());
    // pre-commit matches with Python's `re`; this pattern means the same
    // in Rust's regex.
    let files = regex::Regex::new(h["files"].as_str().unwrap()).unwrap();
    for f in [
        "a.mod",
        "T_ROB1/MainModule.MOD",
        "b.modx",
        "c.prg",
        "d.sys",
        "e.SYS",
    ] {
        assert!(files.is_match(f), "{f}");
    }
    for f in ["a.mod.bak", "SYSPAR/MOC.cfg", "a.pgf", "notes.md", "mod"] {
        assert!(!files.is_match(f), "{f}");
    }
    // The staged modules of one program are read in one run.
    assert_eq!(h["require_serial"].as_bool(), Some(true));
}

#[test]
fn the_hook_fails_an_uncorrected_program_and_passes_it_corrected() {
    let h = hook();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cell.mod");
    std::fs::copy("tests/cmd/correct_data/cell.mod", &file).unwrap();
    let out = hook_command(&h, &[&file]).output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    // Corrected as the hook's args say, the program passes.
    let mut correct = Command::new(BIN);
    correct.args(["correct", "--in-place"]);
    for a in h["args"].as_vec().unwrap() {
        correct.arg(a.as_str().unwrap());
    }
    let done = correct.arg(&file).output().unwrap();
    assert!(done.status.success(), "{done:?}");
    let out = hook_command(&h, &[&file]).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
}
