//! A first look at a URDF before urdf-rs reads it: what the reader would
//! choke on, found with a flat (non-recursive) XML reader, and where each
//! joint and link stands in the file, so that every later error names its
//! line and column.
//!
//! urdf-rs deserialises through serde, which recurses once per nested
//! element: a file of 20,000 nested elements overflows the stack. Numbers
//! are read by Rust's `f64` parser, which takes `NaN` and `inf`: a joint
//! origin of `NaN` then makes every pose NaN and fits never end. Both are
//! refused here.

use crate::error::{Error, Location, Result};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::HashMap;

/// Deepest element nesting a URDF may have. A URDF nests four or five
/// deep (`robot/link/visual/geometry/mesh`); `gazebo` and `transmission`
/// extensions a few more.
pub const MAX_DEPTH: usize = 64;

/// Where the joints and links of a URDF are, by name: byte offsets of
/// their start tags.
#[derive(Debug, Default)]
pub struct UrdfIndex {
    file: String,
    text: String,
    joints: HashMap<String, usize>,
    links: HashMap<String, usize>,
}

impl UrdfIndex {
    fn location(&self, offset: usize) -> Location {
        Location::from_offset(&self.file, self.text.as_bytes(), offset)
    }

    /// Where joint `name` is declared (the file's start when unknown).
    pub fn joint(&self, name: &str) -> Location {
        self.location(self.joints.get(name).copied().unwrap_or(0))
    }

    /// Where link `name` is declared (the file's start when unknown).
    pub fn link(&self, name: &str) -> Location {
        self.location(self.links.get(name).copied().unwrap_or(0))
    }
}

/// Check `text` and index it; `file` names it in messages.
pub fn scan(file: &str, text: &str) -> Result<UrdfIndex> {
    let mut index = UrdfIndex {
        file: file.to_string(),
        text: text.to_string(),
        ..UrdfIndex::default()
    };
    let mut reader = Reader::from_str(text);
    let mut depth = 0usize;
    let mut errors = crate::error::Errors::default();
    loop {
        let pos = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| {
            Error::input(format!("not a readable URDF: {e}"))
                .at(index.location(reader.error_position() as usize))
        })?;
        let (start, empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                depth = depth.saturating_sub(1);
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        if !empty {
            depth += 1;
            if depth > MAX_DEPTH {
                return Err(Error::input(format!(
                    "elements nested more than {MAX_DEPTH} deep: not a URDF this reader takes"
                ))
                .at(index.location(pos)));
            }
        }
        check_numbers(start, pos, &index, &mut errors);
        let tag = start.name();
        let map = match tag.as_ref() {
            b"joint" => &mut index.joints,
            b"link" => &mut index.links,
            _ => continue,
        };
        if let Some(name) = attribute(start, "name") {
            map.entry(name).or_insert(pos);
        }
    }
    match errors
        .into_error(|n| Error::input(format!("{n} values of the URDF are not finite numbers")))
    {
        Some(e) => Err(e),
        None => Ok(index),
    }
}

fn attribute(e: &BytesStart, key: &str) -> Option<String> {
    let a = e.try_get_attribute(key).ok()??;
    a.unescape_value().ok().map(|v| v.into_owned())
}

/// Every attribute that is a list of numbers must hold finite ones.
fn check_numbers(e: &BytesStart, pos: usize, index: &UrdfIndex, errors: &mut crate::error::Errors) {
    for a in e.attributes().flatten() {
        // Names may be anything, `nan` included; only values are numbers.
        let key = a.key.as_ref();
        if [
            b"name".as_slice(),
            b"type",
            b"link",
            b"joint",
            b"filename",
            b"version",
        ]
        .contains(&key)
        {
            continue;
        }
        let Ok(value) = a.unescape_value() else {
            continue;
        };
        let tokens: Vec<&str> = value.split_whitespace().collect();
        let numbers: Vec<f64> = tokens.iter().filter_map(|t| t.parse().ok()).collect();
        if !tokens.is_empty()
            && numbers.len() == tokens.len()
            && numbers.iter().any(|v| !v.is_finite())
        {
            errors.push(
                Error::input(format!(
                    "<{} {}=\"{value}\">: not a finite number",
                    String::from_utf8_lossy(e.name().as_ref()),
                    String::from_utf8_lossy(a.key.as_ref()),
                ))
                .at(index.location(pos)),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deep_nesting_is_refused_without_recursion() {
        let deep = format!(
            "<robot name=\"r\">{}{}</robot>",
            "<a>".repeat(20_000),
            "</a>".repeat(20_000)
        );
        let e = scan("deep.urdf", &deep).unwrap_err();
        assert!(e.to_string().contains("nested more than 64"), "{e}");
        assert_eq!(e.location.as_ref().unwrap().line, 1);
    }

    #[test]
    fn non_finite_numbers_are_refused_where_they_stand() {
        let text = "<robot name=\"r\">\n  <joint name=\"j\" type=\"fixed\">\n    <origin xyz=\"0 0 0\" rpy=\"0 NaN 0\"/>\n  </joint>\n  <link name=\"l\"><inertial><mass value=\"inf\"/></inertial></link>\n</robot>\n";
        let e = scan("nan.urdf", text).unwrap_err();
        let shown = e.to_string();
        assert!(shown.contains("nan.urdf:3:5"), "{shown}");
        assert!(shown.contains("rpy=\"0 NaN 0\""), "{shown}");
        assert!(shown.contains("nan.urdf:5:"), "both are reported: {shown}");
    }

    #[test]
    fn joints_and_links_are_found_by_name() {
        let text = "<robot name=\"r\">\n<link name=\"base\"/>\n<joint name=\"j1\" type=\"revolute\"/>\n</robot>";
        let index = scan("r.urdf", text).unwrap();
        assert_eq!(index.joint("j1").line, 3);
        assert_eq!(index.link("base").line, 2);
        assert_eq!(index.link("nowhere").line, 1);
    }
}
