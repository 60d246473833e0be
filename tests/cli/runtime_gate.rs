//! `correct --runtime --check`, the CI gate on a program rewritten for the
//! controller (issue 48): it passed nothing before (a rewritten program
//! under `--check` was refused, exit 2). Exit 0 when every move calls the
//! module and the module beside is the one this version writes for the
//! program and model; exit 1 naming what is missing or stale; the
//! controller's own write-back of the heating state (its PERS lines) is
//! no change.

use super::outputs::{run, stderr};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A folder holding `fixtures.mod` rewritten by `--runtime` in place,
/// and its module beside it.
fn rewritten() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        root().join("samples/fixtures.mod"),
        dir.path().join("fixtures.mod"),
    )
    .unwrap();
    let out = run(
        dir.path(),
        &["correct", "fixtures.mod", "--runtime", "--in-place"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    dir
}

fn gate(dir: &Path) -> (Option<i32>, String) {
    let out = run(dir, &["correct", "fixtures.mod", "--runtime", "--check"]);
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), stderr(&out));
    (out.status.code(), text)
}

#[test]
fn the_gate_passes_a_rewritten_program_with_its_module() {
    let dir = rewritten();
    let (code, text) = gate(dir.path());
    assert_eq!(code, Some(0), "{text}");
}

#[test]
fn the_gate_fails_a_program_not_rewritten() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        root().join("samples/fixtures.mod"),
        dir.path().join("fixtures.mod"),
    )
    .unwrap();
    let (code, text) = gate(dir.path());
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("not rewritten for the controller"), "{text}");
}

#[test]
fn the_gate_names_a_missing_or_stale_module() {
    let dir = rewritten();
    let module = dir.path().join("RtWarm.sys");
    let good = std::fs::read_to_string(&module).unwrap();
    // A number of the arm edited: not the module this version writes.
    let edited = good.replacen(
        "LOCAL CONST num rtStopGap := 5;",
        "LOCAL CONST num rtStopGap := 6;",
        1,
    );
    assert_ne!(edited, good);
    std::fs::write(&module, &edited).unwrap();
    let (code, text) = gate(dir.path());
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("not the module rapidtherm"), "{text}");
    // The state written back by the controller (its PERS lines, six
    // digits) is no change.
    let saved = good.replacen(
        "LOCAL PERS bool rtKnown := FALSE;",
        "LOCAL PERS bool rtKnown:=TRUE;",
        1,
    );
    assert_ne!(saved, good);
    std::fs::write(&module, &saved).unwrap();
    assert_eq!(gate(dir.path()).0, Some(0));
    std::fs::remove_file(&module).unwrap();
    let (code, text) = gate(dir.path());
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("the module is missing"), "{text}");
}

#[test]
fn the_gate_names_a_move_added_after_the_rewrite() {
    let dir = rewritten();
    let file = dir.path().join("fixtures.mod");
    let text = std::fs::read_to_string(&file).unwrap();
    // A move written on the pendant after the rewrite, to a declared
    // target: it does not call the module.
    let at = text.find("ENDPROC").unwrap();
    let added = format!(
        "{}  MoveJ pHome, v1000, z50, tGlue;\r\n  {}",
        &text[..at],
        &text[at..]
    );
    std::fs::write(&file, added).unwrap();
    let (code, text) = gate(dir.path());
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("do not call RtWarm"), "{text}");
}

#[test]
fn a_second_run_on_the_rewritten_program_writes_the_same_module() {
    let dir = rewritten();
    let module = dir.path().join("RtWarm.sys");
    let first = std::fs::read(&module).unwrap();
    let out = run(
        dir.path(),
        &["correct", "fixtures.mod", "--runtime", "--in-place"],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(std::fs::read(&module).unwrap(), first, "the table kept");
}
