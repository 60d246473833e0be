//! The README's commands run as written (issue 49: its tour named files,
//! `cell.mod`, `session.csv`, `arm.urdf`, that are nowhere): every
//! `rapidtherm` line of its `sh` blocks, in order, in a folder holding
//! copies of the repository's own files it names (samples/, tests/data/),
//! each ending with the exit status its comment says (`exit 1`, else 0).

use super::gate::copy_tree;
use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Each `rapidtherm` line of the `sh` blocks of a Markdown text: its
/// words, and the exit status its comment says.
pub(super) fn command_lines(markdown: &str) -> Vec<(Vec<String>, i32)> {
    let mut out = Vec::new();
    let mut in_sh = false;
    for line in markdown.lines() {
        let t = line.trim();
        if let Some(lang) = t.strip_prefix("```") {
            in_sh = !in_sh && (lang == "sh" || lang == "bash");
            continue;
        }
        if !in_sh || !t.starts_with("rapidtherm ") {
            continue;
        }
        let (command, comment) = t.split_once(" #").unwrap_or((t, ""));
        let exit = if comment.contains("exit 1") { 1 } else { 0 };
        out.push((
            command.split_whitespace().map(str::to_string).collect(),
            exit,
        ));
    }
    out
}

#[test]
fn every_readme_command_runs_on_the_repositorys_files() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = command_lines(&readme);
    assert!(lines.len() > 20, "{} lines", lines.len());
    let dir = tempfile::tempdir().unwrap();
    copy_tree(&root().join("samples"), &dir.path().join("samples"));
    copy_tree(&root().join("tests/data"), &dir.path().join("tests/data"));
    for (words, exit) in lines {
        for w in &words {
            // A file the line reads is the repository's own, or one an
            // earlier line wrote (no placeholder like `cell.mod`).
            if w.contains('/') && !w.starts_with('-') && !w.ends_with('/') {
                let made_before = !w.starts_with("samples/") && !w.starts_with("tests/");
                assert!(
                    made_before || root().join(w).exists(),
                    "{w} is not in the repository"
                );
            }
        }
        let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
            .args(&words[1..])
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(exit),
            "`{}`: {}",
            words.join(" "),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
