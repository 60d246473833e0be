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
    ("digest", &[]),
    ("csv_table", &["error"]),
    ("report", &["error"]),
    ("plot", &["error"]),
    ("rapid", &["error"]),
    ("robot", &["error", "csv_table"]),
    ("thermal", &["error", "csv_table", "report", "plot"]),
    ("model", &["error", "csv_table", "robot", "thermal"]),
    ("resolve", &["error", "digest", "rapid", "robot"]),
    (
        "schedule",
        &["error", "digest", "csv_table", "rapid", "robot", "resolve"],
    ),
    (
        "correct",
        &[
            "error", "digest", "plot", "rapid", "robot", "thermal", "model", "resolve", "schedule",
        ],
    ),
    ("compare", &["error", "rapid", "robot", "resolve"]),
    (
        "diagnose",
        &[
            "error",
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
        if path.is_dir() {
            if ![".git", "target", "corpus", "artifacts", "coverage"]
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

/// The folders whose files may not import each other in a cycle: the main
/// job's layers, where a cycle made the orchestration hard to follow.
const ACYCLIC_FOLDERS: &[&str] = &["correct"];

/// A file's code with comments, strings and character literals blanked
/// out (kept as spaces, so that lines stay where they were), cut before its
/// `#[cfg(test)]` module: what it imports to run.
fn code_only(text: &str) -> String {
    let text = match text.find("\n#[cfg(test)]") {
        Some(i) => &text[..i],
        None => text,
    };
    let b = text.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    out.push(b' ');
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let mut depth = 0;
                while i < b.len() {
                    if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                        depth += 1;
                        out.extend_from_slice(b"  ");
                        i += 2;
                    } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                        depth -= 1;
                        out.extend_from_slice(b"  ");
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        out.push(if b[i] == b'\n' { b'\n' } else { b' ' });
                        i += 1;
                    }
                }
            }
            // A raw string r"..." / r#"..."#.
            b'r' if (b.get(i + 1) == Some(&b'"') || b.get(i + 1) == Some(&b'#'))
                && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) =>
            {
                let mut j = i + 1;
                let mut hashes = 0;
                while b.get(j) == Some(&b'#') {
                    hashes += 1;
                    j += 1;
                }
                if b.get(j) != Some(&b'"') {
                    out.push(b[i]);
                    i += 1;
                    continue;
                }
                j += 1;
                loop {
                    if j >= b.len() {
                        break;
                    }
                    if b[j] == b'"'
                        && b[j + 1..]
                            .iter()
                            .take(hashes)
                            .filter(|&&c| c == b'#')
                            .count()
                            == hashes
                    {
                        j += 1 + hashes;
                        break;
                    }
                    j += 1;
                }
                for &c in &b[i..j.min(b.len())] {
                    out.push(if c == b'\n' { b'\n' } else { b' ' });
                }
                i = j;
            }
            b'"' => {
                out.push(b' ');
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    if b[i] == b'\\' {
                        out.push(b' ');
                        i += 1;
                    }
                    if i < b.len() {
                        out.push(if b[i] == b'\n' { b'\n' } else { b' ' });
                        i += 1;
                    }
                }
                out.push(b' ');
                i += 1;
            }
            // A character literal ('a', '\n', '\''), not a lifetime ('a).
            b'\'' => {
                let close = if b.get(i + 1) == Some(&b'\\') {
                    b[i + 2..]
                        .iter()
                        .position(|&c| c == b'\'')
                        .map(|p| i + 2 + p)
                } else if b.get(i + 2) == Some(&b'\'') {
                    Some(i + 2)
                } else {
                    // A multi-byte character.
                    let s = &text[i + 1..];
                    s.chars()
                        .next()
                        .filter(|c| s[c.len_utf8()..].starts_with('\''))
                        .map(|c| i + 1 + c.len_utf8())
                };
                match close {
                    Some(end) => {
                        out.extend(std::iter::repeat_n(b' ', end + 1 - i));
                        i = end + 1;
                    }
                    None => {
                        out.push(b'\'');
                        i += 1;
                    }
                }
            }
            c => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// A library or binary file as a module: its path of module names from the
/// crate root (`src/correct/solve.rs` → `correct::solve`, a `mod.rs` the
/// folder's module).
#[derive(Clone)]
struct ModFile {
    path: PathBuf,
    module: Vec<String>,
}

