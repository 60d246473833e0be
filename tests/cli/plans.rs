//! The plan is the only input after it is made (issue 47), for every
//! command:
//! - each command's usage error comes before any file is read or written:
//!   exit 2, its message, and the folder as it was, with every input a
//!   FIFO (a read would wait for a writer that never comes, past the
//!   deadline);
//! - on the source of `src/cli/`: no run function takes the types clap
//!   fills (its `Args`, `Subcommand` and `Parser` types), nor a plan that
//!   holds one, and the dispatch hands each command's arguments to its
//!   plan function and only the plan to its run.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_rapidtherm");

/// One refused command line: its words and what its message says.
struct Case {
    args: &'static [&'static str],
    says: &'static str,
}

/// A usage error of every command, each where the command has one the
/// input could hide (a flag read after a file, before this issue).
const CASES: &[Case] = &[
    Case {
        args: &["targets", "a.mod", "--format", "xml"],
        says: "invalid value 'xml' for '--format <FORMAT>'",
    },
    Case {
        args: &[
            "fk", "0", "0", "0", "0", "0", "0", "--robot", "arm.urdf", "--temps", "30,30",
        ],
        says: "--temps: six values needed, got 2",
    },
    Case {
        args: &[
            "ik",
            "500",
            "0",
            "600",
            "1",
            "0",
            "0",
            "0",
            "--robot",
            "arm.urdf",
            "--thermal",
            "thermal.toml",
            "--temps",
            "30,30,30,30,30,30",
            "--conf",
            "0,0,0",
        ],
        says: "--conf: four integers cf1,cf4,cf6,cfx needed",
    },
    Case {
        args: &[
            "heating", "fit", "rec.csv", "--axes", "7", "--plot", "out.svg",
        ],
        says: "--axes: axis 7 does not exist (1..6)",
    },
    Case {
        args: &[
            "heating",
            "eval",
            "--at",
            "5",
            "--records",
            "rec.csv",
            "--model",
            "poly0",
        ],
        says: "poly0",
    },
    Case {
        args: &["schedule", "a.mod", "--cycles", "0", "-o", "out.csv"],
        says: "--cycles must be at least 1",
    },
    Case {
        args: &[
            "correct",
            "a.mod",
            "--model",
            "model.toml",
            "--at",
            "later",
            "-o",
            "out.mod",
        ],
        says: "--at: `later` is neither a minute since the cold start (≥ 0) nor `steady`",
    },
    Case {
        args: &["diff", "a.mod", "b.mod", "--fail-above", "-1"],
        says: "--fail-above -1: the limit must be a number of mm from 0 to",
    },
    Case {
        args: &["model", "show", "--model", "model.toml", "--format", "json"],
        says: "unexpected argument '--format'",
    },
    Case {
        args: &[
            "simulate",
            "--model",
            "model.toml",
            "--effect",
            "gremlins",
            "-o",
            "out.csv",
        ],
        says: "unknown effect `gremlins`",
    },
    Case {
        args: &[
            "simulate",
            "--model",
            "model.toml",
            "--poses",
            "cube",
            "-o",
            "out.csv",
        ],
        says: "--poses `cube`: expected random:N, joints:FILE.csv, iso-cube or program:FILE",
    },
    Case {
        args: &[
            "simulate",
            "--model",
            "model.toml",
            "--times",
            "5,1",
            "-o",
            "out.csv",
        ],
        says: "--times `5,1`: minutes must be >= 0 and increasing",
    },
    Case {
        args: &[
            "diagnose",
            "meas.csv",
            "--noise",
            "0",
            "--save-model",
            "saved.toml",
        ],
        says: "--noise must be a positive number of mm",
    },
    Case {
        args: &[
            "gap",
            "meas.csv",
            "--model",
            "model.toml",
            "--fail-above=-1",
        ],
        says: "--fail-above must be a number of mm >= 0",
    },
    Case {
        args: &["arms", "--format", "xml"],
        says: "invalid value 'xml' for '--format <FORMAT>'",
    },
    Case {
        args: &["completions", "cmd.exe"],
        says: "invalid value 'cmd.exe'",
    },
    Case {
        args: &["man", "--force"],
        says: "--out-dir <DIR>",
    },
];

