//! A module added to a task of a controller backup, in its
//! `BACKINFO/backinfo.txt`: a restore loads the modules that file lists
//! for each task, and only those, so a module put in a task's folder and
//! not listed is not loaded after a restore.
//!
//! The entry is written as the section's own lines are (the same form
//! after `@`, the same line ends), after the section's last system module
//! (system modules load first), and the file's bytes are otherwise kept
//! as they are (a backup written in Latin-1 stays so).

use super::backinfo;
use crate::error::decode_lossless;
use std::path::{Path, PathBuf};

/// The `backinfo.txt` of the backup that holds task folder `dir` (a
/// `TASKn` folder in the backup's `RAPID` folder), and the folder's name
/// there; `None` for a folder of no backup, or a backup without one.
pub fn backinfo_of(dir: &Path) -> Option<(PathBuf, String)> {
    let folder = dir.file_name()?.to_string_lossy().into_owned();
    let rapid = dir.parent()?;
    let is_rapid = rapid
        .file_name()
        .is_some_and(|n| n.eq_ignore_ascii_case("RAPID"));
    if !is_rapid || !super::is_task_folder_name(&folder) {
        return None;
    }
    let root = match rapid.parent() {
        Some(p) if p.as_os_str().is_empty() => Path::new("."),
        Some(p) => p,
        None => return None,
    };
    let path = super::find_ci(root, super::BackupPart::BackInfo.path())?;
    path.is_file().then_some((path, folder))
}

/// One line of the file: its bytes without, and with, its line end.
struct Line<'a> {
    text: &'a [u8],
    end: &'a [u8],
}

/// The lines of `text`, each with its own line end (`\r\n`, `\n` or `\r`
/// alone; the last may have none).
fn lines(text: &[u8]) -> Vec<Line<'_>> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut i = 0;
    while i < text.len() {
        let end = match (text[i], text.get(i + 1)) {
            (b'\r', Some(b'\n')) => 2,
            (b'\r' | b'\n', _) => 1,
            _ => {
                i += 1;
                continue;
            }
        };
        out.push(Line {
            text: &text[start..i],
            end: &text[i..i + end],
        });
        i += end;
        start = i;
    }
    if start < text.len() {
        out.push(Line {
            text: &text[start..],
            end: &[],
        });
    }
    out
}

/// A module line's path, and what follows its `@`.
fn entry(line: &[u8]) -> Option<(String, String)> {
    let text = decode_lossless(line);
    let text = text.trim();
    if text.is_empty() || text.starts_with('#') || text.starts_with(">>") {
        return None;
    }
    let (path, loaded) = text.split_once(" @").unwrap_or((text, ""));
    Some((path.trim().to_string(), loaded.to_string()))
}

fn same_path(a: &str, b: &str) -> bool {
    a.replace('\\', "/")
        .eq_ignore_ascii_case(&b.replace('\\', "/"))
}

