//! `rapidtherm schedule -o FILE` writes the schedule file that
//! `Schedule::read` takes back, and writes nothing on error.

use rapidtherm::schedule::Schedule;
use std::process::Command;

fn rapidtherm() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rapidtherm"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

#[test]
fn output_file_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("times.csv");
    let status = rapidtherm()
        .args([
            "schedule",
            "samples/fixtures.mod",
            "--start",
            "40",
            "--cycles",
            "2",
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    assert!(status.stdout.is_empty(), "data goes to the file only");
    let bytes = std::fs::read(&out).unwrap();
    let s = Schedule::read("times.csv", &bytes).unwrap();
    // FOR i FROM 1 TO nPoints: 4 corners, each visited once per cycle.
    for k in 1..=4 {
        assert_eq!(s.times(&format!("pCorner{{{k}}}")).unwrap().len(), 2);
    }
    // pGrid{2,1} has a comma in its identifier: quoted, read back.
    assert_eq!(s.times("pGrid{2,1}").unwrap().len(), 2);
    assert!(s.times("pHome").unwrap().iter().all(|&t| t >= 40.0));
}

#[test]
fn nothing_written_on_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("times.csv");
    let status = rapidtherm()
        .args(["schedule", "samples/process_lib.sys", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(2));
    assert!(!out.exists());
    let stderr = String::from_utf8_lossy(&status.stderr);
    assert!(stderr.contains("rBead"), "{stderr}");
}

/// `schedule FILE` and `schedule -` (standard input) read the program
/// the same way (one parse, the fast lane inside it) and say the same:
/// the CSV, the notes, the errors (an unreachable target's) and the exit
/// code, on every sample.
#[test]
fn a_file_schedules_as_standard_input_does() {
    let dir = tempfile::tempdir().unwrap();
    let far = dir.path().join("far.mod");
    std::fs::write(
        &far,
        "MODULE far\n  PROC main()\n    MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z1, tool0;\n    MoveL [[5000,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z1, tool0;\n  ENDPROC\nENDMODULE\n",
    )
    .unwrap();
    let samples = concat!(env!("CARGO_MANIFEST_DIR"), "/samples");
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(samples)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "mod"))
        .collect();
    files.sort();
    files.push(far);
    for f in &files {
        let by_name = rapidtherm()
            .args(["schedule", "--start", "30", "--cycles", "2"])
            .arg(f)
            .output()
            .unwrap();
        let piped = rapidtherm()
            .args(["schedule", "--start", "30", "--cycles", "2", "-"])
            .stdin(std::fs::File::open(f).unwrap())
            .output()
            .unwrap();
        let name = f.display().to_string();
        let said =
            |o: &std::process::Output| String::from_utf8_lossy(&o.stderr).replace("<stdin>", &name);
        assert_eq!(by_name.status.code(), piped.status.code(), "{name}");
        assert_eq!(said(&by_name), said(&piped), "{name}");
        assert!(
            by_name.stdout == piped.stdout,
            "{name}: the schedules differ"
        );
    }
}
