//! File handling of `rapidtherm correct`: atomic writes, backups, nothing
//! written on error, standard input and output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/cmd/correct_data")
        .join(name)
}

fn rapidtherm(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn in_place_with_backup_keeps_the_original_and_permissions() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cell.mod");
    std::fs::copy(data("cell.mod"), &file).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o600)).unwrap();
    }
    let out = rapidtherm(
        &[
            "correct",
            "cell.mod",
            "--at",
            "60",
            "--in-place",
            "--backup",
            ".orig",
        ],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let original = std::fs::read(data("cell.mod")).unwrap();
    assert_eq!(
        std::fs::read(dir.path().join("cell.mod.orig")).unwrap(),
        original
    );
    let corrected = std::fs::read(&file).unwrap();
    assert_ne!(corrected, original);
    assert_eq!(corrected, std::fs::read(data("cell_at60.mod")).unwrap());
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&file).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600);
    }
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 2, "no temporary file is left behind");
}

#[test]
fn an_error_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("unreachable.mod"), dir.path().join("u.mod")).unwrap();
    let out = rapidtherm(
        &["correct", "u.mod", "--at", "60", "-o", "out.mod"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.path().join("out.mod").exists());
    let before = std::fs::read(dir.path().join("u.mod")).unwrap();
    let out = rapidtherm(
        &["correct", "u.mod", "--at", "60", "--in-place"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read(dir.path().join("u.mod")).unwrap(), before);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn standard_input_to_standard_output() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(["correct", "-", "--at", "60", "-o", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let input = std::fs::read(data("cell.mod")).unwrap();
    use std::io::Write;
    child.stdin.take().unwrap().write_all(&input).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(out.stdout, std::fs::read(data("cell_at60.mod")).unwrap());
    // The summary goes to stderr, never into the program.
    assert!(String::from_utf8_lossy(&out.stderr).contains("3 target(s) corrected"));
}