/// The files the cases name as inputs, made FIFOs.
const INPUTS: &[&str] = &[
    "a.mod",
    "b.mod",
    "arm.urdf",
    "thermal.toml",
    "rec.csv",
    "model.toml",
    "meas.csv",
];

#[cfg(unix)]
fn fifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
}

/// Every name under `dir` and what kind of file it is.
fn listing(dir: &Path) -> BTreeMap<PathBuf, String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| {
            let kind = format!("{:?}", e.file_type().unwrap());
            (e.path(), kind)
        })
        .collect()
}

/// The run's exit code (`None`: past the hostile inputs' deadline,
/// killed, as a run blocked reading a FIFO is) and standard error.
fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
    let (code, err, _) = super::hostile::run(dir, &args);
    (code, err)
}

#[cfg(unix)]
#[test]
fn every_usage_error_comes_before_any_file_is_read_or_written() {
    let tmp = tempfile::tempdir().unwrap();
    for name in INPUTS {
        fifo(&tmp.path().join(name));
    }
    let before = listing(tmp.path());
    let mut failures = Vec::new();
    for case in CASES {
        let (code, err) = run(tmp.path(), case.args);
        if code != Some(2) || !err.contains(case.says) {
            failures.push(format!(
                "rapidtherm {}: exit {code:?} (want 2), `{}` wanted in: {err}",
                case.args.join(" "),
                case.says
            ));
        }
        let after = listing(tmp.path());
        if after != before {
            failures.push(format!(
                "rapidtherm {}: the folder changed: {after:?}",
                case.args.join(" ")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Every subcommand (and `heating`'s and `model`'s own) has a case above.
#[test]
fn every_command_has_a_usage_case() {
    let help = |args: &[&str]| -> Vec<String> {
        let out = Command::new(BIN).args(args).output().unwrap();
        super::conventions::listed_commands(&String::from_utf8_lossy(&out.stdout))
    };
    let mut commands: Vec<String> = Vec::new();
    for top in help(&["--help"]) {
        let subs = help(&[&top, "--help"]);
        if subs.is_empty() {
            commands.push(top);
        } else {
            commands.extend(subs.into_iter().map(|s| format!("{top} {s}")));
        }
    }
    assert!(commands.len() >= 15, "{commands:?}");
    let covered: BTreeSet<String> = CASES
        .iter()
        .flat_map(|c| [c.args[0].to_string(), c.args[..2].join(" ")])
        .collect();
    let missing: Vec<&String> = commands.iter().filter(|c| !covered.contains(*c)).collect();
    assert!(missing.is_empty(), "no usage case for {missing:?}");
}

/// The files of `src/cli/`, by name.
fn cli_sources() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/cli");
    let mut files: Vec<(String, String)> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "rs"))
        .map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(e.path()).unwrap())
        })
        .collect();
    files.sort();
    files
}

/// The names of the types `text` defines after a `#[derive(...)]` of one
/// of `derives`, and of every type it defines, with its body.
fn types(text: &str, derives: &[&str]) -> (BTreeSet<String>, BTreeMap<String, String>) {
    let mut derived = BTreeSet::new();
    let mut bodies = BTreeMap::new();
    let mut pending = false;
    let lines: Vec<&str> = text.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim();
        if let Some(list) = t.strip_prefix("#[derive(") {
            let list = list.trim_end_matches(")]");
            pending |= list.split(',').any(|d| derives.contains(&d.trim()));
            continue;
        }
        let decl = t
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("pub ");
        let name = decl
            .strip_prefix("struct ")
            .or_else(|| decl.strip_prefix("enum "))
            .map(|rest| identifiers(rest).into_iter().next().unwrap_or_default());
        if let Some(name) = name {
            if pending {
                derived.insert(name.clone());
            }
            pending = false;
            // To its closing brace at the line's start (a unit or tuple
            // struct: its line); comments left out.
            let end = if t.ends_with(';') {
                i
            } else {
                (i..lines.len())
                    .find(|&j| lines[j].starts_with('}'))
                    .unwrap_or(lines.len() - 1)
            };
            let body: String = lines[i..=end]
                .iter()
                .map(|l| l.split("//").next().unwrap_or_default())
                .collect::<Vec<_>>()
                .join("\n");
            bodies.insert(name, body);
        } else if ["fn ", "impl", "use ", "const ", "static ", "mod ", "type "]
            .iter()
            .any(|k| decl.starts_with(k) || decl.starts_with(&format!("pub {k}")))
        {
            // An attribute may take several lines: only another item ends
            // the derive's reach.
            pending = false;
        }
    }
    (derived, bodies)
}

