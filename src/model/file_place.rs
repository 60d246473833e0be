//! Where a key of a model file stands, so that an error about a value the
//! TOML parser accepted (a negative length, a motor 7) names its line and
//! column and the key, not the start of the file.

use crate::error::Location;
use toml::de::{DeTable, DeValue};

/// One step of a key path: a table key or an array index.
#[derive(Debug, Clone, PartialEq)]
pub enum KeyStep {
    Key(&'static str),
    Name(String),
    Index(usize),
}

/// A key path as a reader writes it: `thermal.base.motors`,
/// `effects[2].params.dk_base`.
pub fn dotted(path: &[KeyStep]) -> String {
    let mut out = String::new();
    for p in path {
        match p {
            KeyStep::Key(k) => push_key(&mut out, k),
            KeyStep::Name(k) => push_key(&mut out, k),
            KeyStep::Index(i) => out.push_str(&format!("[{}]", i + 1)),
        }
    }
    out
}

fn push_key(out: &mut String, k: &str) {
    if !out.is_empty() {
        out.push('.');
    }
    out.push_str(k);
}

/// The place of the deepest part of `path` that the text has (the key
/// itself, or the table that lacks it); the file's start when the text
/// does not parse.
pub fn locate(file: &str, text: &str, path: &[KeyStep]) -> Location {
    let at = DeTable::parse(text).ok().map_or(0, |root| {
        let mut best = 0;
        let mut table: Option<&DeTable> = Some(root.get_ref());
        let mut value: Option<&DeValue> = None;
        for part in path {
            let next = match (part, table, value) {
                (KeyStep::Key(_) | KeyStep::Name(_), Some(t), _) => {
                    let want = match part {
                        KeyStep::Key(k) => *k,
                        KeyStep::Name(k) => k.as_str(),
                        KeyStep::Index(_) => unreachable!(),
                    };
                    t.iter()
                        .find(|(k, _)| k.get_ref().as_ref() == want)
                        .map(|(k, v)| (k.span().start, v))
                }
                (KeyStep::Index(i), _, Some(DeValue::Array(a))) => {
                    a.get(*i).map(|v| (v.span().start, v))
                }
                _ => None,
            };
            let Some((start, v)) = next else { break };
            best = start;
            value = Some(v.get_ref());
            table = match v.get_ref() {
                DeValue::Table(t) => Some(t),
                _ => None,
            };
        }
        best
    });
    Location::from_offset(file, text.as_bytes(), at)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "[robot]\nname = \"x\"\n[thermal]\nk0 = -1\n[[effects]]\nname = \"a\"\n[[effects]]\nname = \"b\"\n[effects.params]\ndk = 2\n";

    #[test]
    fn keys_tables_and_array_elements_are_found() {
        let l = locate(
            "m.toml",
            TEXT,
            &[KeyStep::Key("thermal"), KeyStep::Key("k0")],
        );
        assert_eq!((l.line, l.col), (4, 1));
        let l = locate(
            "m.toml",
            TEXT,
            &[
                KeyStep::Key("effects"),
                KeyStep::Index(1),
                KeyStep::Key("params"),
                KeyStep::Name("dk".into()),
            ],
        );
        assert_eq!((l.line, l.col), (10, 1));
        // A key the file lacks: the deepest part it has.
        let l = locate(
            "m.toml",
            TEXT,
            &[KeyStep::Key("thermal"), KeyStep::Key("t_ref")],
        );
        assert_eq!(l.line, 3);
        assert_eq!(
            dotted(&[
                KeyStep::Key("effects"),
                KeyStep::Index(1),
                KeyStep::Key("params")
            ]),
            "effects[2].params"
        );
    }
}
