//! `correct --plot DIR`: the pictures of a correction written as SVG files
//! (the library draws them, `rapidtherm::correct::plot`). The folder is
//! checked before the run, the pictures drawn before anything else is
//! written, and written last: a run that fails leaves the folder as it
//! was.

use super::output::write_atomic;
use super::Inputs;
use rapidtherm::correct::plot::{pictures, Picture};
use rapidtherm::correct::Outcome;
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid::task::Task;
use rapidtherm::writes::Checked;
use std::path::{Path, PathBuf};

/// A `--plot` folder that exists must be a folder.
pub fn check_dir(dir: Option<&Path>) -> Result<()> {
    let Some(dir) = dir else { return Ok(()) };
    match std::fs::metadata(dir) {
        Ok(meta) if !meta.is_dir() => Err(Error::usage(format!(
            "--plot {}: not a folder (the pictures are written into a folder, created if missing)",
            dir.display()
        ))),
        // To be made: its nearest existing folder must be one, checked
        // before the run writes anything else.
        _ => super::output::check_folder("--plot", dir),
    }
}

/// The files [`draw`] names for the motion tasks of a run, known before
/// they are read.
pub fn names(tasks: &[&Task]) -> Vec<PathBuf> {
    let named = tasks.len() > 1 || tasks.iter().any(|t| t.name.is_some());
    let mut out = Vec::new();
    for task in tasks {
        for name in rapidtherm::correct::plot::FILES {
            out.push(file_of(named, task, name));
        }
    }
    out
}

/// A picture's file: with tasks named, the task's name in front.
fn file_of(named: bool, task: &Task, name: &str) -> PathBuf {
    if named {
        PathBuf::from(format!("{}-{name}", file_safe(&task.label())))
    } else {
        PathBuf::from(name)
    }
}

/// The pictures of every task (its files as read, its outcome), by file
/// name in the folder: `top.svg`, `side.svg`, `drift.svg`; with tasks
/// named (a backup) each task's name in front (`T_ROB1-top.svg`). None
/// without `--plot`.
pub fn draw(
    dir: Option<&Path>,
    runs: &[(&Task, &Inputs, &Outcome)],
) -> Result<Vec<(PathBuf, String)>> {
    if dir.is_none() {
        return Ok(Vec::new());
    }
    let named = runs.len() > 1 || runs.iter().any(|(t, _, _)| t.name.is_some());
    let mut out = Vec::new();
    for (task, inputs, outcome) in runs {
        let title = if named {
            format!("task {}", task.label())
        } else {
            let files: Vec<String> = inputs
                .iter()
                .map(|(name, _)| file_name(name).to_string())
                .collect();
            files.join(", ")
        };
        for Picture { name, svg } in pictures(outcome, &title)? {
            out.push((file_of(named, task, name), svg));
        }
    }
    Ok(out)
}

fn file_name(path: &str) -> &str {
    Path::new(path)
        .file_name()
        .and_then(|f| f.to_str())
        .unwrap_or(path)
}

/// Write the pictures into `dir` (created if missing), each atomically,
/// as the checked plan has them.
pub fn write(checked: &Checked, dir: Option<&Path>, drawn: &[(PathBuf, String)]) -> Result<()> {
    let Some(dir) = dir else { return Ok(()) };
    super::output::check_folder("--plot", dir)?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, &e))?;
    for (name, svg) in drawn {
        let path = dir.join(name);
        write_atomic(checked, &path, svg.as_bytes(), None)?;
    }
    Ok(())
}

/// A task label as part of a file name: its last path part, with anything
/// but letters, digits, `_`, `-` and `.` made `_`.
fn file_safe(label: &str) -> String {
    file_name(label)
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect()
}