fn mod_file(src: &Path, file: &Path) -> Option<ModFile> {
    let rel = file.strip_prefix(src).ok()?;
    let mut module: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    let last = module.pop()?;
    if !matches!(last.as_str(), "mod" | "lib" | "main") {
        module.push(last);
    }
    // The binary's files live under `crate::cli` of the binary crate; the
    // library's under its own root: both are read as one tree here.
    Some(ModFile {
        path: file.to_path_buf(),
        module,
    })
}

/// The file of module `module` (names from the crate root), if it has one.
fn file_of(src: &Path, module: &[String]) -> Option<PathBuf> {
    if module.is_empty() {
        return Some(src.join("lib.rs"));
    }
    let base: PathBuf = module.iter().collect();
    let flat = src.join(&base).with_extension("rs");
    let nested = src.join(&base).join("mod.rs");
    [flat, nested].into_iter().find(|p| p.is_file())
}

/// Names a file defines at its top level (functions, types, traits,
/// constants, statics, macros).
fn defined_names(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in code.lines() {
        if line.starts_with(' ') || line.starts_with('\t') {
            continue;
        }
        let mut rest = line;
        if let Some(r) = rest.strip_prefix("pub") {
            rest = r.trim_start();
            if rest.starts_with('(') {
                rest = rest.split_once(')').map_or("", |x| x.1).trim_start();
            }
        }
        for kw in [
            "const fn ",
            "unsafe fn ",
            "fn ",
            "struct ",
            "enum ",
            "trait ",
            "type ",
            "const ",
            "static ",
            "union ",
            "macro_rules! ",
        ] {
            if let Some(r) = rest.strip_prefix(kw) {
                let name: String = r
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    out.insert(name);
                }
                break;
            }
        }
    }
    out
}

/// Every `use` declaration of a file, its braces expanded into paths of
/// segments (`use super::{a, b::{c, d}}` → `super::a`, `super::b::c`,
/// `super::b::d`); `pub` ones marked. `as` renames keep the original name.
fn use_paths(code: &str) -> Vec<(bool, Vec<String>)> {
    fn expand(prefix: &[String], text: &str, out: &mut Vec<Vec<String>>) {
        let text = text.trim();
        if text.is_empty() {
            return;
        }
        // Split at top-level commas.
        let mut depth = 0;
        let mut parts = Vec::new();
        let mut start = 0;
        for (i, c) in text.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    parts.push(&text[start..i]);
                    start = i + 1;
                }
                _ => {}
            }
        }
        parts.push(&text[start..]);
        if parts.len() > 1 {
            for p in parts {
                expand(prefix, p, out);
            }
            return;
        }
        let one = parts[0].trim();
        if one.is_empty() {
            return;
        }
        match one.find('{') {
            Some(b) => {
                let head = one[..b].trim_end_matches(':').trim_end_matches(':');
                let inner = one[b + 1..].trim_end().trim_end_matches('}');
                let mut p = prefix.to_vec();
                p.extend(
                    head.split("::")
                        .filter(|s| !s.is_empty())
                        .map(str::to_string),
                );
                expand(&p, inner, out);
            }
            None => {
                let one = one.split(" as ").next().unwrap_or(one).trim();
                let mut p = prefix.to_vec();
                p.extend(one.split("::").map(|s| s.trim().to_string()));
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("use ") {
        let before = &rest[..i];
        let at_start = before.is_empty()
            || before.ends_with('\n')
            || before.ends_with(' ')
            || before.ends_with('\t')
            || before.ends_with(')')
            || before.ends_with(';')
            || before.ends_with('{');
        let word_start = i == 0
            || !rest.as_bytes()[i - 1].is_ascii_alphanumeric() && rest.as_bytes()[i - 1] != b'_';
        rest = &rest[i + 4..];
        if !(at_start && word_start) {
            continue;
        }
        let Some(end) = rest.find(';') else { break };
        let public = before.trim_end().ends_with("pub")
            || before.trim_end().ends_with(')') && before.contains("pub(");
        let mut paths = Vec::new();
        expand(&[], &rest[..end], &mut paths);
        out.extend(paths.into_iter().map(|p| (public, p)));
        rest = &rest[end..];
    }
    out
}

/// The module a path's first segments name, from `file` (`crate`, `super`,
/// `self`, or a child module of `file`'s own), and the segments after it.
fn resolve_path<'p>(
    src: &Path,
    file: &ModFile,
    path: &'p [String],
) -> Option<(Vec<String>, &'p [String])> {
    let (mut module, mut rest) = match path.first()?.as_str() {
        "crate" => (Vec::new(), &path[1..]),
        "super" => {
            let mut m = file.module.clone();
            let mut rest = path;
            while rest.first().is_some_and(|s| s == "super") {
                m.pop()?;
                rest = &rest[1..];
            }
            (m, rest)
        }
        "self" => (file.module.clone(), &path[1..]),
        first => {
            // A child module of this file's (declared with `mod`).
            let mut m = file.module.clone();
            m.push(first.to_string());
            file_of(src, &m)?;
            (file.module.clone(), path)
        }
    };
    while let Some(seg) = rest.first() {
        let mut m = module.clone();
        m.push(seg.clone());
        if file_of(src, &m).is_some() {
            module = m;
            rest = &rest[1..];
        } else {
            break;
        }
    }
    Some((module, rest))
}

