//! One name per public type across the library: two `pub` structs,
//! enums, traits or type aliases of one name in different files make a
//! reader (and a user importing from two layers) ask which is meant, as
//! `ToolData` once stood for both the RAPID declaration and the
//! kinematic tool frame.

use super::{code_of, rust_files};
use std::collections::BTreeMap;
use std::path::Path;

/// The public types a file's code declares (`pub struct X`, `pub enum
/// X`, `pub trait X`, `pub type X`; `pub(crate)` and narrower are the
/// file's own business).
fn public_types(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in code.lines() {
        let mut words = line.split_whitespace();
        if words.next() != Some("pub") {
            continue;
        }
        let Some(kind) = words.next() else { continue };
        if !matches!(kind, "struct" | "enum" | "trait" | "type") {
            continue;
        }
        if let Some(name) = words.next() {
            let name: String = name
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.push(name);
            }
        }
    }
    out
}

/// Every name declared public in more than one file, with its files.
fn shared_names(files: &[(String, String)]) -> BTreeMap<String, Vec<String>> {
    let mut by_name: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for (path, text) in files {
        for name in public_types(&code_of(text)) {
            by_name.entry(name).or_default().push(path.clone());
        }
    }
    by_name.retain(|_, files| files.len() > 1);
    by_name
}

#[test]
fn every_public_type_has_a_name_of_its_own() {
    let mut paths = Vec::new();
    rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut paths,
    );
    paths.sort();
    let files: Vec<(String, String)> = paths
        .iter()
        .map(|p| {
            (
                p.display().to_string(),
                std::fs::read_to_string(p).expect("readable"),
            )
        })
        .collect();
    assert!(files.len() > 100, "the library's files were read");
    let shared = shared_names(&files);
    assert!(
        shared.is_empty(),
        "public types sharing a name:\n{}",
        shared
            .iter()
            .map(|(n, fs)| format!("  {n}: {}", fs.join(", ")))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn the_check_sees_a_name_declared_twice_and_not_a_private_one() {
    let files = vec![
        (
            "a.rs".to_string(),
            "pub struct ToolData {\n}\npub(crate) struct Ahead;\n".to_string(),
        ),
        (
            "b.rs".to_string(),
            "pub enum ToolData { A }\npub(super) struct Ahead;\n// pub struct Commented;\n"
                .to_string(),
        ),
        ("c.rs".to_string(), "pub struct Commented;\n".to_string()),
    ];
    let shared = shared_names(&files);
    assert_eq!(
        shared.keys().collect::<Vec<_>>(),
        vec!["ToolData"],
        "{shared:?}"
    );
}
