//! The library's layers, checked on its source: each top-level module
//! imports only the modules below it, no library file names clap, and no
//! source file grows past 1,000 lines. The compiler allows any import
//! inside one crate; this test is what keeps the direction.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// What each top-level module of the library may import (besides external
/// crates). Bottom to top: foundations; the language, geometry and
/// temperatures; the warm robot; what programs mean and when targets are
/// reached; the jobs. `src/lib.rs` and the code map in docs/development.md say the same.
const ALLOWED: &[(&str, &[&str])] = &[
    ("error", &[]),
    ("input", &["error"]),
    ("digest", &[]),
    ("csv_table", &["error"]),
    ("report", &["error"]),
    ("plot", &["error"]),
    ("writes", &["error"]),
    ("rapid", &["error", "input"]),
    ("robot", &["error", "input", "csv_table"]),
    ("thermal", &["error", "csv_table", "report", "plot"]),
    (
        "model",
        &["error", "input", "csv_table", "robot", "thermal"],
    ),
    ("resolve", &["error", "digest", "report", "rapid", "robot"]),
    // The RAPID interpreter, on the meaning level beside `resolve` and
    // `schedule`, importing neither.
    ("interp", &["error", "rapid", "robot"]),
    (
        "schedule",
        &["error", "digest", "csv_table", "rapid", "robot", "resolve"],
    ),
    (
        "correct",
        &[
            "error", "digest", "plot", "rapid", "robot", "thermal", "model", "resolve", "interp",
            "schedule",
        ],
    ),
    ("compare", &["error", "rapid", "robot", "resolve"]),
    (
        "diagnose",
        &[
            "error",
            // The job reads its inputs, bounded as every reader is.
            "input",
            "csv_table",
            "report",
            "plot",
            "rapid",
            "robot",
            "thermal",
            "model",
            "resolve",
        ],
    ),
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The code of a file without its comments (doc links may name any
/// module; only code imports).
fn code_of(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level module a library file belongs to (`src/model/warm.rs` →
/// `model`, `src/compare.rs` → `compare`); `None` for the crate root and
/// the binary.
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let first = rel.components().next()?.as_os_str().to_str()?.to_string();
    let name = first.trim_end_matches(".rs").to_string();
    match name.as_str() {
        "lib" | "main" | "cli" => None,
        _ => Some(name),
    }
}

/// Top-level modules a file refers to through `crate::NAME` (also inside
/// `use crate::{a, b}` groups).
fn imports(code: &str, known: &BTreeSet<&str>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for part in group[..end].split(',') {
                let name: String = part
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if known.contains(name.as_str()) {
                    out.insert(name);
                }
            }
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if known.contains(name.as_str()) {
                out.insert(name);
            }
        }
    }
    out
}

#[test]
fn every_module_imports_only_the_layers_below_it() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("src");
    let allowed: BTreeMap<&str, &[&str]> = ALLOWED.iter().copied().collect();
    let known: BTreeSet<&str> = allowed.keys().copied().collect();
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut wrong = Vec::new();
    let mut seen_modules = BTreeSet::new();
    for file in &files {
        let Some(module) = module_of(&src, file) else {
            continue;
        };
        seen_modules.insert(module.clone());
        let Some(may) = allowed.get(module.as_str()) else {
            wrong.push(format!(
                "{}: module `{module}` has no place in the layers (add it to ALLOWED, the map in docs/development.md and src/lib.rs)",
                file.display()
            ));
            continue;
        };
        let text = std::fs::read_to_string(file).unwrap();
        for used in imports(&code_of(&text), &known) {
            if used != module && !may.contains(&used.as_str()) {
                wrong.push(format!(
                    "{}: `{module}` imports `{used}`",
                    file.strip_prefix(root).unwrap().display()
                ));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "imports against the layers:\n{}",
        wrong.join("\n")
    );
    // Every listed module exists (a renamed module must not leave a stale
    // rule that checks nothing).
    for m in known {
        assert!(
            seen_modules.contains(m),
            "ALLOWED lists `{m}`, which src/ does not have"
        );
    }
}

#[test]
fn the_allowed_imports_form_no_cycle() {
    // A module may only import modules listed before it: the table is in
    // layer order, so the graph it allows is acyclic by construction.
    let order: Vec<&str> = ALLOWED.iter().map(|(m, _)| *m).collect();
    for (i, (m, may)) in ALLOWED.iter().enumerate() {
        for dep in *may {
            let j = order.iter().position(|o| o == dep).unwrap();
            assert!(j < i, "`{m}` may import `{dep}`, which is not below it");
        }
    }
}

#[test]
fn no_library_file_names_clap() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut wrong = Vec::new();
    for file in &files {
        if module_of(&src, file).is_none() {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        if code.contains("clap") {
            wrong.push(file.display().to_string());
        }
    }
    assert!(wrong.is_empty(), "library files naming clap: {wrong:?}");
}

#[test]
fn no_source_file_is_over_1000_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "tests", "benches", "examples", "fuzz"] {
        rust_files(&root.join(dir), &mut files);
    }
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let n = std::fs::read_to_string(f).ok()?.lines().count();
            (n > 1000).then(|| format!("{} ({n} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "files over 1,000 lines: {long:?}");
}

/// The diagnosis is a library job (`diagnose::plan`, `diagnose::job`):
/// no file of the command line reads its inputs, chooses which diagnosis
/// runs, prepares the data, runs a diagnosis or edits the model it saves.
#[test]
fn the_cli_holds_no_diagnosis_orchestration() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src/cli"), &mut files);
    let mut wrong = Vec::new();
    for file in &files {
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        for (n, line) in code.lines().enumerate() {
            if [
                "diagnose::diagnose(",
                "diagnose_chain(",
                "problem_of(",
                "register_instrument(",
                "place_in_base(",
                "diagnosed_model(",
                "Measurements::parse(",
                "has_temps(",
                ".robot.urdf",
                ".robot.opw =",
                ".robot.point_mm",
            ]
            .iter()
            .any(|w| line.contains(w))
            {
                wrong.push(format!(
                    "{}:{}: {}",
                    file.strip_prefix(root).unwrap().display(),
                    n + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "the diagnosis's work belongs to rapidtherm::diagnose::job:\n{}",
        wrong.join("\n")
    );
}

/// Every message of the command line goes through `src/cli/messages.rs`,
/// so that `-q`, `-v` and `--color` apply to it: no other file of the CLI
/// writes to standard error itself.
#[test]
fn the_cli_speaks_on_stderr_only_through_its_messages_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src/cli"), &mut files);
    files.push(root.join("src/main.rs"));
    assert!(
        files.iter().any(|f| f.ends_with("src/cli/messages.rs")),
        "src/cli/messages.rs is where messages are written"
    );
    let mut wrong = Vec::new();
    for file in files.iter().filter(|f| !f.ends_with("messages.rs")) {
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        for (n, line) in code.lines().enumerate() {
            if ["eprintln!", "eprint!", "stderr()"]
                .iter()
                .any(|w| line.contains(w))
            {
                wrong.push(format!(
                    "{}:{}: {}",
                    file.strip_prefix(root).unwrap().display(),
                    n + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "write messages with the macros of src/cli/messages.rs (error!, warning!, note!, status!, outcome!, info!), not directly:\n{}",
        wrong.join("\n")
    );
}

/// Every file of the repository that is not a build product: what a
/// clone holds (`.git`, a folder or a worktree's file, `target/` and the
/// fuzzer's own folders skipped).
fn repository_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        // `.git` is a folder in a clone and a file in a worktree.
        if name == ".git" {
            continue;
        }
        if path.is_dir() {
            if !["target", "corpus", "artifacts", "coverage"]
                .iter()
                .any(|skip| name == *skip)
            {
                repository_files(&path, out);
            }
        } else if name != ".git" {
            out.push(path);
        }
    }
}

/// `path` with `.` and `..` taken out, lexically; `None` when it climbs
/// above its start.
fn normalise(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    Some(out)
}

/// The repository stands alone: no file it ships (source, tests, data,
/// docs, README, CI) names the reference folder that sat beside it while
/// the project was built, or a relative path that climbs out of the
/// repository. A relative path is taken from the file's own folder and
/// from the repository's root (where the tests run); it is wrong only when
/// both leave the repository.
#[test]
fn no_file_points_outside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    repository_files(root, &mut files);
    files.sort();
    // Written in two pieces so that this file does not name it either.
    let reference = concat!("shared", "/");
    let machine = concat!("/work", "/");
    let is_path = |c: char| c.is_ascii_alphanumeric() || "_-./~".contains(c);
    let mut wrong = Vec::new();
    for file in &files {
        let Ok(bytes) = std::fs::read(file) else {
            continue;
        };
        let text = String::from_utf8_lossy(&bytes);
        let rel = file.strip_prefix(root).unwrap();
        let dir = rel.parent().unwrap_or(Path::new(""));
        for (n, line) in text.lines().enumerate() {
            if line.contains(reference) {
                wrong.push(format!(
                    "{}:{}: names {reference}: {}",
                    rel.display(),
                    n + 1,
                    line.trim()
                ));
            }
            if line.contains(machine) {
                wrong.push(format!(
                    "{}:{}: an absolute path of this machine: {}",
                    rel.display(),
                    n + 1,
                    line.trim()
                ));
            }
            let mut from = 0;
            while let Some(i) = line[from..].find("../") {
                let at = from + i;
                let start = line[..at]
                    .char_indices()
                    .rev()
                    .take_while(|(_, c)| is_path(*c))
                    .last()
                    .map_or(at, |(j, _)| j);
                let end = line[at..]
                    .char_indices()
                    .find(|(_, c)| !is_path(*c))
                    .map_or(line.len(), |(j, _)| at + j);
                let token = &line[start..end];
                let inside = |base: &Path| normalise(&base.join(token)).is_some();
                if token.starts_with('/') || (!inside(dir) && !inside(Path::new(""))) {
                    wrong.push(format!(
                        "{}:{}: `{token}` leaves the repository",
                        rel.display(),
                        n + 1
                    ));
                }
                from = end.max(at + 3);
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "the repository must stand alone (a user's clone has nothing beside it):\n{}",
        wrong.join("\n")
    );
}

// ------------------------------------------------- import cycles of files

#[path = "layers/files.rs"]
mod files;
#[path = "layers/lane.rs"]
mod lane;
#[path = "layers/long_fns.rs"]
mod long_fns;
#[path = "layers/names.rs"]
mod names;
