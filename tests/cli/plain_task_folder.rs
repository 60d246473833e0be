//! A repository that keeps only `RAPID/TASK1` (the programs, as cell
//! engineers version them; no `BACKINFO/` or `SYSPAR/` beside) is not a
//! broken controller backup: its task folder is read as its modules, as
//! the files named one by one would be (issue 49: it was refused, exit 2,
//! for lacking backinfo.txt, SYS.cfg and MOC.cfg). A folder with either
//! part is a backup and keeps the backup's rules.

use std::path::Path;
use std::process::{Command, Output};

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A temporary repository holding `RAPID/TASK1/PROGMOD/fixtures.mod`
/// only (the sample program; its moves reach 14 of its targets, three
/// are unused).
fn repository() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    let progmod = dir.path().join("RAPID/TASK1/PROGMOD");
    std::fs::create_dir_all(&progmod).expect("folders");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/samples/fixtures.mod"),
        progmod.join("fixtures.mod"),
    )
    .expect("copied");
    dir
}

const MODULE: &str = "RAPID/TASK1/PROGMOD/fixtures.mod";
const NOTE: &str = "read as a task folder, not a controller backup";

#[test]
fn a_task_folder_without_backinfo_or_syspar_is_read_as_its_modules() {
    let dir = repository();
    let at = dir.path();
    // The module named alone: the reference (files one by one never were
    // a backup).
    let alone = run(at, &["correct", MODULE, "--at", "60", "-o", "alone.mod"]);
    assert_eq!(alone.status.code(), Some(0), "{}", stderr(&alone));
    // The task folder, its RAPID folder and the repository root: each
    // the same one task, checked (uncorrected, so the gate fails: exit
    // 1, not the usage/input error 2 of a backup missing its parts).
    for named in ["RAPID/TASK1", "RAPID", "."] {
        let o = run(
            at,
            &[
                "correct", named, "--at", "60", "--check", "--accept", "unused",
            ],
        );
        let said = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{named}: {said}");
        assert!(
            said.contains("14 target(s) would move more than 0.001 mm"),
            "{named}: {said}"
        );
        assert!(!said.contains("the backup has no"), "{named}: {said}");
        // Where it matters, the arm taken by default is said to be no
        // backup's, with the way to name another.
        assert!(said.contains(NOTE), "{named}: {said}");
        assert!(said.contains("--robot TASK1="), "{named}: {said}");
    }
    // Corrected in place through the task folder: the file is what the
    // module named alone gives, and the gate then passes.
    let o = run(at, &["correct", "RAPID/TASK1", "--at", "60", "--in-place"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(at.join(MODULE)).expect("read"),
        std::fs::read(at.join("alone.mod")).expect("read")
    );
    let o = run(
        at,
        &[
            "correct",
            "RAPID/TASK1",
            "--at",
            "60",
            "--check",
            "--accept",
            "unused",
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// The note is said where an arm is taken by default only: not when the
/// user named the arm, and not by a command that takes none.
#[test]
fn the_note_is_said_only_where_the_arm_is_a_default() {
    let dir = repository();
    let named_arm = run(
        dir.path(),
        &[
            "correct",
            "RAPID/TASK1",
            "--at",
            "60",
            "--check",
            "--robot",
            "irb140",
        ],
    );
    assert_eq!(named_arm.status.code(), Some(1), "{}", stderr(&named_arm));
    assert!(!stderr(&named_arm).contains(NOTE), "{}", stderr(&named_arm));
    let targets = run(dir.path(), &["targets", "RAPID/TASK1"]);
    assert_eq!(targets.status.code(), Some(0), "{}", stderr(&targets));
    assert!(!stderr(&targets).contains(NOTE), "{}", stderr(&targets));
    // -q hides notes, as every note.
    let quiet = run(dir.path(), &["-q", "correct", "RAPID/TASK1", "--at", "60"]);
    assert_eq!(quiet.status.code(), Some(0), "{}", stderr(&quiet));
    assert!(!stderr(&quiet).contains(NOTE), "{}", stderr(&quiet));
}

/// `BACKINFO/` or `SYSPAR/` (any case, as a copy through Windows leaves
/// it) makes the folder a backup, and a backup missing its other parts
/// is refused naming each, as before.
#[test]
fn a_folder_with_backinfo_or_syspar_keeps_the_backups_rules() {
    let cases: [(&str, &str, &[&str]); 3] = [
        (
            "SYSPAR",
            "",
            &[
                "the backup has no BACKINFO/backinfo.txt",
                "the backup has no SYSPAR/SYS.cfg",
                "the backup has no SYSPAR/MOC.cfg",
            ],
        ),
        ("syspar", "", &["the backup has no BACKINFO/backinfo.txt"]),
        (
            "BACKINFO",
            "backinfo.txt",
            &[
                "the backup has no SYSPAR/SYS.cfg",
                "the backup has no SYSPAR/MOC.cfg",
            ],
        ),
    ];
    for (part, file, missing) in cases {
        let dir = repository();
        std::fs::create_dir(dir.path().join(part)).expect("folder");
        if !file.is_empty() {
            std::fs::write(
                dir.path().join(part).join(file),
                ">>TASK1: (T_ROB1,,)\nPROGMOD/fixtures.mod @ fixtures.mod\n\n",
            )
            .expect("written");
        }
        for named in ["RAPID/TASK1", "."] {
            let o = run(dir.path(), &["correct", named, "--at", "60", "--check"]);
            let said = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{part} {named}: {said}");
            for m in missing {
                assert!(said.contains(m), "{part} {named}: {m}: {said}");
            }
            assert!(!said.contains(NOTE), "{part} {named}: {said}");
        }
    }
}
