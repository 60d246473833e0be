//! Nothing lost: every output of a run is checked before anything is
//! written (an output that is one of the run's inputs, a plot folder under
//! a file, a read-only file), a replaced file keeps its owner and mode;
//! and nothing assumed: measurement sets a diagnosis cannot mean anything
//! on (one point, metres, copied rows, one label on two poses) are refused.

use super::hostile::snapshot;
use std::path::Path;
use std::process::{Command, Output};

pub(super) fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

pub(super) fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Exit 2, and the message says `words`.
pub(super) fn refused(out: &Output, words: &str) {
    assert_eq!(out.status.code(), Some(2), "{}", stderr(out));
    assert!(
        stderr(out).contains(words),
        "`{words}` not in: {}",
        stderr(out)
    );
}

/// Simulated measurements of the IRB 140: 8 poses at 0, 60 and 120 min.
fn measured(dir: &Path) -> String {
    let out = run(
        dir,
        &[
            "simulate", "--poses", "random:8", "--times", "0,60,120", "--noise", "0.02",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    String::from_utf8(out.stdout).unwrap()
}

const PROGRAM: &str = "MODULE M\n  CONST robtarget p1:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    MoveL p1,v100,fine,tool0;\n  ENDPROC\nENDMODULE\n";

#[test]
fn an_output_that_is_an_input_of_the_run_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.csv"), measured(d)).unwrap();
    std::fs::write(d.join("x.mod"), PROGRAM).unwrap();
    std::fs::write(
        d.join("heat.csv"),
        "time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c\n0,20,20,20,20,20,20\n30,25,26,27,24,23,22\n60,28,29,30,27,25,24\n90,30,31,32,29,27,25\n120,31,32,33,30,28,26\n",
    )
    .unwrap();
    let before = snapshot(d);
    for (args, words) in [
        (
            &["heating", "fit", "heat.csv", "--plot", "heat.csv"][..],
            "--plot heat.csv: that is an input of this run",
        ),
        (
            &["simulate", "--poses", "program:x.mod", "-o", "x.mod"][..],
            "-o x.mod: that is an input of this run",
        ),
        (
            &["simulate", "--poses", "program:x.mod", "-o", "./x.mod"][..],
            "that is an input of this run",
        ),
        (
            &["schedule", "x.mod", "-o", "x.mod"][..],
            "-o x.mod: that is an input of this run",
        ),
        (
            &["diagnose", "a.csv", "--save-model", "a.csv"][..],
            "--save-model a.csv: that is an input of this run",
        ),
    ] {
        let out = run(d, args);
        refused(&out, words);
        assert_eq!(snapshot(d), before, "rapidtherm {args:?} wrote");
    }
}

#[test]
fn a_plot_folder_under_a_file_is_named_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.csv"), measured(d)).unwrap();
    std::fs::write(d.join("file"), "not a folder").unwrap();
    let before = snapshot(d);
    let out = run(
        d,
        &[
            "diagnose",
            "a.csv",
            "--plot",
            "file/sub",
            "--save-model",
            "m.toml",
        ],
    );
    refused(&out, "--plot file/sub: `file` is a file, not a folder");
    assert!(!stderr(&out).contains("os error"), "{}", stderr(&out));
    assert_eq!(snapshot(d), before);
    // A save-model file in a missing folder: refused before the plots.
    let out = run(
        d,
        &[
            "diagnose",
            "a.csv",
            "--plot",
            "plots",
            "--save-model",
            "no/such/m.toml",
        ],
    );
    refused(&out, "the folder `no/such` does not exist");
    assert!(!d.join("plots").exists(), "the plots were written");
    assert_eq!(snapshot(d), before);
    // A correction in place with such a plot folder leaves the program.
    std::fs::write(d.join("x.mod"), PROGRAM).unwrap();
    let before = snapshot(d);
    let out = run(
        d,
        &[
            "correct",
            "x.mod",
            "--at",
            "120",
            "--in-place",
            "--plot",
            "file/sub",
        ],
    );
    refused(&out, "--plot file/sub: `file` is a file, not a folder");
    assert_eq!(snapshot(d), before);
}