/// The identifiers of `text`, each path's last (`super::tasks::TaskPick`:
/// `TaskPick`); the names of other crates' paths left out (`clap::Command`
/// is clap's own, not the command line's `Command`).
fn identifiers(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut flush = |word: &mut String| {
        if !word.is_empty() {
            let foreign = ["clap::", "std::", "rapidtherm::", "serde", "nalgebra::"]
                .iter()
                .any(|c| word.starts_with(c));
            if !foreign {
                out.push(word.rsplit("::").next().unwrap_or_default().to_string());
            }
            word.clear();
        }
    };
    for c in text.chars() {
        if c.is_alphanumeric() || c == '_' || c == ':' {
            word.push(c);
        } else {
            flush(&mut word);
        }
    }
    flush(&mut word);
    out
}

/// The parameter lists of every `fn run` and `fn run_*` in `text`.
fn run_signatures(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("fn run") {
        let after = &rest[at + 3..];
        let name: String = after
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let Some(open) = after.find('(') else { break };
        let mut depth = 0;
        let mut end = open;
        for (i, c) in after[open..].char_indices() {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                _ => {}
            }
            if depth == 0 {
                end = open + i;
                break;
            }
        }
        out.push((name, after[open + 1..end].to_string()));
        rest = &after[end..];
    }
    out
}

#[test]
fn no_run_function_takes_what_clap_fills() {
    let clap = [
        "clap::Args",
        "clap::Subcommand",
        "clap::Parser",
        "Parser",
        "Subcommand",
    ];
    let mut clap_types = BTreeSet::new();
    let mut bodies = BTreeMap::new();
    let sources = cli_sources();
    for (_, text) in &sources {
        let (derived, defined) = types(text, &clap);
        clap_types.extend(derived);
        bodies.extend(defined);
    }
    // The reader finds what it looks for.
    for known in ["Cli", "Command", "CorrectArgs", "TaskArgs", "HeatingArgs"] {
        assert!(
            clap_types.contains(known),
            "{known} not found: {clap_types:?}"
        );
    }
    let mut failures = Vec::new();
    let mut runs = 0;
    for (file, text) in &sources {
        for (name, params) in run_signatures(text) {
            runs += 1;
            // The types the run is given, and those they hold, to the last.
            let mut seen = BTreeSet::new();
            let mut todo = identifiers(&params);
            while let Some(t) = todo.pop() {
                if !seen.insert(t.clone()) {
                    continue;
                }
                if clap_types.contains(&t) {
                    failures.push(format!("{file}: {name} is given {t}, which clap fills"));
                } else if let Some(body) = bodies.get(&t) {
                    todo.extend(identifiers(body));
                }
            }
        }
    }
    assert!(runs >= 15, "only {runs} run functions found");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Each arm of the dispatch makes the plan from the arguments and hands
/// the run the plan alone.
#[test]
fn the_dispatch_runs_plans() {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/cli/mod.rs"))
            .unwrap();
    let start = text.find("match cli.command {").expect("the dispatch");
    let block = &text[start..];
    let block = &block[..block.find("\n    };").expect("its end")];
    let arms: Vec<&str> = block.split("Command::").skip(1).collect();
    assert!(arms.len() >= 14, "{arms:?}");
    for arm in arms {
        assert!(
            arm.contains("::plan") && arm.contains(".and_then("),
            "not a plan, then its run: {arm}"
        );
    }
}
