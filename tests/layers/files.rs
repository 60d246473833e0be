//! Import cycles of files: within every folder of `src/`, no file
//! imports, through others of its folder, a file that imports it. The
//! reading is the files' own: `use` declarations, paths in the code, and
//! glob imports of the names a file reads.

use super::rust_files;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

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

/// No file of `src/` imports, through others, a file that imports it: each
/// folder reads as layers of files. A folder's cycle is a cycle of the
/// whole tree's graph cut down to that folder, and cutting only removes
/// arrows, so every folder's cycle lies inside one of the whole tree's:
/// reading `src/` whole holds every folder, today's and tomorrow's, and
/// `src/lib.rs` and the files at the top with them.
#[test]
fn no_files_of_a_folder_import_each_other_in_a_cycle() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("src");
    let graph = file_imports(&src);
    let mut wrong = Vec::new();
    for cycle in cycles(&graph) {
        let names: Vec<String> = cycle
            .iter()
            .map(|f| f.strip_prefix(root).unwrap().display().to_string())
            .collect();
        let edges: Vec<String> = cycle
            .iter()
            .flat_map(|f| {
                graph[f].iter().filter(|t| cycle.contains(t)).map(|t| {
                    format!(
                        "{} -> {}",
                        f.strip_prefix(&src).unwrap().display(),
                        t.strip_prefix(&src).unwrap().display()
                    )
                })
            })
            .collect();
        wrong.push(format!("{} ({})", names.join(", "), edges.join("; ")));
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
