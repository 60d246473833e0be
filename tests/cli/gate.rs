//! The gate sees everything that moves the robot (issue 53): a robconf or
//! an external axis changed fails `diff --fail-above` whatever the
//! millimetres; a task without targets on both sides is equal, not
//! failed; limits beyond any thermal correction are usage errors before
//! any input is read. Each case passed (or failed) wrongly before.

use std::path::Path;
use std::process::{Command, Output};

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A module with robtarget p10 of robconf `conf` and external axes
/// `extax`, and jointtarget j10 of external axes `jextax`.
fn module(conf: &str, extax: &str, jextax: &str) -> String {
    format!(
        "MODULE Cell\n    CONST robtarget p10:=[[400,150,380],[0,0,1,0],[{conf}],[{extax}]];\n    CONST jointtarget j10:=[[0,0,0,0,30,0],[{jextax}]];\n    PROC main()\n        MoveAbsJ j10, v100, fine, tool0;\n        MoveL p10, v100, fine, tool0;\n    ENDPROC\nENDMODULE\n"
    )
}

const CONF: &str = "0,0,0,0";
const UNUSED: &str = "9E9,9E9,9E9,9E9,9E9,9E9";

/// `diff a.mod b.mod --fail-above 0.5` on the two texts.
fn gate(a: &str, b: &str) -> Output {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.mod"), a).unwrap();
    std::fs::write(dir.path().join("b.mod"), b).unwrap();
    run(
        dir.path(),
        &["diff", "a.mod", "b.mod", "--fail-above", "0.5"],
    )
}

// Before: the arm swinging through another configuration to the same
// pose passed a gate of 0.5 mm.
#[test]
fn a_robconf_changed_fails_the_gate() {
    let a = module(CONF, UNUSED, UNUSED);
    let out = gate(&a, &module("0,-1,0,0", UNUSED, UNUSED));
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    assert!(
        text(&out).contains("p10: robtarget moved 0.0000 mm"),
        "{}",
        text(&out)
    );
    assert!(text(&out).contains("robconf changed"), "{}", text(&out));
    // The same program passes.
    assert_eq!(gate(&a, &a).status.code(), Some(0));
}

// Before: a track axis now moving (9E+09 → 100) passed.
#[test]
fn an_external_axis_changed_fails_the_gate() {
    let a = module(CONF, UNUSED, UNUSED);
    let used = "100,9E9,9E9,9E9,9E9,9E9";
    for b in [module(CONF, used, UNUSED), module(CONF, UNUSED, used)] {
        let out = gate(&a, &b);
        assert_eq!(out.status.code(), Some(1), "{}", text(&out));
        assert!(
            text(&out).contains("an external axis changed"),
            "{}",
            text(&out)
        );
    }
    // A track moved by 20 mm: its value changed.
    let out = gate(
        &module(CONF, used, UNUSED),
        &module(CONF, "120,9E9,9E9,9E9,9E9,9E9", UNUSED),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    // The unused value written another way (as a controller saves it) is
    // the same value.
    let out = gate(
        &a,
        &module(CONF, "9E+09,9E+09,9E+09,9E+09,9E+09,9E+09", UNUSED),
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out));
}

/// `from` copied into `to`, folders and files.
pub(super) fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

// Before: a backup whose background task holds no targets failed the
// gate compared with itself ("nothing was compared, the gate fails").
#[test]
fn a_backup_compared_with_itself_passes() {
    let dir = tempfile::tempdir().unwrap();
    let backup = dir.path().join("backup");
    copy_tree(
        Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/samples/backup_multimove"
        )),
        &backup,
    );
    // T_COM's one robtarget (a message buffer) gone: a task without any.
    let comm = backup.join("RAPID/TASK3/PROGMOD/Comm.mod");
    let source = std::fs::read_to_string(&comm).unwrap();
    let without: String = source
        .lines()
        .filter(|l| !l.contains("robtarget"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_ne!(without, source);
    std::fs::write(&comm, without).unwrap();
    let out = run(
        dir.path(),
        &["diff", "backup", "backup", "--fail-above", "0.5"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", text(&out));
    // Two programs with targets but none in common still fail.
    let a = module(CONF, UNUSED, UNUSED);
    let b = a.replace("p10", "p11").replace("j10", "j11");
    let out = gate(&a, &b);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
}

// Before: `--tolerance 1e308` passed every check. A limit beyond any
// thermal correction is a usage error, raised before the input is read
// (the file named does not exist).
#[test]
fn limits_beyond_any_thermal_correction_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &[
            "correct",
            "none.mod",
            "--at",
            "120",
            "--check",
            "--tolerance",
            "1e308",
        ][..],
        &[
            "correct",
            "none.mod",
            "--at",
            "120",
            "--check",
            "--tolerance",
            "10.5",
        ],
        &["diff", "none.mod", "none.mod", "--fail-above", "1e308"],
        &[
            "diff",
            "none.mod",
            "none.mod",
            "--fail-above",
            "0.1",
            "--fail-above-deg",
            "90",
        ],
    ] {
        let out = run(dir.path(), args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", text(&out));
        let log = text(&out);
        assert!(!log.contains("none.mod"), "{args:?}: read before: {log}");
        assert!(log.len() < 400, "{args:?}: {log}");
    }
    let out = run(
        dir.path(),
        &[
            "correct",
            "none.mod",
            "--at",
            "120",
            "--check",
            "--tolerance",
            "10",
        ],
    );
    assert!(
        text(&out).contains("none.mod"),
        "10 mm is taken: {}",
        text(&out)
    );
}
