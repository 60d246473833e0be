//! `rapidtherm correct --runtime`: the controller module and the program
//! rewritten to call it, written beside the output (or shown as a diff, or
//! counted); the library's `correct::runtime::job` makes them.

use super::events::EventMessages;
use super::messages;
use super::output::FileSink;
use super::unified_diff::unified_diff;
use super::write_stdout;
use super::Status;
use rapidtherm::correct::plan::{Action, Destination, RuntimePlan};
use rapidtherm::correct::runtime::job;
use rapidtherm::correct::runtime::write::{self, module_path};
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid::task::Task;
use rapidtherm::writes::Checked;

/// The uses of the flag the rest of the plan cannot see: a module name
/// RAPID reads, and somewhere to put the module.
pub fn check_module(module: &str, action: &Action) -> Result<()> {
    rapidtherm::correct::runtime::module::check_module_name(module)?;
    if *action == Action::Write(Destination::Stdout) {
        return Err(Error::usage(
            "--runtime writes a module beside the program: give -o FILE, --in-place or --diff, not standard output",
        ));
    }
    Ok(())
}

pub fn run(plan: &RuntimePlan, found: Vec<Task>, checked: &Checked) -> Result<Status> {
    let runs = job::run(plan, found, &mut EventMessages::default())?;
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
                plan.module
            ));
        }
        messages::lines(&format!(
            "{task}{} target argument(s) call {} ({} already did); {} move(s) of no robot left alone\n",
            t.wrapped, plan.module, t.already, t.left
        ));
    }
    match &plan.action {
        Action::Write(dest) => {
            let mut sink = FileSink::new(plan.action.backup(), checked);
            write::write(dest, &runs, &mut sink)?;
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
                // Only a regular file is read: a FIFO of that name would
                // block the diff for ever.
                let before = match std::fs::metadata(&path) {
                    Ok(m) if m.is_file() => std::fs::read(&path).unwrap_or_default(),
                    _ => Vec::new(),
                };
                text.extend(unified_diff(
                    &path.display().to_string(),
                    &before,
                    &r.module.1,
                ));
            }
            // The backup's list of the modules a restore loads, with them.
            for f in write::backinfo_rewrites(&runs)? {
                text.extend(unified_diff(
                    &f.path.display().to_string(),
                    &f.before,
                    &f.after,
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
