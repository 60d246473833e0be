//! No function of the library is longer than 150 lines: a longer one does
//! several things, each of which wants a name. Every `.rs` file under
//! `src/` is read as Rust (by `syn`, not by a scan of our own), and every
//! function in it, free, method, trait default or nested in another, is
//! measured from the line its body opens on to the line it closes on.

use super::rust_files;
use std::collections::BTreeSet;
use std::path::Path;
use syn::visit::Visit;

/// The longest body a function may have, in lines (its braces included).
const MAX_LINES: usize = 150;

/// Functions allowed to be longer, named exactly (`path::fn`): none since
/// issue 47 split the last. An entry that is no longer long fails too, so
/// that the list can only shrink.
const KNOWN_LONG: &[&str] = &[];

/// A function whose body is longer than [`MAX_LINES`].
#[derive(Debug, PartialEq)]
struct Long {
    name: String,
    line: usize,
    lines: usize,
}

/// Collects the long functions of one file, at every depth.
#[derive(Default)]
struct Measure {
    long: Vec<Long>,
}

impl Measure {
    fn body(&mut self, name: &syn::Ident, block: &syn::Block) {
        let open = block.brace_token.span.open().start().line;
        let close = block.brace_token.span.close().end().line;
        let lines = close + 1 - open;
        if lines > MAX_LINES {
            self.long.push(Long {
                name: name.to_string(),
                line: name.span().start().line,
                lines,
            });
        }
    }
}

impl<'ast> Visit<'ast> for Measure {
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        self.body(&f.sig.ident, &f.block);
        syn::visit::visit_item_fn(self, f);
    }

    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        self.body(&f.sig.ident, &f.block);
        syn::visit::visit_impl_item_fn(self, f);
    }

    fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
        if let Some(block) = &f.default {
            self.body(&f.sig.ident, block);
        }
        syn::visit::visit_trait_item_fn(self, f);
    }
}

/// The functions of `text` longer than [`MAX_LINES`], or why it is not Rust.
fn long_fns(text: &str) -> Result<Vec<Long>, syn::Error> {
    let file = syn::parse_file(text)?;
    let mut measure = Measure::default();
    measure.visit_file(&file);
    Ok(measure.long)
}

#[test]
fn no_function_is_over_150_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    files.sort();
    assert!(files.len() > 100, "src/ read: {} files", files.len());
    let mut wrong = Vec::new();
    let mut known_found = BTreeSet::new();
    for path in &files {
        let rel = path.strip_prefix(root).unwrap_or(path);
        let rel = rel.to_string_lossy().replace('\\', "/");
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{rel}: {e}"));
        let long = long_fns(&text).unwrap_or_else(|e| {
            let at = e.span().start();
            panic!("{rel}:{}:{}: not read as Rust: {e}", at.line, at.column + 1)
        });
        for f in long {
            let named = format!("{rel}::{}", f.name);
            if KNOWN_LONG.contains(&named.as_str()) {
                known_found.insert(named);
            } else {
                wrong.push(format!(
                    "{rel}:{}: fn {} is {} lines long (at most {MAX_LINES})",
                    f.line, f.name, f.lines
                ));
            }
        }
    }
    for known in KNOWN_LONG {
        if !known_found.contains(*known) {
            wrong.push(format!(
                "{known} is listed in KNOWN_LONG but is not over {MAX_LINES} lines \
                 (or not found): take it off the list"
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "functions over {MAX_LINES} lines say several things; split them into named steps:\n{}",
        wrong.join("\n")
    );
}

/// The checker sees a long function at every depth (free, method, trait
/// default, nested), and lets one of exactly 150 lines pass.
#[test]
fn the_checker_finds_long_functions() {
    // A body of `n` lines: its opening line, n - 2 statements, its close.
    let body = |n: usize| {
        let mut s = String::from("{\n");
        for i in 0..n - 2 {
            s.push_str(&format!("    let _x{i} = {i};\n"));
        }
        s.push_str("}\n");
        s
    };
    let snippet = format!(
        "fn fits() {fits}\n\
         fn free() {long}\n\
         struct S;\n\
         impl S {{\n fn method(&self) {long} }}\n\
         trait T {{\n fn provided(&self) {long} fn required(&self); }}\n\
         fn outer() {{\n fn nested() {long} }}\n",
        fits = body(150),
        long = body(151),
    );
    let found = long_fns(&snippet).expect("the snippet is Rust");
    let names: Vec<(&str, usize)> = found.iter().map(|f| (f.name.as_str(), f.lines)).collect();
    assert_eq!(
        names,
        [
            ("free", 151),
            ("method", 151),
            ("provided", 151),
            // `outer` holds `nested`, so it is long too.
            ("outer", 153),
            ("nested", 151)
        ]
    );
    // `free` is named two lines after `fits`'s 150 (a blank one between).
    assert_eq!(found[0].line, 152);
    assert!(long_fns("fn broken( {").is_err());
}