#[cfg(unix)]
#[test]
fn a_read_only_file_is_not_replaced() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("x.mod"), PROGRAM).unwrap();
    std::fs::set_permissions(d.join("x.mod"), std::fs::Permissions::from_mode(0o444)).unwrap();
    std::fs::write(d.join("out.mod"), "old").unwrap();
    std::fs::set_permissions(d.join("out.mod"), std::fs::Permissions::from_mode(0o444)).unwrap();
    let before = snapshot(d);
    for args in [
        &["correct", "x.mod", "--at", "120", "--in-place"][..],
        &["correct", "x.mod", "--at", "120", "-o", "out.mod"][..],
    ] {
        let out = run(d, args);
        refused(&out, "is read-only, so it is not replaced");
        assert_eq!(snapshot(d), before, "rapidtherm {args:?} wrote");
    }
    // Made writable by its owner, it is replaced, and keeps its mode.
    std::fs::set_permissions(d.join("x.mod"), std::fs::Permissions::from_mode(0o640)).unwrap();
    let out = run(d, &["correct", "x.mod", "--at", "120", "--in-place"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_ne!(std::fs::read(d.join("x.mod")).unwrap(), PROGRAM.as_bytes());
    let mode = std::fs::metadata(d.join("x.mod"))
        .unwrap()
        .permissions()
        .mode()
        & 0o777;
    assert_eq!(mode, 0o640);
}

#[cfg(unix)]
#[test]
fn a_replaced_file_keeps_its_owner() {
    use std::os::unix::fs::MetadataExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let p = d.join("x.mod");
    std::fs::write(&p, PROGRAM).unwrap();
    // Another owner can only be given by a privileged user; as any other,
    // the file is this user's and must stay so.
    let other = std::os::unix::fs::chown(&p, Some(4242), Some(4243)).is_ok();
    let (uid, gid) = {
        let m = std::fs::metadata(&p).unwrap();
        (m.uid(), m.gid())
    };
    assert!(!other || (uid, gid) == (4242, 4243));
    let out = run(d, &["correct", "x.mod", "--at", "120", "--in-place"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let m = std::fs::metadata(&p).unwrap();
    assert_eq!((m.uid(), m.gid()), (uid, gid));
    assert_ne!(std::fs::read(&p).unwrap(), PROGRAM.as_bytes());
}

/// The rows of a measurements CSV, header apart.
fn rows(csv: &str) -> (String, Vec<String>) {
    let mut lines = csv.lines();
    let header = lines.next().unwrap().to_string();
    (header, lines.map(str::to_string).collect())
}

fn with_position(row: &str, xyz: [f64; 3], scale: f64) -> String {
    let mut f: Vec<String> = row.split(',').map(str::to_string).collect();
    let n = f.len();
    for k in 0..3 {
        let v: f64 = f[n - 3 + k].parse().unwrap();
        f[n - 3 + k] = format!("{:.6}", if scale > 0.0 { v * scale } else { xyz[k] });
    }
    f.join(",")
}

#[test]
fn measurements_a_diagnosis_cannot_mean_anything_on_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (header, good) = rows(&measured(d));
    let write = |name: &str, rows: &[String]| {
        std::fs::write(d.join(name), format!("{header}\n{}\n", rows.join("\n"))).unwrap();
    };
    write("good.csv", &good);
    let out = run(d, &["diagnose", "good.csv"]);
    assert!(
        out.status.code() != Some(2),
        "the unchanged set is diagnosed: {}",
        stderr(&out)
    );

    let same: Vec<String> = good
        .iter()
        .map(|r| with_position(r, [400.0, 0.0, 700.0], 0.0))
        .collect();
    write("same.csv", &same);
    let metres: Vec<String> = good
        .iter()
        .map(|r| with_position(r, [0.0; 3], 1e-3))
        .collect();
    write("metres.csv", &metres);
    let mut copied = vec![good[0].clone(); 128];
    copied.extend(good[1..].iter().cloned());
    write("copied.csv", &copied);
    // P2's label on P1's row at the next time.
    let mut relabelled = good.clone();
    let i = good.iter().rposition(|r| r.starts_with("P1,")).unwrap();
    relabelled[i] = relabelled[i].replacen("P1,", "P2,", 1);
    write("relabelled.csv", &relabelled);

    for command in ["diagnose", "gap"] {
        for (file, words) in [
            ("same.csv", "measured positions are the same point"),
            ("metres.csv", "metres instead of millimetres"),
            ("copied.csv", "repeat line 2 exactly"),
            (
                "relabelled.csv",
                "pose `P2` has other joints here than at line",
            ),
        ] {
            let out = run(d, &[command, file]);
            refused(&out, words);
            assert!(stderr(&out).contains(file), "{}", stderr(&out));
        }
    }
}

#[test]
fn the_gap_gate_is_checked_before_reading_and_never_passed_by_nan() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &["gap", "missing.csv", "--fail-above", "NaN"]);
    refused(&out, "--fail-above must be a number of mm >= 0");
}

#[cfg(unix)]
#[test]
fn a_device_takes_a_correction_whether_or_not_it_changes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("x.mod"), PROGRAM).unwrap();
    // Unchanged at minute 0 and at the start of a schedule: the program is
    // written as read, which a device cannot be rewound for.
    for args in [
        &["correct", "x.mod", "--at", "0", "-o", "/dev/null"][..],
        &["correct", "x.mod", "--start", "0", "-o", "/dev/null"][..],
        &["correct", "x.mod", "--at", "120", "-o", "/dev/null"][..],
    ] {
        let out = run(d, args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    }
    assert_eq!(std::fs::read(d.join("x.mod")).unwrap(), PROGRAM.as_bytes());
}