/// Identifiers of a file's code.
fn identifiers(code: &str) -> BTreeSet<String> {
    code.split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .filter(|w| {
            w.chars()
                .next()
                .is_some_and(|c| c.is_alphabetic() || c == '_')
        })
        .map(str::to_string)
        .collect()
}

/// The import graph of the files under `src`: file → the files whose
/// names it uses (through `use` declarations, paths in its code, and
/// glob imports of the names it reads), following a module's `pub use`
/// of a child to the child that defines the name.
fn file_imports(src: &Path) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let infos: Vec<ModFile> = files.iter().filter_map(|f| mod_file(src, f)).collect();
    let code: BTreeMap<PathBuf, String> = files
        .iter()
        .map(|f| (f.clone(), code_only(&std::fs::read_to_string(f).unwrap())))
        .collect();
    let defined: BTreeMap<PathBuf, BTreeSet<String>> = code
        .iter()
        .map(|(f, c)| (f.clone(), defined_names(c)))
        .collect();
    // What each module file re-exports: name → the child file defining it,
    // and the files it re-exports wholesale (`pub use child::*`).
    let mut reexports: BTreeMap<PathBuf, (BTreeMap<String, PathBuf>, Vec<PathBuf>)> =
        BTreeMap::new();
    for info in &infos {
        let entry = reexports.entry(info.path.clone()).or_default();
        for (public, path) in use_paths(&code[&info.path]) {
            if !public {
                continue;
            }
            let Some((module, rest)) = resolve_path(src, info, &path) else {
                continue;
            };
            let Some(target) = file_of(src, &module) else {
                continue;
            };
            match rest.first().map(String::as_str) {
                Some("*") => entry.1.push(target),
                Some(name) => {
                    entry.0.insert(name.to_string(), target);
                }
                None => {}
            }
        }
    }
    // The file that defines `name`, looked for in `file` and what it
    // re-exports.
    let definer = |file: &PathBuf, name: &str| -> Option<PathBuf> {
        if defined.get(file).is_some_and(|d| d.contains(name)) {
            return Some(file.clone());
        }
        let (named, globs) = reexports.get(file)?;
        if let Some(t) = named.get(name) {
            return Some(t.clone());
        }
        globs
            .iter()
            .find(|g| defined.get(*g).is_some_and(|d| d.contains(name)))
            .cloned()
    };
    let mut graph: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
    for info in &infos {
        let c = &code[&info.path];
        let used = identifiers(c);
        let mut edges = BTreeSet::new();
        let add = |module: &[String], rest: &[String], edges: &mut BTreeSet<PathBuf>| {
            let Some(target) = file_of(src, module) else {
                return;
            };
            match rest.first().map(String::as_str) {
                None => {
                    edges.insert(target);
                }
                Some("*") => {
                    for name in &used {
                        if let Some(d) = definer(&target, name) {
                            edges.insert(d);
                        }
                    }
                }
                Some(name) => {
                    edges.insert(definer(&target, name).unwrap_or(target));
                }
            }
        };
        for (_, path) in use_paths(c) {
            if let Some((module, rest)) = resolve_path(src, info, &path) {
                add(&module, rest, &mut edges);
            }
        }
        // Paths written in the code: `crate::a::b`, `super::x::y`, and in a
        // module file its children's `child::name`.
        let words: Vec<&str> = c
            .split(|ch: char| !(ch.is_alphanumeric() || ch == '_' || ch == ':'))
            // `use super::{a, b}` leaves `super::` here: its paths are the
            // `use` declaration's.
            .filter(|w| w.contains("::") && !w.ends_with("::"))
            .collect();
        for w in words {
            let path: Vec<String> = w
                .split("::")
                .filter(|s| !s.is_empty())
                .map(str::to_string)
                .collect();
            if let Some((module, rest)) = resolve_path(src, info, &path) {
                if module != info.module || !rest.is_empty() && path[0] != "self" {
                    add(&module, rest, &mut edges);
                }
            }
        }
        edges.remove(&info.path);
        graph.insert(info.path.clone(), edges);
    }
    graph
}

