//! The fast lane is the reader's own: no library file outside
//! `src/rapid/` names its compact storage (the runs of moves, of
//! declarations and of array elements) or the switch that turns it off.
//! Passes outside the reader see every statement and declaration through
//! the reader's view (`Program::statements`, `items`, `module_data`,
//! `value_of`), which yields those of the runs too.

use super::{code_of, rust_files};
use std::path::Path;

/// Names of the lane's storage: the switch and the module field, and the
/// variants (of `StatementKind` and `Expr`) that held runs in the tree.
const FIELDS: &[&str] = &["decl_runs", "lanes"];
const VARIANTS: &[(&str, &str)] = &[("StatementKind", "Moves"), ("Expr", "Elements")];

fn is_word(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

/// Where the identifier `word` stands in `code` as a whole word.
fn words<'c>(code: &'c str, word: &'c str) -> impl Iterator<Item = usize> + 'c {
    code.match_indices(word).map(|(i, _)| i).filter(move |&i| {
        let b = code.as_bytes();
        (i == 0 || !is_word(b[i - 1])) && b.get(i + word.len()).is_none_or(|&c| !is_word(c))
    })
}

/// The path segment before `::` ending at `at` (`StatementKind` of
/// `StatementKind::Moves`), if any.
fn segment_before(code: &str, at: usize) -> Option<&str> {
    let head = code[..at].trim_end().strip_suffix("::")?.trim_end();
    let start = head.bytes().rposition(|b| !is_word(b)).map_or(0, |p| p + 1);
    Some(&head[start..])
}

/// The lane's names in one file's code (comments removed): `in_robot` for
/// the robot's files, whose own `lanes` module (SIMD lanes of the IK) is
/// no business of the reader's.
fn lane_names(code: &str, in_robot: bool) -> Vec<String> {
    let mut found = Vec::new();
    for f in FIELDS {
        for at in words(code, f) {
            let rest = code[at + f.len()..].trim_start();
            let module_path = *f == "lanes"
                && in_robot
                && (rest.starts_with("::") || code[..at].trim_end().ends_with("mod"));
            if !module_path {
                found.push(f.to_string());
            }
        }
    }
    for (owner, variant) in VARIANTS {
        // The enum by its name, or by a name it is imported as.
        let mut names = vec![owner.to_string()];
        for at in words(code, owner) {
            let rest = code[at + owner.len()..].trim_start();
            if let Some(alias) = rest.strip_prefix("as ") {
                let alias: String = alias
                    .trim_start()
                    .bytes()
                    .take_while(|&b| is_word(b))
                    .map(char::from)
                    .collect();
                names.push(alias);
            }
        }
        for at in words(code, variant) {
            if segment_before(code, at).is_some_and(|s| names.iter().any(|n| n == s)) {
                found.push(format!("{owner}::{variant}"));
            }
        }
    }
    found
}

#[test]
fn no_file_outside_the_reader_names_the_lanes_storage() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut wrong = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&src).unwrap();
        if rel.starts_with("rapid") {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(file).unwrap());
        for name in lane_names(&code, rel.starts_with("robot")) {
            wrong.push(format!("{}: {name}", rel.display()));
        }
    }
    assert!(
        wrong.is_empty(),
        "files outside src/rapid/ naming the fast lane's storage: {wrong:?}"
    );
}

#[test]
fn the_lanes_names_are_found_however_written() {
    let named = [
        (
            "match &s.kind { StatementKind::Moves(run) => {} }",
            "StatementKind::Moves",
        ),
        (
            "use crate::rapid::StatementKind as S;\nS :: Moves(r) => {}",
            "StatementKind::Moves",
        ),
        ("Some(Expr::Elements(run)) => {}", "Expr::Elements"),
        ("for &r in &m.decl_runs {}", "decl_runs"),
        ("rapid::ParseOptions { lanes: false }", "lanes"),
        ("use super::lanes::sin_cos6;", "lanes"),
    ];
    for (code, name) in named {
        assert_eq!(lane_names(code, false), [name], "{code}");
    }
    // Other enums' variants of these names, and the robot's own module.
    let innocent = [
        "Finding::Moves(c) => Row {}",
        "FindingStatus::Moves => \"moves\"",
        "let elements = Elements(3);",
        "mod lanes;\nuse super::lanes::sin_cos6;",
    ];
    for code in innocent {
        assert!(lane_names(code, true).is_empty(), "{code}");
    }
}
