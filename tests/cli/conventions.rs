//! Shell completions and man pages cover the whole command line: every
//! subcommand and every long flag of `correct`, read from the binary's own
//! help, so that a new flag or command cannot be left out of them.

use std::process::Command;

fn rapidtherm(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(args)
        .output()
        .unwrap();
    assert!(out.status.success(), "rapidtherm {args:?} failed: {out:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// The commands a `--help` text lists under `Commands:` (but `help`).
pub(super) fn listed_commands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|n| *n != "help")
        .map(str::to_string)
        .collect()
}

/// The subcommands `rapidtherm --help` lists (but `help`).
fn subcommands() -> Vec<String> {
    let names = listed_commands(&rapidtherm(&["--help"]));
    assert!(
        names.len() >= 12 && names.iter().any(|n| n == "correct"),
        "{names:?}"
    );
    names
}

/// The long flags (without `--`) `rapidtherm correct --help` lists,
/// `--help` and the global ones included.
fn correct_flags() -> Vec<String> {
    let help = rapidtherm(&["correct", "--help"]);
    let mut flags: Vec<String> = Vec::new();
    for line in help.lines().map(str::trim_start) {
        let Some(rest) = line
            .strip_prefix("-")
            .and_then(|r| r.split_once("--").map(|(_, f)| f))
            .or_else(|| line.strip_prefix("--"))
        else {
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
            .collect();
        if !name.is_empty() && !flags.contains(&name) {
            flags.push(name);
        }
    }
    for f in [
        "at", "check", "in-place", "quiet", "verbose", "color", "help",
    ] {
        assert!(flags.iter().any(|g| g == f), "--{f} not in {flags:?}");
    }
    flags
}

#[test]
fn completions_name_every_subcommand_and_every_flag_of_correct() {
    let commands = subcommands();
    let flags = correct_flags();
    for shell in ["bash", "zsh", "fish"] {
        let script = rapidtherm(&["completions", shell]);
        for c in &commands {
            assert!(
                script.contains(c.as_str()),
                "{shell} completions lack the subcommand {c}"
            );
        }
        // The part of the script that completes `correct`'s flags.
        let correct_part: String = match shell {
            // `rapidtherm__correct)` … `;;`: the opts of `correct`.
            "bash" => script
                .split("rapidtherm__subcmd__correct)")
                .nth(1)
                .or_else(|| script.split("rapidtherm__correct)").nth(1))
                .and_then(|s| s.split(";;").next())
                .expect("bash: a case for correct")
                .to_string(),
            // `(correct)` … the next `;;`.
            "zsh" => script
                .split("(correct)")
                .nth(1)
                .and_then(|s| s.split(";;").next())
                .expect("zsh: a case for correct")
                .to_string(),
            // The lines completing after `correct`.
            _ => script
                .lines()
                .filter(|l| l.contains("using_subcommand correct\""))
                .collect::<Vec<_>>()
                .join("\n"),
        };
        for f in &flags {
            let named = match shell {
                "fish" => correct_part.contains(&format!("-l {f}")),
                _ => correct_part.contains(&format!("--{f}")),
            };
            assert!(named, "{shell} completions of correct lack --{f}");
        }
    }
}

#[test]
fn completions_refuse_an_unknown_shell() {
    let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .args(["completions", "tcsh"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
}

/// A man page as roff: a title line first, the usual sections, requests
/// only of the man macros' kind (a line starting with `.` or `'` is a
/// request: a name of letters).
fn assert_roff_page(roff: &str, name: &str) {
    let first = roff
        .lines()
        .find(|l| !l.starts_with(".ie") && !l.starts_with(".el") && !l.starts_with(".\\\""));
    assert!(
        first.is_some_and(|l| l.starts_with(&format!(".TH {name} 1"))),
        "{name}: first request is not .TH: {first:?}"
    );
    for section in [".SH NAME", ".SH SYNOPSIS", ".SH DESCRIPTION", ".SH OPTIONS"] {
        assert!(roff.contains(section), "{name}: no {section}");
    }
    for line in roff.lines().filter(|l| l.starts_with('.')) {
        let request: String = line[1..]
            .chars()
            .take_while(|c| !c.is_whitespace())
            .collect();
        assert!(
            request.is_empty()
                || request == "\\\""
                || request.chars().all(|c| c.is_ascii_alphabetic()),
            "{name}: not a roff request: {line}"
        );
    }
}

#[test]
fn the_man_page_names_every_subcommand() {
    let page = rapidtherm(&["man"]);
    assert_roff_page(&page, "rapidtherm");
    let subcommands = page
        .split(".SH SUBCOMMANDS")
        .nth(1)
        .expect("a SUBCOMMANDS section");
    for c in subcommands_of_help() {
        assert!(
            subcommands.contains(&format!("rapidtherm\\-{c}(1)")),
            "the man page lacks {c}"
        );
    }
    // Read by man itself where it is installed: an extra check, not the
    // only one.
    if let Ok(out) = Command::new("man")
        .args(["--warnings", "-l", "-Tutf8", "-"])
        .env("MANWIDTH", "80")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .and_then(|mut child| {
            use std::io::Write;
            child.stdin.take().unwrap().write_all(page.as_bytes())?;
            child.wait_with_output()
        })
    {
        if out.status.success() {
            let text = String::from_utf8_lossy(&out.stdout);
            assert!(text.contains("correct"), "man renders the page");
            assert!(
                out.stderr.is_empty(),
                "man warns: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

fn subcommands_of_help() -> Vec<String> {
    subcommands()
}

#[test]
fn man_out_dir_writes_a_page_per_subcommand() {
    let dir = tempfile::tempdir().unwrap();
    let out = rapidtherm(&["man", "--out-dir", dir.path().to_str().unwrap()]);
    assert!(out.is_empty(), "nothing on standard output: {out}");
    let page = |name: &str| {
        std::fs::read_to_string(dir.path().join(format!("{name}.1")))
            .unwrap_or_else(|e| panic!("{name}.1: {e}"))
    };
    assert_roff_page(&page("rapidtherm"), "rapidtherm");
    for c in subcommands() {
        let name = format!("rapidtherm-{c}");
        assert_roff_page(&page(&name), &name);
    }
    // Nested subcommands have theirs.
    assert_roff_page(&page("rapidtherm-heating-fit"), "rapidtherm-heating-fit");
    let correct = page("rapidtherm-correct");
    for f in correct_flags() {
        assert!(
            correct.contains(&format!("\\-\\-{}", f.replace('-', "\\-"))),
            "rapidtherm-correct.1 lacks --{f}"
        );
    }
    assert!(
        !dir.path().join("rapidtherm-help.1").exists(),
        "no page for `help`"
    );
}

/// The argument lists of the CLI transcripts that only read (no standard
/// input, no file written, no environment of their own).
fn reading_transcripts() -> Vec<Vec<String>> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cmd");
    let mut cases = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap().flatten() {
        let path = entry.path();
        if path.extension().is_none_or(|e| e != "toml") || path.with_extension("stdin").exists() {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let case: toml::Table = toml::from_str(&text).unwrap();
        let Some(args) = case.get("args").and_then(|a| a.as_array()) else {
            continue;
        };
        let args: Vec<String> = args
            .iter()
            .filter_map(|a| a.as_str().map(str::to_string))
            .collect();
        let writes = args.iter().any(|a| {
            [
                "-o",
                "--output",
                "--in-place",
                "--plot",
                "--save-model",
                "--out-dir",
                "-",
            ]
            .contains(&a.as_str())
        });
        if !writes && !case.contains_key("env") && !case.contains_key("fs") {
            cases.push(args);
        }
    }
    assert!(cases.len() > 100, "{} transcripts", cases.len());
    cases
}

/// Standard output is data: `-q`, `-vv` and `--color always` change what
/// is said on standard error, never what is printed on standard output,
/// nor the exit code.
#[test]
fn message_flags_never_change_standard_output() {
    let run = |args: &[String], extra: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args(args)
            .args(extra)
            .env_remove("NO_COLOR")
            .env_remove("CLICOLOR_FORCE")
            .output()
            .unwrap();
        // A JUnit report says when and how long it ran (docs/ci.md): the
        // rest is compared.
        let clock = regex::Regex::new(r#"(timestamp|time)="[^"]*""#).unwrap();
        let stdout = clock
            .replace_all(&String::from_utf8_lossy(&out.stdout), "$1=\"\"")
            .into_owned();
        (out.status.code(), stdout)
    };
    for args in reading_transcripts() {
        // `--help` and `--version` end parsing; flags after them are not
        // read.
        // Transcripts of these flags themselves are what they are.
        if args.iter().any(|a| {
            a.starts_with("--help")
                || a == "-V"
                || a.starts_with("--color")
                || ["-q", "--quiet", "-v", "-vv", "--verbose"].contains(&a.as_str())
        }) {
            continue;
        }
        let plain = run(&args, &[]);
        if plain.0 == Some(2) {
            continue; // a usage or input error: nothing on standard output
        }
        for extra in [&["-q"][..], &["-vv"], &["--color", "always"]] {
            assert!(
                run(&args, extra) == plain,
                "rapidtherm {} {}: standard output or exit code changed",
                args.join(" "),
                extra.join(" ")
            );
        }
    }
}