/// `text` (a `backinfo.txt`) with `module` (its path inside the task's
/// folder, `SYSMOD/RtWarm.sys`) listed in the section of `task` (its
/// folder, `TASK1`, or its name, `T_ROB1`; any case). `None` where
/// nothing changes: the module is listed already, or no section is the
/// task's (see [`backinfo::parse`] to tell which).
pub fn with_module(text: &[u8], task: &str, module: &str) -> Option<Vec<u8>> {
    let all = lines(text);
    let listed = backinfo::parse(&decode_lossless(text));
    let header = listed
        .iter()
        .find(|t| t.folder.eq_ignore_ascii_case(task) || t.name.eq_ignore_ascii_case(task))?;
    if header.modules.iter().any(|m| same_path(m, module)) {
        return None;
    }
    // The section: from its header to the next `>>` line.
    let first = header.line; // the line after the header, 0-based
    let last = (first..all.len())
        .find(|&k| decode_lossless(all[k].text).trim_start().starts_with(">>"))
        .unwrap_or(all.len());
    let entries: Vec<(usize, String, String)> = (first..last)
        .filter_map(|k| entry(all[k].text).map(|(p, l)| (k, p, l)))
        .collect();
    let is_sys = |p: &str| {
        p.replace('\\', "/")
            .to_ascii_uppercase()
            .starts_with("SYSMOD/")
    };
    // After the last system module; else after the last module; else
    // right under the header.
    let after = (entries.iter().rev().find(|(_, p, _)| is_sys(p)))
        .or(entries.last())
        .map_or(first - 1, |(k, _, _)| *k);
    // The form of the section's lines not hidden: `@ ` and nothing, or
    // `@ name` with the file's name, as written or in lower case.
    let file = module.rsplit(['/', '\\']).next().unwrap_or(module);
    let named: Vec<(&str, &str)> = (entries.iter())
        .map(|(_, p, l)| (p.rsplit(['/', '\\']).next().unwrap_or(p), l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.eq_ignore_ascii_case("HIDDEN"))
        .collect();
    let lowered = |(theirs, l): &(&str, &str)| *l != *theirs && *l == theirs.to_ascii_lowercase();
    let loaded = if named.is_empty() {
        String::new()
    } else if named.iter().any(lowered) {
        file.to_ascii_lowercase()
    } else {
        file.to_string()
    };
    let end: &[u8] = match all.get(after).map(|l| l.end) {
        Some(e) if !e.is_empty() => e,
        _ => crate::error::line_break_of(text).as_bytes(),
    };
    let mut out = Vec::with_capacity(text.len() + module.len() + 16);
    for (k, l) in all.iter().enumerate() {
        out.extend_from_slice(l.text);
        if k == after {
            // The last line of the file may have had no line end.
            out.extend_from_slice(if l.end.is_empty() { end } else { l.end });
            out.extend_from_slice(format!("{module} @ {loaded}").as_bytes());
            out.extend_from_slice(if l.end.is_empty() { &[] } else { end });
            continue;
        }
        out.extend_from_slice(l.end);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::with_module;

    const SAMPLE: &str = ">>SYSPAR:\nSYS.cfg\n\n>>TASK1: (T_ROB1,,)\nSYSMOD/user.sys @ \nPROGMOD/MainModule.mod @ \n\n>>TASK2: (T_ROB2,,)\nSYSMOD/user.sys @ \nPROGMOD/Rob2.mod @ \n\n>>EOF:\n";

    fn added(text: &str, task: &str) -> String {
        String::from_utf8(with_module(text.as_bytes(), task, "SYSMOD/RtWarm.sys").unwrap()).unwrap()
    }

    #[test]
    fn the_entry_goes_after_the_tasks_system_modules_in_their_form() {
        let out = added(SAMPLE, "T_ROB2");
        assert_eq!(
            out,
            SAMPLE.replace(
                "SYSMOD/user.sys @ \nPROGMOD/Rob2.mod",
                "SYSMOD/user.sys @ \nSYSMOD/RtWarm.sys @ \nPROGMOD/Rob2.mod"
            )
        );
        // By folder too; the other task's section is left alone.
        let by_folder = added(SAMPLE, "task1");
        assert!(by_folder.contains(
            ">>TASK1: (T_ROB1,,)\nSYSMOD/user.sys @ \nSYSMOD/RtWarm.sys @ \nPROGMOD/MainModule.mod"
        ));
        assert!(by_folder.contains(">>TASK2: (T_ROB2,,)\nSYSMOD/user.sys @ \nPROGMOD/Rob2.mod"));
    }

    #[test]
    fn listed_once_only_and_no_section_no_change() {
        let once = added(SAMPLE, "T_ROB1");
        assert_eq!(
            with_module(once.as_bytes(), "T_ROB1", "SYSMOD/RtWarm.sys"),
            None
        );
        // Listed in another case or with a backslash: listed.
        let other = once.replace("SYSMOD/RtWarm.sys", "sysmod\\RTWARM.SYS");
        assert_eq!(
            with_module(other.as_bytes(), "T_ROB1", "SYSMOD/RtWarm.sys"),
            None
        );
        assert_eq!(
            with_module(SAMPLE.as_bytes(), "T_ROB9", "SYSMOD/RtWarm.sys"),
            None
        );
    }

    #[test]
    fn line_ends_and_the_loaded_name_follow_the_section() {
        let crlf = ">>TASK1: (T_ROB1,Cell,)\r\nSYSMOD/user.sys @ user.sys\r\nPROGMOD/Main.mod @ main.mod\r\nSYSMOD/LINKEDM.sys @ HIDDEN\r\n\r\n>>EOF:\r\n";
        let out = added(crlf, "T_ROB1");
        assert_eq!(
            out,
            ">>TASK1: (T_ROB1,Cell,)\r\nSYSMOD/user.sys @ user.sys\r\nPROGMOD/Main.mod @ main.mod\r\nSYSMOD/LINKEDM.sys @ HIDDEN\r\nSYSMOD/RtWarm.sys @ rtwarm.sys\r\n\r\n>>EOF:\r\n"
        );
        // A section that is the file's end, its last line without an end.
        let open = ">>TASK1: (T_ROB1,,)\nSYSMOD/user.sys @ ";
        assert_eq!(
            added(open, "T_ROB1"),
            ">>TASK1: (T_ROB1,,)\nSYSMOD/user.sys @ \nSYSMOD/RtWarm.sys @ "
        );
        // A section with no module yet: right under its header.
        let empty = ">>TASK1: (T_ROB1,,)\n\n>>EOF:\n";
        assert_eq!(
            added(empty, "T_ROB1"),
            ">>TASK1: (T_ROB1,,)\nSYSMOD/RtWarm.sys @ \n\n>>EOF:\n"
        );
        // Latin-1 bytes elsewhere in the file are kept as they are.
        let mut latin1 = b"# Z\xfcrich\n".to_vec();
        latin1.extend_from_slice(SAMPLE.as_bytes());
        let out = with_module(&latin1, "T_ROB1", "SYSMOD/RtWarm.sys").unwrap();
        assert!(out.starts_with(b"# Z\xfcrich\n"));
    }
}
