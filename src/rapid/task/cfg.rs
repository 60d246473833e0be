//! ABB's configuration files (`SYSPAR/*.cfg`): what a backup says about its
//! tasks and robots.
//!
//! The format (RobotWare's "CFG_1.0"): a header line `SYS:CFG_1.0:6:0::`,
//! then sections. A section starts with a line `NAME:` in the first column
//! and ends with a line `#`. Each instance of a section is one line of
//! `-Attribute value` pairs (a bare `-Attribute` is a flag), continued on
//! the next line after a trailing `\`. Values are quoted strings, numbers
//! or comma lists. Only what rapidtherm reads is interpreted; everything
//! else is kept as text. Every value keeps its line and column, so that a
//! value rapidtherm cannot use is reported where it stands.

use crate::error::{split_lines, Error, Location};
use std::collections::BTreeMap;

/// One attribute of an instance: its name as written, its value (`None`
/// for a flag) and where the value (or the flag) stands in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Attribute {
    pub name: String,
    pub value: Option<String>,
    /// 1-based line and column (characters) of the value, or of the flag.
    pub line: usize,
    pub col: usize,
}

/// One instance: its attributes in file order, and the line it starts on.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Instance {
    pub attributes: Vec<Attribute>,
    pub line: usize,
}

impl Instance {
    fn find(&self, name: &str) -> Option<&Attribute> {
        self.attributes
            .iter()
            .find(|a| a.name.eq_ignore_ascii_case(name))
    }

    /// The value of an attribute (names compare case-insensitively, as the
    /// controller's do: `-Name` and `-name` both occur).
    pub fn get(&self, name: &str) -> Option<&str> {
        self.find(name).and_then(|a| a.value.as_deref())
    }

    /// Where an attribute's value stands: line and column.
    pub fn place(&self, name: &str) -> Option<(usize, usize)> {
        self.find(name).map(|a| (a.line, a.col))
    }

    /// True when the attribute is present, as a flag or with a value.
    pub fn has(&self, name: &str) -> bool {
        self.find(name).is_some()
    }
}

/// A whole configuration file: the instances of each section, by
/// upper-case section name, and the file's text for messages.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cfg {
    pub sections: BTreeMap<String, Vec<Instance>>,
    /// The file's name, as messages give it.
    pub file: String,
    lines: Vec<String>,
}

impl Cfg {
    /// Read a configuration file's text. A line that is not understood is
    /// skipped, so that a backup of a newer RobotWare still gives what this
    /// reader knows; but a file without the `CFG_` header line is not a
    /// configuration file at all, and that is an error at its first line.
    pub fn parse(file: &str, text: &str) -> Result<Cfg, Error> {
        let header = split_lines(text).find(|l| !l.trim().is_empty());
        if !header.is_some_and(|h| h.contains(":CFG_")) {
            let bytes = text.as_bytes();
            return Err(Error::input(format!(
                "{file}: not a controller configuration file (no `…:CFG_1.0:…` header line)"
            ))
            .at(Location::from_offset(file, bytes, 0)));
        }
        let mut cfg = Cfg {
            file: file.to_string(),
            lines: split_lines(text).map(str::to_string).collect(),
            ..Cfg::default()
        };
        let mut section: Option<String> = None;
        // The instance line being joined across `\` continuations, with
        // where each joined piece came from (its line, and its offset in
        // the joined text).
        let mut pending = String::new();
        let mut pieces: Vec<(usize, usize)> = Vec::new();
        for (n, raw) in split_lines(text).enumerate() {
            let line = raw.trim_end_matches('\r');
            pieces.push((n + 1, pending.len()));
            if let Some(head) = line.strip_suffix('\\') {
                pending.push_str(head);
                pending.push(' ');
                continue;
            }
            let whole = std::mem::take(&mut pending) + line;
            let spans = std::mem::take(&mut pieces);
            let trimmed = whole.trim();
            if trimmed == "#" {
                section = None;
            } else if !whole.starts_with(char::is_whitespace)
                && trimmed.ends_with(':')
                && !trimmed.contains(char::is_whitespace)
                && !trimmed.contains("CFG_")
            {
                let name = trimmed.trim_end_matches(':').to_ascii_uppercase();
                cfg.sections.entry(name.clone()).or_default();
                section = Some(name);
            } else if trimmed.starts_with('-') {
                if let Some(name) = &section {
                    let place = |offset: usize| {
                        let &(line, start) = spans
                            .iter()
                            .rev()
                            .find(|(_, start)| *start <= offset)
                            .unwrap_or(&spans[0]);
                        let col = 1 + whole[start..offset].chars().count();
                        (line, col)
                    };
                    let inst = instance(&whole, &place);
                    cfg.sections.entry(name.clone()).or_default().push(inst);
                }
            }
        }
        Ok(cfg)
    }

