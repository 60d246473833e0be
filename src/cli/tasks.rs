//! What the command line names, as tasks: files one by one, program files
//! (`.pgf`), task folders and whole controller backups
//! (`rapidtherm::rapid::task`), `--task` to pick some, and the outputs of
//! several tasks joined into one.

use super::Inputs;
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid::task::{self, Task};
use rapidtherm::rapid::Program;
use std::path::{Path, PathBuf};

/// `--task` as the command line takes it.
#[derive(clap::Args, Debug, Clone, Default)]
// The group keeps the name it had when this struct was the pick itself.
#[group(id = "TaskPick")]
pub struct TaskArgs {
    /// With a controller backup, task folders or program files: only this
    /// task (its controller name, e.g. T_ROB1, or its folder, e.g. TASK1);
    /// may be given several times. Default: every task.
    #[arg(long = "task", value_name = "NAME")]
    pub tasks: Vec<String>,
}

/// The tasks of a backup (or of several task folders) to work on, as a
/// plan keeps them: every task when empty.
#[derive(Debug, Clone, Default)]
pub struct TaskPick {
    pub tasks: Vec<String>,
}

impl From<TaskArgs> for TaskPick {
    fn from(a: TaskArgs) -> TaskPick {
        TaskPick { tasks: a.tasks }
    }
}

/// The tasks `paths` stand for, narrowed to those `pick` names.
pub fn select(paths: &[PathBuf], pick: &TaskPick) -> Result<Vec<Task>> {
    let all = task::discover(paths)?;
    if pick.tasks.is_empty() {
        return Ok(all);
    }
    let named = |t: &Task, want: &str| {
        t.name
            .as_deref()
            .is_some_and(|n| n.eq_ignore_ascii_case(want))
            || t.origin
                .as_deref()
                .and_then(Path::file_name)
                .is_some_and(|f| f.to_string_lossy().eq_ignore_ascii_case(want))
    };
    for want in &pick.tasks {
        if !all.iter().any(|t| named(t, want)) {
            let names: Vec<String> = all.iter().map(Task::label).collect();
            return Err(Error::usage(format!(
                "--task {want}: no such task here (tasks: {})",
                names.join(", ")
            )));
        }
    }
    Ok(all
        .into_iter()
        .filter(|t| pick.tasks.iter().any(|w| named(t, w)))
        .collect())
}

/// Read a task's modules and parse them as one program; the reader's
/// warnings and the task's notes go to stderr.
pub fn read(task: &Task) -> Result<(Inputs, Program)> {
    rapidtherm::correct::job::read_task(task, &mut super::events::EventMessages::default())
}

/// Renderings of several tasks as one output: as it is when `labels` is
/// `None` (files given one by one: one unnamed task); otherwise a heading
/// before each table, a leading `task` column in CSV, and in JSON one
/// document whose `tasks` are `{"task": …, <the task's own fields>}`
/// (plus `extra` fields per task).
pub fn join(
    format: super::Format,
    labels: Option<&[String]>,
    texts: Vec<String>,
    extra: &[Vec<(&str, String)>],
) -> Result<String> {
    let Some(labels) = labels else {
        // One text (a listing of a million targets is 150 MB): as it is,
        // not copied.
        if texts.len() == 1 {
            return Ok(texts.into_iter().next().unwrap_or_default());
        }
        return Ok(texts.concat());
    };
    let mut out = String::new();
    match format {
        super::Format::Table => {
            for (label, text) in labels.iter().zip(&texts) {
                out.push_str(&format!("task {label}:\n{text}"));
            }
        }
        super::Format::Csv => {
            let mut header_done = false;
            for (label, text) in labels.iter().zip(&texts) {
                for (n, line) in text.lines().enumerate() {
                    if n == 0 {
                        if !header_done {
                            out.push_str(&format!("task,{line}\n"));
                            header_done = true;
                        }
                    } else {
                        out.push_str(&format!("{label},{line}\n"));
                    }
                }
            }
        }
        super::Format::Json => {
            // Each task's document (`{"schema": …, fields}`) becomes an
            // entry of `tasks`, its fields beside the task's name, under
            // the one schema of the command.
            let mut all = Vec::new();
            let mut schema = None;
            for (k, (label, text)) in labels.iter().zip(&texts).enumerate() {
                let value: serde_json::Value =
                    serde_json::from_str(text).map_err(|e| Error::input(e.to_string()))?;
                let serde_json::Value::Object(mut fields) = value else {
                    return Err(Error::input(format!(
                        "the JSON of task {label} is no object"
                    )));
                };
                let command = fields
                    .remove("schema")
                    .and_then(|s| s.as_str().map(str::to_string));
                let mut entry = serde_json::Map::new();
                entry.insert("task".into(), label.clone().into());
                for (name, v) in extra.get(k).into_iter().flatten() {
                    entry.insert((*name).into(), v.clone().into());
                }
                entry.append(&mut fields);
                all.push(serde_json::Value::Object(entry));
                schema = schema.or(command);
            }
            let doc = serde_json::json!({
                "schema": schema.unwrap_or_default(),
                "tasks": all,
            });
            out = rapidtherm::report::json::to_string(&doc)? + "\n";
        }
    }
    Ok(out)
}

/// The labels of tasks when they are named (a backup, task folders,
/// program files), `None` for files given one by one.
pub fn labels(tasks: &[&Task]) -> Option<Vec<String>> {
    (tasks.len() > 1 || tasks.iter().any(|t| t.name.is_some()))
        .then(|| tasks.iter().map(|t| t.label()).collect())
}

/// The one motion task a command that times a single robot works on.
pub fn one_motion_task(paths: &[PathBuf], pick: &TaskPick, command: &str) -> Result<Task> {
    let mut motion: Vec<Task> = select(paths, pick)?
        .into_iter()
        .filter(|t| t.motion != Some(false))
        .collect();
    match motion.len() {
        1 => Ok(motion.remove(0)),
        0 => Err(Error::usage(format!(
            "{command}: no motion task here (SYSPAR/SYS.cfg marks none)"
        ))),
        _ => {
            let names: Vec<String> = motion.iter().map(Task::label).collect();
            Err(Error::usage(format!(
                "{command} times one robot: pick one of the motion tasks {} with --task",
                names.join(", ")
            )))
        }
    }
}
