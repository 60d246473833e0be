//! Every command block of docs/*.md runs as written on the repository's own
//! files (issue 49: the documents named `prog.mod`, `cell.mod`, `rec.csv`,
//! `BACKUP`, files a new user does not have). docs/ci.md's examples run in
//! `ci_snippets.rs` on a repository of `RAPID/TASK1` alone, the README's in
//! `readme_tour.rs`; this test takes every other document.
//!
//! Each document runs in a folder of its own holding copies of the
//! repository's `samples/` and `tests/` data; its `sh`, `bash` and
//! `console` blocks' lines run in order through `bash -c`, the built
//! `rapidtherm` first on the `PATH` and `HOME` inside the folder (the
//! completions and man pages land there). A pipeline's tail (`| less -R`,
//! `| man -l -`) is a reader the test does not have: the part before the
//! pipe runs. Each line ends with the exit status its comment says
//! (`exit 1`, `exit 2`, else 0), and every file a line reads is in the
//! folder when it runs: the repository's own, or one an earlier line
//! wrote, never a placeholder.
//!
//! Development commands (`cargo`, `git`, `valgrind`, `callgrind_annotate`)
//! are not run: CI runs the tests itself, and benches take minutes. A
//! line of any other kind fails the test until it is classified here.

use super::gate::copy_tree;
use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_rapidtherm");
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// A command line of a document: where it stands, what it says, the exit
/// status its comment promises.
struct Line {
    at: usize,
    text: String,
    exit: i32,
}

/// The command lines of a document's shell blocks, with continuations
/// joined and `console` prompts taken off (a `console` block's other lines
/// are output).
fn command_lines(markdown: &str) -> Vec<Line> {
    let mut out = Vec::new();
    let mut lang: Option<String> = None;
    let mut pending: Option<(usize, String)> = None;
    for (i, raw) in markdown.lines().enumerate() {
        let t = raw.trim();
        if let Some(info) = t.strip_prefix("```") {
            lang = match lang {
                Some(_) => None,
                None => Some(info.split_whitespace().next().unwrap_or("").to_string()),
            };
            continue;
        }
        let Some(l) = lang.as_deref() else { continue };
        let body = match l {
            "sh" | "bash" | "shell" => t,
            "console" => match t.strip_prefix("$ ") {
                Some(cmd) => cmd,
                None => continue,
            },
            _ => continue,
        };
        let (at, mut text) = pending.take().unwrap_or((i + 1, String::new()));
        if let Some(head) = body.strip_suffix('\\') {
            text.push_str(head.trim_end());
            text.push(' ');
            pending = Some((at, text));
            continue;
        }
        text.push_str(body);
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let exit = match text.split_once(" #") {
            Some((_, c)) if c.contains("exit 1") => 1,
            Some((_, c)) if c.contains("exit 2") => 2,
            _ => 0,
        };
        out.push(Line { at, text, exit });
    }
    out
}

/// The program a line runs, past any `VAR=value` assignments before it.
fn program(line: &str) -> &str {
    line.split_whitespace()
        .find(|w| !w.contains('='))
        .unwrap_or("")
}

/// The words of the part before the comment and the first pipe.
fn words(line: &str) -> Vec<&str> {
    let code = line.split_once(" #").map_or(line, |(c, _)| c);
    let head = code.split_once(" | ").map_or(code, |(h, _)| h);
    head.split_whitespace().collect()
}

/// The files a `rapidtherm` line reads: its arguments that look like
/// paths (a folder, a file with an extension), except the values of the
/// options that name what a run writes (an output, a module's name) and
/// what a redirection names.
fn inputs<'a>(words: &[&'a str]) -> Vec<&'a str> {
    const NOT_READ: [&str; 8] = [
        "-o",
        "--out",
        "--out-dir",
        "--plot",
        "--save-model",
        "--backup",
        "--report",
        "--runtime-module",
    ];
    let mut out = Vec::new();
    let mut skip = false;
    for w in words.iter().skip(1) {
        if skip {
            skip = false;
            continue;
        }
        if NOT_READ.contains(w) {
            skip = true;
            continue;
        }
        // `> file` names the next word; `>file` and `2>&1` name none.
        if w.starts_with('>') || w.starts_with("2>") {
            skip = *w == ">" || *w == "2>";
            continue;
        }
        let pathlike = !w.starts_with('-')
            && !w.contains('=')
            && (w.contains('/') || Path::new(w).extension().is_some_and(|e| e.len() <= 4))
            && !w.chars().next().is_some_and(|c| c.is_ascii_digit());
        if pathlike {
            out.push(*w);
        }
    }
    out
}

fn run_document(name: &str) -> usize {
    let text = std::fs::read_to_string(Path::new(ROOT).join("docs").join(name)).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let work = dir.path();
    copy_tree(&Path::new(ROOT).join("samples"), &work.join("samples"));
    for sub in ["data", "cmd/correct_data", "malformed"] {
        copy_tree(
            &Path::new(ROOT).join("tests").join(sub),
            &work.join("tests").join(sub),
        );
    }
    let bin_dir = Path::new(BIN).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut ran = 0;
    for line in command_lines(&text) {
        let prog = program(&line.text);
        match prog {
            // (`cd fuzz` leads the fuzzing block's cargo lines.)
            "cargo" | "git" | "valgrind" | "callgrind_annotate" | "cd" => continue,
            // The man reader reads what `rapidtherm man` wrote (which runs).
            "man" => continue,
            "rapidtherm" | "mkdir" | "cp" => {}
            other => panic!(
                "docs/{name}:{}: `{other}` is neither run nor classified as a development command",
                line.at
            ),
        }
        let w = words(&line.text);
        if prog == "rapidtherm" {
            for input in inputs(&w) {
                assert!(
                    work.join(input).exists() || input.starts_with('~'),
                    "docs/{name}:{}: `{input}` is neither the repository's nor written by an earlier line",
                    line.at
                );
            }
        }
        let out = Command::new("bash")
            .arg("-c")
            .arg(w.join(" "))
            .current_dir(work)
            .env("PATH", &path)
            .env("HOME", work.join("home"))
            .env_remove("NO_COLOR")
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(line.exit),
            "docs/{name}:{}: `{}`: {}",
            line.at,
            line.text,
            String::from_utf8_lossy(&out.stderr)
        );
        ran += 1;
    }
    ran
}

#[test]
fn every_command_of_the_documents_runs_on_the_repositorys_files() {
    let mut names: Vec<String> = std::fs::read_dir(Path::new(ROOT).join("docs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md") && n != "ci.md")
        .collect();
    names.sort();
    let ran: usize = names.iter().map(|n| run_document(n)).sum();
    // About 50 user commands stand in the documents today; a parser that
    // found none would pass every document vacuously.
    assert!(ran >= 40, "{ran} command lines ran");
}

#[test]
fn the_parser_reads_prompts_continuations_and_exit_comments() {
    let md = "```console\n$ rapidtherm a # exit 1\noutput\n```\n```sh\nrapidtherm b \\\n  --c # exit 2\n# comment\n```\n```text\nrapidtherm d\n```\n";
    let lines = command_lines(md);
    let got: Vec<(&str, i32)> = lines.iter().map(|l| (l.text.as_str(), l.exit)).collect();
    assert_eq!(
        got,
        [
            ("rapidtherm a # exit 1", 1),
            ("rapidtherm b --c # exit 2", 2)
        ]
    );
    assert_eq!(
        inputs(&words("rapidtherm correct a.mod --at 60 -o b.mod > c.txt")),
        ["a.mod"]
    );
}
