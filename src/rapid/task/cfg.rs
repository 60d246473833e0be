//! ABB's configuration files (`SYSPAR/*.cfg`): what a backup says about its
//! tasks and robots.
//!
//! The format (RobotWare's "CFG_1.0"): a header line `SYS:CFG_1.0:6:0::`,
//! then sections. A section starts with a line `NAME:` in the first column
//! and ends with a line `#`. Each instance of a section is one line of
//! `-Attribute value` pairs (a bare `-Attribute` is a flag), continued on
//! the next line after a trailing `\`. Values are quoted strings, numbers
//! or comma lists. Only what rapidtherm reads is interpreted; everything
//! else is kept as text.

use std::collections::BTreeMap;

/// One instance: its attributes by lower-case name, in file order. A flag
/// has the value `None`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Instance {
    pub attributes: Vec<(String, Option<String>)>,
}

impl Instance {
    /// The value of an attribute (names compare case-insensitively, as the
    /// controller's do: `-Name` and `-name` both occur).
    pub fn get(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(name))
            .and_then(|(_, v)| v.as_deref())
    }

    /// True when the attribute is present, as a flag or with a value.
    pub fn has(&self, name: &str) -> bool {
        self.attributes
            .iter()
            .any(|(k, _)| k.eq_ignore_ascii_case(name))
    }
}

/// A whole configuration file: the instances of each section, by
/// upper-case section name.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cfg {
    pub sections: BTreeMap<String, Vec<Instance>>,
}

impl Cfg {
    /// Read a configuration file's text. The format has no errors worth
    /// stopping for: a line that is not understood is skipped, so that a
    /// backup of a newer RobotWare still gives what this reader knows.
    pub fn parse(text: &str) -> Cfg {
        let mut cfg = Cfg::default();
        let mut section: Option<String> = None;
        let mut pending = String::new();
        for raw in text.lines() {
            let line = raw.trim_end_matches('\r');
            if let Some(head) = line.strip_suffix('\\') {
                pending.push_str(head);
                pending.push(' ');
                continue;
            }
            let whole = std::mem::take(&mut pending) + line;
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
                    cfg.sections
                        .entry(name.clone())
                        .or_default()
                        .push(instance(trimmed));
                }
            }
        }
        cfg
    }

    /// The instances of a section (none when the file has no such section).
    pub fn section(&self, name: &str) -> &[Instance] {
        self.sections
            .get(&name.to_ascii_uppercase())
            .map_or(&[], Vec::as_slice)
    }
}

/// The attributes of one instance line.
fn instance(line: &str) -> Instance {
    let mut attributes: Vec<(String, Option<String>)> = Vec::new();
    let mut chars = line.chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| c.is_whitespace()) {
            chars.next();
        }
        let Some(c) = chars.next() else { break };
        if c == '-' && chars.peek().is_some_and(|c| c.is_alphabetic() || *c == '_') {
            let mut key = String::new();
            while let Some(&c) = chars.peek() {
                if c.is_whitespace() {
                    break;
                }
                key.push(c);
                chars.next();
            }
            attributes.push((key, None));
            continue;
        }
        // A value: of the attribute before it.
        let mut value = String::new();
        if c == '"' {
            for c in chars.by_ref() {
                if c == '"' {
                    break;
                }
                value.push(c);
            }
        } else {
            value.push(c);
            while let Some(&c) = chars.peek() {
                if c.is_whitespace() {
                    break;
                }
                value.push(c);
                chars.next();
            }
        }
        if let Some((_, slot @ None)) = attributes.last_mut() {
            *slot = Some(value);
        }
    }
    Instance { attributes }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SYS: &str = "SYS:CFG_1.0:6:0::\n#\nCAB_TASKS:\n\n      -Name \"T_ROB2\" -Type \"NORMAL\" -UseMechanicalUnitGroup \"rob2\" -MotionTask \n\n      -Name \"T_COM\" -Type \"STATIC\" -Entry \"Main\"\\\n      -TrustLevel \"None\"\n#\nMANFS_LIMIT:\n\n      -name \"LIMITFLAG\" -text_id 30,82 -mode \"0\"\n";

    #[test]
    fn reads_sections_instances_flags_and_continuations() {
        let cfg = Cfg::parse(SYS);
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
}
