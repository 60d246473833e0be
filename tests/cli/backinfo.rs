//! A rewritten controller backup lists the run-time module in
//! `BACKINFO/backinfo.txt`, which a restore reads to know what each task
//! loads (issue 48): each motion task's section gains the module's entry,
//! in the file's own form, and a second run changes nothing.

use super::gate::copy_tree;
use super::hostile::snapshot;
use super::outputs::{run, stderr};
use std::path::{Path, PathBuf};

/// The module lines of each `>>TASKn:` section of a backinfo.txt, by
/// the section's header, read apart from the code under test.
fn sections(text: &str) -> Vec<(String, Vec<String>)> {
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for line in text.lines() {
        if line.starts_with(">>") {
            out.push((line.to_string(), Vec::new()));
        } else if !line.trim().is_empty() {
            if let Some((_, lines)) = out.last_mut() {
                lines.push(line.to_string());
            }
        }
    }
    out.retain(|(h, _)| h.starts_with(">>TASK"));
    out
}

fn backup(dir: &Path) -> PathBuf {
    let bk = dir.join("bk");
    copy_tree(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples/backup_multimove"),
        &bk,
    );
    bk
}

#[test]
fn the_rewritten_backup_lists_the_module_for_each_motion_task() {
    let dir = tempfile::tempdir().unwrap();
    let bk = backup(dir.path());
    let info = bk.join("BACKINFO/backinfo.txt");
    let before = std::fs::read_to_string(&info).unwrap();
    let o = run(dir.path(), &["correct", "bk", "--runtime", "--in-place"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // Announced as every file written is.
    let wrote = format!("wrote {}", Path::new("bk/BACKINFO/backinfo.txt").display());
    assert!(stderr(&o).contains(&wrote), "{}", stderr(&o));
    let after = std::fs::read_to_string(&info).unwrap();
    // Worked by hand from the sample: T_ROB1 and T_ROB2 move a robot
    // (SYS.cfg), each loads user.sys from SYSMOD; T_COM moves none.
    let want = [
        (
            ">>TASK1: (T_ROB1,,)",
            vec![
                "SYSMOD/user.sys @ ",
                "SYSMOD/RtWarm.sys @ ",
                "PROGMOD/MainModule.mod @ ",
                "PROGMOD/ScanPath.mod @ ",
            ],
        ),
        (
            ">>TASK2: (T_ROB2,,)",
            vec![
                "SYSMOD/user.sys @ ",
                "SYSMOD/RtWarm.sys @ ",
                "PROGMOD/1_T_ROB2.mod @ ",
            ],
        ),
        (
            ">>TASK3: (T_COM,,)",
            vec!["SYSMOD/user.sys @ ", "PROGMOD/Comm.mod @ "],
        ),
    ];
    let got = sections(&after);
    let got: Vec<(&str, Vec<&str>)> = got
        .iter()
        .map(|(h, l)| (h.as_str(), l.iter().map(String::as_str).collect()))
        .collect();
    assert_eq!(got, want);
    // Each module listed is in its task's folder.
    for task in ["TASK1", "TASK2"] {
        assert!(bk
            .join("RAPID")
            .join(task)
            .join("SYSMOD/RtWarm.sys")
            .is_file());
    }
    // Nothing else of the file changed: two lines more.
    assert_eq!(after.lines().count(), before.lines().count() + 2);
    assert_eq!(
        after.replace("SYSMOD/RtWarm.sys @ \n", ""),
        before,
        "only the entries are added"
    );

    // A second run: the backup stays as it is, backinfo.txt included.
    let kept = snapshot(&bk);
    let o = run(dir.path(), &["correct", "bk", "--runtime", "--in-place"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("backinfo.txt"), "{}", stderr(&o));
    assert_eq!(snapshot(&bk), kept);
}

#[test]
fn the_diff_shows_the_entries_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bk = backup(dir.path());
    let kept = snapshot(&bk);
    let o = run(dir.path(), &["correct", "bk", "--runtime", "--diff"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("+SYSMOD/RtWarm.sys @ "),
        "{out}\n{}",
        stderr(&o)
    );
    assert_eq!(out.matches("+SYSMOD/RtWarm.sys @ ").count(), 2, "{out}");
    assert_eq!(snapshot(&bk), kept);
}