    /// The instances of a section (none when the file has no such section).
    pub fn section(&self, name: &str) -> &[Instance] {
        self.sections
            .get(&name.to_ascii_uppercase())
            .map_or(&[], Vec::as_slice)
    }

    /// A place in this file, with its line's text for the caret display.
    pub fn location(&self, line: usize, col: usize) -> Location {
        Location {
            file: self.file.clone(),
            line,
            col,
            line_text: self
                .lines
                .get(line.wrapping_sub(1))
                .map_or("", |l| l.trim_end_matches('\r'))
                .into(),
        }
    }
}

/// The attributes of one (joined) instance line; `place` turns an offset
/// in it into a line and column of the file.
fn instance(line: &str, place: &dyn Fn(usize) -> (usize, usize)) -> Instance {
    let mut attributes: Vec<Attribute> = Vec::new();
    let mut chars = line.char_indices().peekable();
    let start_line = place(0).0;
    loop {
        while chars.peek().is_some_and(|(_, c)| c.is_whitespace()) {
            chars.next();
        }
        let Some((at, c)) = chars.next() else { break };
        if c == '-'
            && chars
                .peek()
                .is_some_and(|(_, c)| c.is_alphabetic() || *c == '_')
        {
            let mut key = String::new();
            while let Some(&(_, c)) = chars.peek() {
                if c.is_whitespace() {
                    break;
                }
                key.push(c);
                chars.next();
            }
            let (line, col) = place(at);
            attributes.push(Attribute {
                name: key,
                value: None,
                line,
                col,
            });
            continue;
        }
        // A value: of the attribute before it.
        let mut value = String::new();
        if c == '"' {
            for (_, c) in chars.by_ref() {
                if c == '"' {
                    break;
                }
                value.push(c);
            }
        } else {
            value.push(c);
            while let Some(&(_, c)) = chars.peek() {
                if c.is_whitespace() {
                    break;
                }
                value.push(c);
                chars.next();
            }
        }
        if let Some(slot @ Attribute { value: None, .. }) = attributes.last_mut() {
            let (line, col) = place(at);
            slot.value = Some(value);
            slot.line = line;
            slot.col = col;
        }
    }
    Instance {
        attributes,
        line: start_line,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SYS: &str = "SYS:CFG_1.0:6:0::\n#\nCAB_TASKS:\n\n      -Name \"T_ROB2\" -Type \"NORMAL\" -UseMechanicalUnitGroup \"rob2\" -MotionTask \n\n      -Name \"T_COM\" -Type \"STATIC\" -Entry \"Main\"\\\n      -TrustLevel \"None\"\n#\nMANFS_LIMIT:\n\n      -name \"LIMITFLAG\" -text_id 30,82 -mode \"0\"\n";

    #[test]
    fn reads_sections_instances_flags_and_continuations() {
        let cfg = Cfg::parse("SYS.cfg", SYS).unwrap();
        let tasks = cfg.section("cab_tasks");
        assert_eq!(tasks.len(), 2);
        assert_eq!(tasks[0].get("name"), Some("T_ROB2"));
        assert_eq!(tasks[0].get("UseMechanicalUnitGroup"), Some("rob2"));
        assert!(tasks[0].has("MotionTask"));
        assert!(!tasks[1].has("MotionTask"));
        assert_eq!(tasks[1].get("TrustLevel"), Some("None"));
        assert_eq!(cfg.section("MANFS_LIMIT")[0].get("text_id"), Some("30,82"));
        assert!(cfg.section("ROBOT").is_empty());
    }

    #[test]
    fn values_keep_their_line_and_column_across_continuations() {
        let cfg = Cfg::parse("SYS.cfg", SYS).unwrap();
        let tasks = cfg.section("cab_tasks");
        assert_eq!(tasks[0].line, 5);
        // `"T_ROB2"` starts at column 13 of line 5.
        assert_eq!(tasks[0].place("Name"), Some((5, 13)));
        // `"None"` is on the continuation line 8, column 19.
        assert_eq!(tasks[1].place("TrustLevel"), Some((8, 19)));
        let loc = cfg.location(8, 19);
        assert_eq!(&loc.line_text[18..], "\"None\"");
    }

    #[test]
    fn every_line_end_reads_the_same() {
        let lf = Cfg::parse("SYS.cfg", SYS).unwrap();
        for eol in ["\r\n", "\r"] {
            let other = Cfg::parse("SYS.cfg", &SYS.replace('\n', eol)).unwrap();
            assert_eq!(other.sections, lf.sections, "{eol:?}");
        }
    }

    #[test]
    fn a_file_without_the_header_is_not_a_configuration() {
        let e = Cfg::parse("MOC.cfg", "garbage\nROBOT:\n -name \"x\"\n").unwrap_err();
        assert!(e.to_string().contains("MOC.cfg:1:1"), "{e}");
        assert!(Cfg::parse("MOC.cfg", "").is_err());
    }
}
