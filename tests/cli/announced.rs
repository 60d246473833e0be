//! Every file a run writes is named on standard error, `wrote PATH`, once
//! it is in place (docs/conventions.md, issue 49): once per file, none
//! under `-q`, none for standard output, and none when the run is refused.
//! The files expected are written out by hand from each command's `--help`,
//! and checked against the folder as the run left it.

use super::hostile::snapshot;
use super::outputs::{run, stderr};
use std::path::{Path, PathBuf};

const PROGRAM: &str = "MODULE M\n  CONST robtarget p1:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    MoveL p1,v100,fine,tool0;\n  ENDPROC\nENDMODULE\n";

/// The paths of the `wrote` lines of a run's standard error, in order.
fn announced(err: &str) -> Vec<String> {
    err.lines()
        .filter_map(|l| l.strip_prefix("wrote "))
        .map(str::to_string)
        .collect()
}

/// The files new or changed in `dir` between two snapshots, relative.
fn changed(dir: &Path, before: &[(PathBuf, String)], after: &[(PathBuf, String)]) -> Vec<String> {
    let mut out: Vec<String> = after
        .iter()
        .filter(|a| a.1 != "dir" && !before.contains(a))
        .map(|(p, _)| p.strip_prefix(dir).unwrap().display().to_string())
        .collect();
    out.sort();
    out
}

fn files(dir: &Path) -> Vec<(PathBuf, String)> {
    snapshot(dir)
        .into_iter()
        .map(|(p, (h, _))| (p, h))
        .collect()
}

/// Each writing command, with the files it writes, in the order they are
/// announced (a run's files by name).
fn cases() -> Vec<(Vec<&'static str>, Vec<&'static str>)> {
    vec![
        (
            vec!["correct", "a.mod", "--at", "60", "-o", "c.mod"],
            vec!["c.mod"],
        ),
        (
            vec!["correct", "a.mod", "--at", "60", "--in-place"],
            vec!["a.mod"],
        ),
        (
            vec!["correct", "a.mod", "--runtime", "-o", "out.mod"],
            vec!["RtWarm.sys", "out.mod"],
        ),
        (vec!["schedule", "a.mod", "-o", "s.csv"], vec!["s.csv"]),
        (
            vec![
                "simulate", "--poses", "random:3", "--times", "0,60", "-o", "m.csv",
            ],
            vec!["m.csv"],
        ),
    ]
}

#[test]
fn each_file_written_is_announced_once_and_none_under_quiet() {
    for (args, expected) in cases() {
        for quiet in [false, true] {
            let dir = tempfile::tempdir().unwrap();
            let d = dir.path();
            std::fs::write(d.join("a.mod"), PROGRAM).unwrap();
            let before = files(d);
            let mut args = args.clone();
            if quiet {
                args.push("-q");
            }
            let out = run(d, &args);
            assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
            // The files are written whatever -q says.
            assert_eq!(changed(d, &before, &files(d)), expected, "{args:?}");
            let said = announced(&stderr(&out));
            if quiet {
                assert!(said.is_empty(), "{args:?} announced {said:?}");
            } else {
                assert_eq!(said, expected, "{args:?}: {}", stderr(&out));
            }
        }
    }
}

#[test]
fn standard_output_a_check_and_a_refused_run_announce_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.mod"), PROGRAM).unwrap();
    std::fs::write(d.join("bad.mod"), "MODULE M\n  PROC main(\nENDMODULE\n").unwrap();
    let before = files(d);
    for (args, code) in [
        (vec!["correct", "a.mod", "--at", "60", "-o", "-"], 0),
        (vec!["schedule", "a.mod"], 0),
        (vec!["correct", "a.mod", "--at", "60", "--check"], 1),
        // The output is the input: refused before anything is read.
        (vec!["correct", "a.mod", "--at", "60", "-o", "a.mod"], 2),
        // The program does not parse: refused once read, nothing written.
        (vec!["correct", "bad.mod", "--at", "60", "-o", "c.mod"], 2),
        (vec!["correct", "bad.mod", "--runtime", "-o", "c.mod"], 2),
        (vec!["schedule", "bad.mod", "-o", "s.csv"], 2),
        (vec!["simulate", "--times", "60:0:1", "-o", "m.csv"], 2),
    ] {
        let out = run(d, &args);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {}", stderr(&out));
        assert_eq!(announced(&stderr(&out)), Vec::<String>::new(), "{args:?}");
        assert_eq!(files(d), before, "{args:?} wrote");
    }
}
