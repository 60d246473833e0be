//! Every command's `--help` ends with examples and exit statuses, and its
//! man page has EXIT STATUS and EXAMPLES (issue 49: none had them). Each
//! example is run, as written, in a folder holding a copy of the
//! repository's samples, and ends with the exit status it says: a help
//! text cannot promise a command line that does not work.

use super::conventions::listed_commands;
use super::gate::copy_tree;
use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn help(path: &[&str]) -> String {
    let mut args: Vec<&str> = path.to_vec();
    args.push("--help");
    let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(&args)
        .output()
        .unwrap();
    assert!(out.status.success(), "{args:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// Every command path below `rapidtherm` its helps list (`heating fit`
/// among them), the top one as "".
fn command_paths() -> Vec<Vec<String>> {
    let mut out = vec![Vec::new()];
    let mut k = 0;
    while k < out.len() {
        let path = out[k].clone();
        let refs: Vec<&str> = path.iter().map(String::as_str).collect();
        for sub in listed_commands(&help(&refs)) {
            let mut p = path.clone();
            p.push(sub);
            out.push(p);
        }
        k += 1;
    }
    out
}

/// The examples of a help text: each `$ ` line, and the exit status the
/// file gives it (read back from the data file: the help shows the
/// command lines).
fn examples(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.trim_start().strip_prefix("$ "))
        .map(str::to_string)
        .collect()
}

#[test]
fn every_help_ends_with_examples_and_exit_statuses() {
    let paths = command_paths();
    assert!(paths.len() > 15, "{paths:?}");
    for path in &paths {
        let refs: Vec<&str> = path.iter().map(String::as_str).collect();
        let text = help(&refs);
        assert!(
            text.contains("\nExamples:\n"),
            "{path:?}: no examples\n{text}"
        );
        assert!(
            text.contains("\nExit status:\n  0  "),
            "{path:?}: no exit status"
        );
        assert!(!examples(&text).is_empty(), "{path:?}");
        for e in examples(&text) {
            let words: Vec<&str> = e.split_whitespace().collect();
            assert_eq!(words[0], "rapidtherm", "{e}");
        }
    }
}

/// `(command line, exit status)` of every example in the data file, in
/// order, by command.
fn documented() -> Vec<(String, Vec<(String, i32)>)> {
    let text = std::fs::read_to_string(root().join("data/help/examples.toml")).unwrap();
    let file: toml::Value = toml::from_str(&text).unwrap();
    file["command"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let path = c["path"].as_str().unwrap().to_string();
            let runs = c["examples"]
                .as_array()
                .unwrap()
                .iter()
                .map(|e| {
                    let exit = e.get("exit").and_then(toml::Value::as_integer).unwrap_or(0);
                    (e["run"].as_str().unwrap().to_string(), exit as i32)
                })
                .collect();
            (path, runs)
        })
        .collect()
}

#[test]
fn every_example_runs_and_ends_as_it_says() {
    for (path, runs) in documented() {
        let dir = tempfile::tempdir().unwrap();
        copy_tree(&root().join("samples"), &dir.path().join("samples"));
        for (run, exit) in runs {
            let words: Vec<&str> = run.split_whitespace().collect();
            let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
                .args(&words[1..])
                .current_dir(dir.path())
                .output()
                .unwrap();
            assert_eq!(
                out.status.code(),
                Some(exit),
                "`{run}` (rapidtherm {path}): {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

#[test]
fn every_man_page_has_exit_status_and_examples() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(["man", "--out-dir", dir.path().to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.success());
    for path in command_paths() {
        let name = std::iter::once("rapidtherm".to_string())
            .chain(path.iter().cloned())
            .collect::<Vec<_>>()
            .join("-");
        let page = std::fs::read_to_string(dir.path().join(format!("{name}.1"))).unwrap();
        assert!(page.contains(".SH \"EXIT STATUS\""), "{name}");
        assert!(page.contains(".SH EXAMPLES\n.TP\n\\fBrapidtherm"), "{name}");
    }
}
