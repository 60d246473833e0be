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

mod corrected;
mod host;
mod prepare;
mod shared;
mod still;

pub use corrected::{CorrectedTask, Inputs, Streaming};
pub use host::{Event, Host, OutputFile, Sink};
pub use prepare::{checked_arm, load_model, model_label, warm_robot};
pub use shared::refuse_files_of_two_tasks;
pub use still::NO_ARM;

use super::cold_prints::ColdPrints;
use super::context::{CorrectWith, Precomputed, Prepared};
use super::plan::TimeBasis;
use super::plan::{Action, CorrectPlan, Destination};
use super::program::{correct_in_memory, correct_prepared};
use super::{Outcome, ReportRows, Writers};
use crate::error::{Error, Errors, Remedy, Result};
use crate::model::Model;
use crate::rapid::task::Task;
use crate::rapid::{self, Program, Source};
use crate::resolve::arm::base_frame;
use host::took;
use prepare::{warm_run, when_and_notes};
use std::io::Write;
use std::path::Path;

/// Run `plan` on `tasks` (those that move no robot are said and left
/// alone; where one holds moves, its targets are reported left cold). With [`Action::Write`], the corrected files are written
/// through `sink`, and kept once every task is corrected; otherwise
/// nothing is written, and each run's outputs are in its outcome.
pub fn run(
    plan: &CorrectPlan,
    tasks: Vec<Task>,
    host: &mut dyn Host,
    sink: &mut dyn Sink,
) -> Result<Vec<CorrectedTask>> {
    crate::resolve::arm::check_task_specs(&plan.arms.specs, &tasks)?;
    let model = load_model(&plan.arms.model)?;
    let (motion, still): (Vec<Task>, Vec<Task>) = tasks.into_iter().partition(moves_a_robot);
    shared::refuse_files_of_two_tasks(&motion)?;
    // One task written to files is written as it is corrected (a program of
    // a million targets is never held in memory); several tasks, or a run
    // whose results are reported, are corrected in memory first.
    let streamed = motion.len() == 1 && !plan.keep_rows && matches!(plan.action, Action::Write(_));
    let mut runs = Vec::new();
    let mut errors = Errors::default();
    for task in motion {
        let to: Option<&mut dyn Sink> = if streamed { Some(&mut *sink) } else { None };
        match correct_task(plan, &model, task, host, to) {
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
    // A task SYS.cfg says moves nothing, but which holds moves, is
    // reported with its targets left cold (after the motion tasks: a
    // single destination is the one motion task's).
    for task in still {
        let (inputs, program) = read_task(&task, host)?;
        if let Some(run) = still::still_task(task, inputs, &program, host) {
            runs.push(run);
        }
    }
    if let (Action::Write(to), false) = (&plan.action, streamed) {
        write(to, &runs, sink)?;
    }
    Ok(runs)
}

/// Whether a task moves a robot (a backup's SYS.cfg says which do not).
pub fn moves_a_robot(task: &Task) -> bool {
    task.motion != Some(false)
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
/// (the task's notes, its files, the reader's warnings) is told. A file
/// is mapped into memory, not copied.
pub fn read_task(task: &Task, host: &mut dyn Host) -> Result<(Inputs, Program)> {
    read_task_beside(task, host, |_| ()).map(|(inputs, program, _)| (inputs, program))
}

/// [`read_task`], with `beside` run on the files' bytes on a thread of
/// its own while they are parsed; its result, `None` where its thread
/// ended without one.
fn read_task_beside<T: Send>(
    task: &Task,
    host: &mut dyn Host,
    beside: impl FnOnce(&Inputs) -> T + Send,
) -> Result<(Inputs, Program, Option<T>)> {
    announce(task, host);
    let mut inputs = Vec::new();
    for f in &task.modules {
        inputs.push(read_source(f)?);
    }
    let started = std::time::Instant::now();
    let (program, made) = std::thread::scope(|scope| {
        let inputs = &inputs;
        let made = scope.spawn(move || beside(inputs));
        let program = rapid::parse_sources(inputs.clone());
        (program, made.join().ok())
    });
    let program = program?;
    took(host, "parsing", started);
    for w in &program.warnings {
        host.event(Event::Warning(w));
    }
    host.event(Event::Lane {
        task: &task.label(),
        files: &program.files,
        tally: &program.lane,
    });
    Ok((inputs, program, made))
}

/// A file's name in messages and its bytes: standard input for `-`, a
/// regular file mapped into memory, anything else (a pipe) read.
pub fn read_source(path: &Path) -> Result<(String, Source)> {
    if path != Path::new("-") && std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return Ok((path.display().to_string(), Source::new(map_file(path)?)));
    }
    let (name, bytes) = prepare::read_named(path)?;
    Ok((name, Source::new(bytes)))
}

/// The bytes of `path`, memory-mapped: a program of 100 MB is read as the
/// work needs it, not copied first.
pub fn map_file(path: &Path) -> Result<memmap2::Mmap> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, &e))?;
    // SAFETY: the map is read while the program holds it; a program being
    // rewritten by another process as it is read is outside what any
    // reader can promise (a read into memory would read a mix too).
    unsafe { memmap2::Mmap::map(&file) }.map_err(|e| Error::io(path, &e))
}