/// The cycles (strongly connected sets of more than one file) of a graph.
fn cycles(graph: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<PathBuf>> {
    // Tarjan's algorithm, iteratively small enough to recurse here.
    struct State<'g> {
        graph: &'g BTreeMap<PathBuf, BTreeSet<PathBuf>>,
        index: BTreeMap<&'g PathBuf, usize>,
        low: BTreeMap<&'g PathBuf, usize>,
        stack: Vec<&'g PathBuf>,
        on: BTreeSet<&'g PathBuf>,
        next: usize,
        out: Vec<Vec<PathBuf>>,
    }
    fn visit<'g>(s: &mut State<'g>, v: &'g PathBuf) {
        s.index.insert(v, s.next);
        s.low.insert(v, s.next);
        s.next += 1;
        s.stack.push(v);
        s.on.insert(v);
        for w in s.graph.get(v).into_iter().flatten() {
            let Some((w, _)) = s.graph.get_key_value(w) else {
                continue;
            };
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut set = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on.remove(w);
                set.push(w.clone());
                if w == v {
                    break;
                }
            }
            if set.len() > 1 {
                set.sort();
                s.out.push(set);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// No file of the main job's folders imports, through others of its
/// folder, a file that imports it: each folder reads as layers of files.
#[test]
fn no_files_of_a_folder_import_each_other_in_a_cycle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("src");
    let graph = file_imports(&src);
    let mut wrong = Vec::new();
    for folder in ACYCLIC_FOLDERS {
        let dir = src.join(folder);
        let inside: BTreeMap<PathBuf, BTreeSet<PathBuf>> = graph
            .iter()
            .filter(|(f, _)| f.starts_with(&dir))
            .map(|(f, to)| {
                let to = to.iter().filter(|t| t.starts_with(&dir)).cloned().collect();
                (f.clone(), to)
            })
            .collect();
        for cycle in cycles(&inside) {
            let names: Vec<String> = cycle
                .iter()
                .map(|f| f.strip_prefix(root).unwrap().display().to_string())
                .collect();
            let src = &src;
            let edges: Vec<String> = cycle
                .iter()
                .flat_map(|f| {
                    inside[f]
                        .iter()
                        .filter(|t| cycle.contains(t))
                        .map(move |t| {
                            format!(
                                "{} -> {}",
                                f.strip_prefix(src).unwrap().display(),
                                t.strip_prefix(src).unwrap().display()
                            )
                        })
                })
                .collect();
            wrong.push(format!("{} ({})", names.join(", "), edges.join("; ")));
        }
    }
    assert!(
        wrong.is_empty(),
        "files importing each other in a cycle:\n{}",
        wrong.join("\n")
    );
}

/// The file-level reading finds a cycle where there is one, follows a
/// module's re-export to the file that defines the name, and ignores
/// comments, strings and tests.
#[test]
fn the_file_level_reading_sees_cycles_and_only_cycles() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    let write = |rel: &str, text: &str| {
        let p = src.join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    };
    write("lib.rs", "pub mod m;\n");
    write(
        "m/mod.rs",
        "mod a;\nmod b;\nmod c;\npub use c::Shared;\npub fn top() { a::run(); }\n",
    );
    write("m/a.rs", "use super::b::helper;\n// super::c::Nothing\npub fn run() { helper(); let _ = \"super::c::x\"; }\n");
    write("m/b.rs", "use super::Shared;\npub fn helper() {}\n#[cfg(test)]\nmod tests { use super::super::a::run; }\n");
    write(
        "m/c.rs",
        "pub struct Shared;\npub fn back() { super::a::run(); }\n",
    );
    let graph = file_imports(&src);
    let f = |rel: &str| src.join(rel);
    assert!(graph[&f("m/a.rs")].contains(&f("m/b.rs")));
    assert!(
        graph[&f("m/b.rs")].contains(&f("m/c.rs")),
        "through the re-export"
    );
    assert!(
        !graph[&f("m/b.rs")].contains(&f("m/a.rs")),
        "tests are not read"
    );
    assert!(
        !graph[&f("m/a.rs")].contains(&f("m/c.rs")),
        "comments and strings are not read"
    );
    // a -> b -> c -> a.
    let found = cycles(&graph);
    assert_eq!(found, vec![vec![f("m/a.rs"), f("m/b.rs"), f("m/c.rs")]]);
    write("m/c.rs", "pub struct Shared;\n");
    assert!(cycles(&file_imports(&src)).is_empty());
}
