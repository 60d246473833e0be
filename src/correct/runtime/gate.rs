//! `correct --runtime --check`: the gate a CI runs on a program rewritten
//! for the controller. It passes when every move's target argument calls
//! the module, the program is as the rewrite left it, and the module
//! beside it is the one this version writes for it under this model;
//! each thing missing or stale is a finding (exit 1), never a refusal.
//!
//! The module is compared with the one written from the program's cold
//! original (its table numbers the cold program's targets), its `PERS`
//! lines aside: the controller writes the heating state back into them
//! when it saves the module (docs/runtime.md).

use super::job::{basis, made};
use super::rewrite::{move_insertions, Route};
use crate::correct::job::{load_model, moves_a_robot, read_task, Host};
use crate::correct::marker;
use crate::correct::plan::RuntimePlan;
use crate::error::Result;
use crate::rapid::task::Task;

/// One thing the gate found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GateFinding {
    /// The task's label.
    pub task: String,
    pub what: String,
}

/// What the gate finds on each task that moves a robot.
pub fn gate(plan: &RuntimePlan, tasks: Vec<Task>, host: &mut dyn Host) -> Result<Vec<GateFinding>> {
    crate::resolve::arm::check_task_specs(&plan.arms.specs, &tasks)?;
    let model = load_model(&plan.arms.model)?;
    let mut out = Vec::new();
    for task in tasks.iter().filter(|t| moves_a_robot(t)) {
        for what in gate_task(plan, &model, task, host)? {
            out.push(GateFinding {
                task: task.label(),
                what,
            });
        }
    }
    Ok(out)
}

fn gate_task(
    plan: &RuntimePlan,
    model: &crate::model::Model,
    task: &Task,
    host: &mut dyn Host,
) -> Result<Vec<String>> {
    let module = plan.module.as_str();
    let made = made(plan, model, task, host)?;
    let (_, program) = read_task(task, host)?;
    if let Some(u) = marker::untrusted(&program) {
        return Ok(vec![marker::refuse_untrusted(&program, &u).message]);
    }
    let Some(found) = marker::find(&program) else {
        return Ok(vec![format!(
            "not rewritten for the controller: `correct --runtime --runtime-module {module}` has not run on it"
        )]);
    };
    let wanted = marker::for_run(&basis(module), &made.label, false, b"");
    if !found.marker.same_correction(&wanted) {
        return Ok(vec![marker::refuse(&program, &found, &wanted).message]);
    }
    let mut findings = Vec::new();
    let (_, tally) = move_insertions(&program, module, &mut |_, _| Route::Slow);
    if tally.wrapped > 0 {
        findings.push(format!(
            "{} target argument(s) of moves do not call {module} (moves added since the rewrite): rewrite the cold original",
            tally.wrapped
        ));
    }
    let file = super::module::module_file(module);
    let Some(first) = task.modules.first() else {
        return Ok(findings);
    };
    let path = super::write::module_path(first, &file);
    // The cold original cannot be given back where the file was edited
    // since: said, and no module to compare with.
    let want = match made.module_of_rewritten(&program) {
        Ok(want) => want,
        Err(e) => {
            findings.push(e.message);
            return Ok(findings);
        }
    };
    match std::fs::read(&path) {
        Err(_) => findings.push(format!(
            "{}: the module is missing: the rewritten program calls {module}, which the controller will not find",
            path.display()
        )),
        Ok(have) if !same_module(&have, &want) => findings.push(format!(
            "{}: not the module rapidtherm {} writes for this program and model (another version, model or arm, or edited): write it again with `correct --runtime`",
            path.display(),
            env!("CARGO_PKG_VERSION")
        )),
        Ok(_) => {}
    }
    Ok(findings)
}

/// Whether two module texts are the same but for their `PERS` lines (the
/// state the controller writes back) and line ends.
pub fn same_module(a: &[u8], b: &[u8]) -> bool {
    let lines = |t: &[u8]| -> Vec<Vec<u8>> {
        t.split(|&c| c == b'\n')
            .map(|l| l.strip_suffix(b"\r").unwrap_or(l).to_vec())
            .filter(|l| {
                let t = l.trim_ascii_start();
                !(t.len() >= 10 && t[..10].eq_ignore_ascii_case(b"LOCAL PERS"))
            })
            .collect()
    };
    lines(a) == lines(b)
}
