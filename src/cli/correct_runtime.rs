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
    rapidtherm::correct::runtime::names::check_module_name(module)?;
    if *action == Action::Write(Destination::Stdout) {
        return Err(Error::usage(
            "--runtime writes a module beside the program: give -o FILE, --in-place or --diff, not standard output",
        ));
    }
    Ok(())
}

pub fn run(plan: &RuntimePlan, found: Vec<Task>, checked: &Checked) -> Result<Status> {
    if let Action::Check(_) = plan.action {
        return gate(plan, found);
    }
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
            "{task}{} target argument(s) call {} ({} already did): {} by the module's table, {} by its slower path (the controller's CalcJointT: targets made or indexed at run time); {} move(s) of no robot left alone\n",
            t.wrapped,
            plan.module,
            t.already,
            t.table,
            t.wrapped - t.table,
            t.left
        ));
        for u in &t.unwrapped {
            let file = r.inputs.get(u.file).map_or("", |(n, _)| n.as_str());
            messages::lines(&format!(
                "{task}{file}:{}:{}: left as written: {}\n",
                u.line, u.col, u.reason
            ));
        }
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

/// `--runtime --check`: each finding a line on standard output (`task:
/// what` where the run has several tasks or a named one), the verdict on
/// standard error; exit 1 when anything is found.
fn gate(plan: &RuntimePlan, found: Vec<Task>) -> Result<Status> {
    let named = found.len() > 1 || found.iter().any(|t| t.name.is_some());
    let findings =
        rapidtherm::correct::runtime::gate::gate(plan, found, &mut EventMessages::default())?;
    let mut text = String::new();
    for f in &findings {
        if named {
            text.push_str(&format!("task {}: ", f.task));
        }
        text.push_str(&f.what);
        text.push('\n');
    }
    write_stdout(text.as_bytes())?;
    if findings.is_empty() {
        messages::lines(&format!(
            "check: every move calls {} and the module beside is the one this version writes\n",
            plan.module
        ));
        Ok(Status::Success)
    } else {
        messages::lines(&format!(
            "check: {} finding(s) for the controller module {}\n",
            findings.len(),
            plan.module
        ));
        Ok(Status::Changes)
    }
}
