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
