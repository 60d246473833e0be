//! `rapidtherm correct --runtime`: the controller module and the program
//! rewritten to call it, written beside the output (or shown as a diff, or
//! counted); the library's `correct::runtime::job` makes them.

use super::events::Said;
use super::messages;
use super::output::FileSink;
use super::unified_diff::unified_diff;
use super::write_stdout;
use super::Status;
use rapidtherm::correct::job::Sink;
use rapidtherm::correct::plan::{Action, CorrectPlan, Destination};
use rapidtherm::correct::runtime::job::{self, RuntimeRan};
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid::task::Task;
use std::io::Write;
use std::path::{Path, PathBuf};

/// What `--runtime` reads of `correct`'s arguments.
pub struct RuntimeArgs<'a> {
    /// The module's name.
    pub module: &'a str,
    pub output: Option<&'a Path>,
    pub backup: Option<String>,
}

/// The uses of the flag the plan cannot see: a module name RAPID reads,
/// and somewhere to put the module.
pub fn check_args(args: &RuntimeArgs) -> Result<()> {
    let name = args.module;
    let ok = name.len() <= 31
        && name.bytes().next().is_some_and(|b| b.is_ascii_alphabetic())
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
    if !ok {
        return Err(Error::usage(format!(
            "--runtime-module `{name}`: a RAPID name (a letter, then letters, digits or _; at most 31, its jointtarget function adds a J)"
        )));
    }
    if args.output == Some(Path::new("-")) {
        return Err(Error::usage(
            "--runtime writes a module beside the program: give -o FILE, --in-place or --diff, not standard output",
        ));
    }
    Ok(())
}

pub fn run(args: &RuntimeArgs, plan: &CorrectPlan, found: Vec<Task>) -> Result<Status> {
    let runs = job::run(plan, args.module, found, &mut Said::default())?;
    for r in &runs {
        let t = &r.tally;
        let task = if runs.len() > 1 || r.task.name.is_some() {
            format!("task {}: ", r.task.label())
        } else {
            String::new()
        };
        if r.already {
            messages::lines(&format!(
                "{task}already rewritten for {}; nothing to do\n",
                args.module
            ));
        }
        messages::lines(&format!(
            "{task}{} target argument(s) call {} ({} already did); {} move(s) of no robot left alone\n",
            t.wrapped, args.module, t.already, t.left
        ));
    }
    match &plan.action {
        Action::Write(dest) => {
            let mut sink = FileSink::new(args.backup.clone());
            write(dest, &runs, &mut sink)?;
            sink.commit()?;
            Ok(Status::Success)
        }
        Action::Diff { .. } => {
            let mut text = Vec::new();
            for r in &runs {
                for (f, (name, before)) in r.inputs.iter().enumerate() {
                    text.extend(unified_diff(name, before.bytes(), &r.file_bytes(f)));
                }
                let path = module_path(&r.task.modules[0], &r.module.0);
                let before = std::fs::read(&path).unwrap_or_default();
                text.extend(unified_diff(
                    &path.display().to_string(),
                    &before,
                    &r.module.1,
                ));
            }
            let changed = !text.is_empty();
            write_stdout(&text)?;
            Ok(if changed {
                Status::Changes
            } else {
                Status::Success
            })
        }
        Action::Check(_) | Action::Report => Ok(Status::Success),
    }
}

fn module_path(program: &Path, file: &str) -> PathBuf {
    RuntimeRan::module_dir(program).join(file)
}

/// The programs where the plan says, and each task's module beside them
/// (one module per folder: two tasks of one folder that need different
/// modules are refused).
fn write(dest: &Destination, runs: &[RuntimeRan], sink: &mut FileSink) -> Result<()> {
    let mut modules: Vec<(PathBuf, &[u8])> = Vec::new();
    for r in runs {
        let beside = match dest {
            Destination::File(out) => out.clone(),
            _ => r.task.modules[0].clone(),
        };
        let path = module_path(&beside, &r.module.0);
        if let Some((_, other)) = modules.iter().find(|(p, _)| *p == path) {
            if *other != r.module.1.as_slice() {
                return Err(Error::usage(format!(
                    "{}: two tasks of one folder need different modules (different arms); rewrite one task at a time",
                    path.display()
                )));
            }
            continue;
        }
        modules.push((path, &r.module.1));
    }
    let mut outputs = Vec::new();
    let put = |sink: &mut FileSink, name: &str, bytes: &[u8]| -> Result<_> {
        let mut o = sink.create(name)?;
        o.write_all(bytes)
            .map_err(|e| Error::io(Path::new(name), &e))?;
        Ok(o)
    };
    // A program file written as the rewrite makes it, through a buffer.
    let put_file = |sink: &mut FileSink, name: &str, r: &RuntimeRan, f: usize| -> Result<_> {
        let mut o = sink.create(name)?;
        let mut buffered = std::io::BufWriter::with_capacity(1 << 20, &mut o);
        r.write_file(f, &mut buffered)
            .and_then(|_| buffered.flush())
            .map_err(|e| Error::io(Path::new(name), &e))?;
        drop(buffered);
        Ok(o)
    };
    match dest {
        Destination::File(out) => {
            outputs.push(put_file(sink, &out.display().to_string(), &runs[0], 0)?);
        }
        Destination::Stdout => {
            return Err(Error::usage("--runtime cannot write to standard output"))
        }
        Destination::InPlace { .. } => {
            for r in runs {
                for (f, (name, _)) in r.inputs.iter().enumerate() {
                    if r.file_changed(f) {
                        outputs.push(put_file(sink, name, r, f)?);
                    }
                }
            }
        }
    }
    for (path, bytes) in &modules {
        // A module as it already is stays untouched (and gets no backup).
        if std::fs::read(path).is_ok_and(|b| b == *bytes) {
            continue;
        }
        outputs.push(put(sink, &path.display().to_string(), bytes)?);
    }
    for o in outputs {
        o.finish(true)?;
    }
    Ok(())
}
