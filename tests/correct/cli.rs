//! File handling of `rapidtherm correct`: atomic writes, backups, nothing
//! written on error, standard input and output.

use super::rapidtherm;
use std::path::PathBuf;
use std::process::{Command, Stdio};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/cmd/correct_data")
        .join(name)
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

/// The README's own command run twice: the second run finds the marker
/// and changes nothing, and the backup stays the cold original (before,
/// the file was corrected twice and `.orig` overwritten with the once
/// corrected one).
#[test]
fn in_place_twice_is_in_place_once() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cell.mod");
    std::fs::copy(data("cell.mod"), &file).unwrap();
    let args = [
        "correct",
        "cell.mod",
        "--at",
        "120",
        "--in-place",
        "--backup",
        ".orig",
    ];
    let first = rapidtherm(&args, dir.path());
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let once = std::fs::read(&file).unwrap();
    let second = rapidtherm(&args, dir.path());
    assert!(
        second.status.success(),
        "{}",
        String::from_utf8_lossy(&second.stderr)
    );
    assert!(String::from_utf8_lossy(&second.stderr).contains("already corrected"));
    assert_eq!(std::fs::read(&file).unwrap(), once);
    assert_eq!(
        std::fs::read(dir.path().join("cell.mod.orig")).unwrap(),
        std::fs::read(data("cell.mod")).unwrap()
    );
}

/// A backup that exists is never replaced, and then nothing is written.
#[test]
fn an_existing_backup_is_never_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cell.mod");
    std::fs::copy(data("cell.mod"), &file).unwrap();
    std::fs::write(dir.path().join("cell.mod.orig"), b"the only cold copy").unwrap();
    let out = rapidtherm(
        &[
            "correct",
            "cell.mod",
            "--at",
            "120",
            "--in-place",
            "--backup",
            ".orig",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("exists already"));
    assert_eq!(
        std::fs::read(dir.path().join("cell.mod.orig")).unwrap(),
        b"the only cold copy"
    );
    assert_eq!(
        std::fs::read(&file).unwrap(),
        std::fs::read(data("cell.mod")).unwrap()
    );
}

/// `--diff` of a Latin-1 program is in Latin-1: a unified-diff applier
/// (diffy, strict about context as `patch` is) applies it to the original
/// and gives what `-o` writes (before, it was transcoded to UTF-8 and
/// `patch` failed on the original).
#[test]
fn a_latin1_diff_applies_as_a_patch() {
    let dir = tempfile::tempdir().unwrap();
    let sample = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples/weld_cell_latin1.mod");
    let original = std::fs::read(&sample).unwrap();
    assert!(
        std::str::from_utf8(&original).is_err(),
        "the sample is Latin-1"
    );
    std::fs::write(dir.path().join("w.mod"), &original).unwrap();
    let diff = rapidtherm(&["correct", "w.mod", "--at", "120", "--diff"], dir.path());
    assert_eq!(diff.status.code(), Some(1));
    let corrected = rapidtherm(&["correct", "w.mod", "--at", "120", "-o", "-"], dir.path());
    assert!(corrected.status.success());
    assert!(
        std::str::from_utf8(&diff.stdout).is_err(),
        "the diff keeps the Latin-1 bytes"
    );
    let patch = diffy::Patch::from_bytes(&diff.stdout).expect("a unified diff");
    assert_eq!(patch.original(), Some(b"a/w.mod".as_slice()));
    assert_eq!(patch.modified(), Some(b"b/w.mod".as_slice()));
    let patched = diffy::apply_bytes(&original, &patch).expect("the diff applies");
    assert_eq!(patched, corrected.stdout);
}
