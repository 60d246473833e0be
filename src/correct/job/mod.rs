//! The main job: a planned correction ([`CorrectPlan`]) run on the tasks
//! the user named. Each task is prepared (its arm, its files read, when
//! its targets are reached, the warm robot), corrected, and its corrected
//! files written through the caller's [`Sink`]; what happens on the way
//! is told to the caller's [`Host`]. The caller renders the reports
//! (per-target rows, the check's findings, diffs) from what [`run`]
//! returns.
//!
//! Every task is tried before anything is written, so that a run reports
//! all its errors and a refused task leaves every file as it was.

mod host;
mod prepare;
mod ran;
mod stream;

pub use host::{Event, Host, Output, Sink};
pub use prepare::load_model;
pub use ran::{Inputs, Ran};
pub use stream::{is_plain_file, map_file};

use super::correct;
use super::plan::{Action, CorrectPlan, Destination};
use crate::error::{Error, Errors, Remedy, Result};
use crate::model::Model;
use crate::rapid::task::Task;
use crate::rapid::{self, Program};
use crate::resolve::arm::base_frame;
use host::took;
use prepare::{checked_arm, warm_run, when_and_notes};
use std::io::Write;

/// Run `plan` on `tasks` (those that move no robot are said and left
/// alone). With [`Action::Write`], the corrected files are written
/// through `sink`, and kept once every task is corrected; otherwise
/// nothing is written, and each run's outputs are in its outcome.
pub fn run(
    plan: &CorrectPlan,
    tasks: Vec<Task>,
    host: &mut dyn Host,
    sink: &mut dyn Sink,
) -> Result<Vec<Ran>> {
    let model = load_model(&plan.model)?;
    let (motion, still): (Vec<Task>, Vec<Task>) = tasks.into_iter().partition(moves_a_robot);
    if let Some(ran) = stream::correct(plan, &model, &motion, host, sink)? {
        say_still(&still, host);
        return Ok(vec![ran]);
    }
    let mut runs = Vec::new();
    let mut errors = Errors::default();
    for task in motion {
        match correct_task(plan, &model, task, host) {
            Ok(run) => runs.push(run),
            Err(e) => errors.push(e),
        }
    }
    if let Some(e) = errors.into_error(|n| {
        Error::input(format!(
            "{n} tasks cannot be corrected; nothing was written"
        ))
    }) {
        return Err(e);
    }
    say_still(&still, host);
    if let Action::Write(to) = &plan.action {
        write(to, &runs, sink)?;
    }
    Ok(runs)
}

/// Whether a task moves a robot (a backup's SYS.cfg says which do not).
pub fn moves_a_robot(task: &Task) -> bool {
    task.motion != Some(false)
}

/// Tasks that move no robot are named and left alone.
fn say_still(still: &[Task], host: &mut dyn Host) {
    for t in still {
        host.event(Event::NotMotion { task: &t.label() });
    }
}

/// What reading a task says before it reads: its notes, and its files.
pub fn announce(task: &Task, host: &mut dyn Host) {
    for note in &task.notes {
        host.event(Event::TaskNote(note));
    }
    host.event(Event::Reads {
        task: &task.label(),
        files: &task.modules,
    });
}

/// Read a task's modules and parse them as one program; what reading says
/// (the task's notes, its files, the reader's warnings) is told.
pub fn read_task(task: &Task, host: &mut dyn Host) -> Result<(Inputs, Program)> {
    announce(task, host);
    let mut inputs = Vec::new();
    for f in &task.modules {
        inputs.push(prepare::read_named(f)?);
    }
    let refs: Vec<(&str, &[u8])> = inputs
        .iter()
        .map(|(n, b)| (n.as_str(), b.as_slice()))
        .collect();
    let started = std::time::Instant::now();
    let program = rapid::parse_files(&refs)?;
    took(host, "parsing", started);
    for w in &program.warnings {
        host.event(Event::Warning(w));
    }
    Ok((inputs, program))
}

/// One task corrected on the whole-program path.
fn correct_task(plan: &CorrectPlan, model: &Model, task: Task, host: &mut dyn Host) -> Result<Ran> {
    let arm = checked_arm(plan, &task, model, host)?;
    let (inputs, program) = read_task(&task, host)?;
    let (when, notes) = when_and_notes(plan, &program, &arm.robot, base_frame(&task)?)?;
    for note in &notes {
        host.event(Event::Note(note));
    }
    let (arm_name, warm, options) = warm_run(plan, model, &task, arm, (when, 0.0), host)?;
    let started = std::time::Instant::now();
    let outcome = correct(&program, &warm, &options, &mut |done, total| {
        host.event(Event::Progress { done, total })
    })?;
    took(host, &format!("task {}: correcting", task.label()), started);
    Ok(Ran {
        task,
        arm: arm_name,
        inputs,
        outcome,
    })
}

/// Write the runs' corrected files where the plan says.
fn write(to: &Destination, runs: &[Ran], sink: &mut dyn Sink) -> Result<()> {
    let mut writes: Vec<(&String, &Vec<u8>)> = Vec::new();
    match to {
        Destination::File(out) => {
            let mut o = sink.create(&out.display().to_string())?;
            o.write_all(&runs[0].outcome.outputs[0])
                .map_err(|e| Error::io(out, &e))?;
            return o.finish(true);
        }
        Destination::Stdout => {
            let mut o = sink.create("-")?;
            o.write_all(&runs[0].outcome.outputs[0])
                .map_err(|e| Error::io(std::path::Path::new("<stdout>"), &e))?;
            return o.finish(true);
        }
        Destination::InPlace { .. } => {}
    }
    for r in runs {
        for ((name, before), after) in r.inputs.iter().zip(&r.outcome.outputs) {
            if after == before {
                continue;
            }
            // One file read in two tasks (a shared module named twice)
            // must not be corrected twice over.
            if writes.iter().any(|(n, a)| *n == name && *a != after) {
                return Err(Error::input(format!(
                    "{name} is read in two tasks that would correct it differently; correct one task at a time"
                ))
                .with_remedy(Remedy::OneTaskAtATime));
            }
            writes.push((name, after));
        }
    }
    // Every output is made (its backup checked) before any is kept: a
    // refused backup leaves the whole program as it was.
    let mut outputs = Vec::new();
    for (name, after) in &writes {
        let mut o = sink.create(name)?;
        o.write_all(after)
            .map_err(|e| Error::io(std::path::Path::new(name.as_str()), &e))?;
        outputs.push(o);
    }
    for o in outputs {
        o.finish(true)?;
    }
    Ok(())
}