/// One task corrected: into `to`'s outputs as it goes where given (the
/// plan writes files), else in memory.
fn correct_task(
    plan: &CorrectPlan,
    model: &Model,
    task: Task,
    host: &mut dyn Host,
    to: Option<&mut dyn Sink>,
) -> Result<CorrectedTask> {
    let arm = checked_arm(&plan.arms, &task, model, host)?;
    // The files' fingerprints, for their markers, are hashed beside the
    // parse: after it, the run waited for them with a core idle.
    let (inputs, program, colds) = read_task_beside(&task, host, |inputs| {
        ColdPrints::of(inputs.iter().map(|(_, source)| source.bytes()))
    })?;
    let base = base_frame(&task)?;
    // A `--start` run walks the program on one core (another answers
    // each move's reach): what the program alone decides for the
    // correction is made beside the walk, not after it.
    let (when_notes, prepared) = std::thread::scope(|scope| {
        let beside = match &plan.when {
            TimeBasis::Start { entry, .. } => {
                let program = &program;
                Some(scope.spawn(move || Prepared::of(program, entry, base.as_ref())))
            }
            _ => None,
        };
        let when_notes = when_and_notes(plan, &program, &arm.robot, base);
        // A thread that ended without its result: made again by the run.
        (when_notes, beside.and_then(|h| h.join().ok()))
    });
    // What a thread ended without, the run makes itself.
    let (when, notes, cold_joints) = when_notes?;
    let ahead = Precomputed {
        prepared,
        colds,
        cold_joints,
    };
    for note in &notes {
        host.event(Event::Note(note));
    }
    let (arm_name, warm, options) = warm_run(plan, model, &task, arm, when, host)?;
    let started = std::time::Instant::now();
    let mut progress = |done, total| host.event(Event::Progress { done, total });
    let (outcome, streaming) = match (to, &plan.action) {
        (Some(sink), Action::Write(dest)) => {
            let with = CorrectWith::new(&warm, &options, ahead);
            let (outcome, changed) = correct_streamed(&program, with, dest, sink, &mut progress)?;
            (outcome, Streaming::Streamed { changed })
        }
        _ => (
            correct_in_memory(
                &program,
                CorrectWith::new(&warm, &options, ahead),
                &mut progress,
            )?,
            Streaming::InMemory,
        ),
    };
    let what = match streaming {
        Streaming::Streamed { .. } => "correcting and writing",
        Streaming::InMemory => "correcting",
    };
    took(host, &format!("task {}: {what}", task.label()), started);
    Ok(CorrectedTask {
        task,
        arm: arm_name,
        inputs,
        outcome,
        streaming,
    })
}

/// A program corrected straight into the sink's outputs: each file's (or
/// the one destination's) corrected bytes written as they are made, kept
/// where they change it. Unchanged, a file written in place stays as it
/// is (and gets no backup); another destination gets its bytes as they
/// are.
fn correct_streamed<'p>(
    program: &'p Program,
    with: CorrectWith<'_, 'p>,
    dest: &Destination,
    sink: &mut dyn Sink,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(Outcome, Vec<bool>)> {
    let names: Vec<String> = match dest {
        Destination::File(out) => vec![out.display().to_string()],
        Destination::Stdout => vec!["-".to_string()],
        Destination::InPlace { .. } => program.files.clone(),
    };
    let in_place = matches!(dest, Destination::InPlace { .. });
    let mut outputs = Vec::with_capacity(names.len());
    for name in &names {
        outputs.push(sink.create(name)?);
    }
    let corrected = {
        let mut buffered: Vec<std::io::BufWriter<&mut Box<dyn OutputFile>>> = outputs
            .iter_mut()
            .map(|o| std::io::BufWriter::with_capacity(1 << 20, o))
            .collect();
        let mut writers: Vec<&mut (dyn Write + Send)> = buffered
            .iter_mut()
            .map(|b| b as &mut (dyn Write + Send))
            .collect();
        let to = Writers::new(&mut writers, ReportRows::SummaryOnly);
        let c = correct_prepared(program, with, to, progress)?;
        for b in &mut buffered {
            b.flush().map_err(|e| Error::io(Path::new(&names[0]), &e))?;
        }
        c
    };
    for (f, mut out) in outputs.into_iter().enumerate() {
        let changed = corrected.changed.get(f).copied().unwrap_or(false);
        if !changed && !in_place {
            out.restart()
                .and_then(|_| out.write_all(program.source(f)))
                .map_err(|e| Error::io(Path::new(&names[f]), &e))?;
        }
        out.finish(changed || !in_place)?;
    }
    Ok((corrected.outcome, corrected.changed))
}

/// Write the runs' corrected files where the plan says.
fn write(to: &Destination, runs: &[CorrectedTask], sink: &mut dyn Sink) -> Result<()> {
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
            if after.as_slice() == before.bytes() {
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
