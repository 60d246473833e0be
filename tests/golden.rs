//! Golden files of the main job: for every sample program, the corrected
//! program (`correct --at 120 -o -`) and the diff of original against
//! corrected (`diff --format csv`), produced by the real binary. Any
//! difference fails; regenerate deliberately with
//! `RAPIDTHERM_BLESS=1 cargo test --test golden` and review the change.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn samples() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(root().join("samples"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("mod" | "modx" | "prg" | "sys")
            )
        })
        .collect();
    out.sort();
    out
}

fn rapidtherm(args: &[&str]) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "rapidtherm {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// Compare with the golden file, or write it when blessing.
fn check(golden: &Path, actual: &[u8], failures: &mut Vec<String>) {
    if std::env::var_os("RAPIDTHERM_BLESS").is_some() {
        std::fs::write(golden, actual).unwrap();
        return;
    }
    match std::fs::read(golden) {
        Ok(expected) if expected == actual => {}
        Ok(_) => failures.push(format!("{} differs", golden.display())),
        Err(_) => failures.push(format!("{} is missing", golden.display())),
    }
}

#[test]
fn corrected_programs_and_diffs_match_the_golden_files() {
    let dir = root().join("tests/golden");
    let mut failures = Vec::new();
    for sample in samples() {
        let name = sample.file_name().unwrap().to_string_lossy().into_owned();
        let rel = format!("samples/{name}");
        let corrected = rapidtherm(&["correct", &rel, "--at", "120", "-o", "-"]);
        check(
            &dir.join(format!("{name}.at120")),
            &corrected,
            &mut failures,
        );
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join(&name);
        std::fs::write(&out, &corrected).unwrap();
        let diff = rapidtherm(&["diff", &rel, out.to_str().unwrap(), "--format", "csv"]);
        check(
            &dir.join(format!("{name}.at120.diff.csv")),
            &diff,
            &mut failures,
        );
    }
    assert!(
        failures.is_empty(),
        "golden files differ (regenerate with RAPIDTHERM_BLESS=1 cargo test --test golden):\n{}",
        failures.join("\n")
    );
}
