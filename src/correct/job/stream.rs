//! A correction written to a file on a program of millions of moves: the
//! file memory-mapped, its moves cut out by the fast recogniser, the rest
//! parsed whole, the corrected file written as it is produced (see
//! `docs/streaming.md`); with a schedule, the whole program read from the
//! skeleton first, to time each target. Any other run, and any program
//! the fast path declines, takes the whole-program path unchanged.

use super::host::{took, Event, Host, Sink};
use super::prepare::{checked_arm, estimate_options, warm_run, when_and_notes};
use super::Ran;
use crate::correct::plan::{Action, CorrectPlan, Destination, TimeBasis};
use crate::correct::stream::correct_streamed;
use crate::correct::{CutTimes, When};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::rapid;
use crate::rapid::task::Task;
use crate::rapid::Program;
use crate::resolve::arm::base_frame;
use crate::schedule::{self, CutEstimate, CutVisits};
use std::io::Write;
use std::path::Path;

/// Run the plan streamed where it applies; `None`: it does not (or the
/// fast path declined), and nothing was written or said but what the
/// whole path says again.
pub(super) fn correct(
    plan: &CorrectPlan,
    model: &Model,
    motion: &[Task],
    host: &mut dyn Host,
    sink: &mut dyn Sink,
) -> Result<Option<Ran>> {
    // The pictures need every target's correction, which a streamed run
    // does not keep: with them the whole path runs, and draws them. A
    // schedule on standard input can be read once only, and the whole
    // path must have it should the streamed run decline.
    if plan.keep_rows || plan.when.schedule_file() == Some(Path::new("-")) {
        return Ok(None);
    }
    let [task] = motion else {
        return Ok(None);
    };
    let [path] = task.modules.as_slice() else {
        return Ok(None);
    };
    // In place, the new file is renamed over the one read when complete,
    // while the old one stays mapped (on Unix, where a file renamed over
    // keeps its readers' view).
    let (out, in_place) = match &plan.action {
        Action::Write(Destination::File(out)) => (out.as_path(), false),
        Action::Write(Destination::InPlace { .. }) if cfg!(unix) => (path.as_path(), true),
        _ => return Ok(None),
    };
    if task.name.is_some()
        || !is_plain_file(path)
        || out == Path::new("-")
        || std::fs::metadata(out).is_ok_and(|m| !m.is_file())
    {
        return Ok(None);
    }
    let map = map_file(path)?;
    let src: &[u8] = &map;
    let started = std::time::Instant::now();
    // An estimate walks the cut moves: their numbers are kept as they are
    // cut, not read a second time.
    let estimated = matches!(plan.when, TimeBasis::Start { .. });
    let skeleton = match estimated {
        true => rapid::fastmove::skeleton_with_poses(src),
        false => rapid::fastmove::skeleton(src),
    };
    took(host, "cutting the moves out", started);
    if skeleton.cuts.is_empty() {
        return Ok(None);
    }
    let name = path.display().to_string();
    // An estimate reads the skeleton twice: as it is, for the correction,
    // and with its runs of cut moves, for the walk (both on a program of
    // moves and other statements mixed).
    let started = std::time::Instant::now();
    let (program, runs) = match estimated {
        true => rayon::join(
            || rapid::parse(&name, &skeleton.bytes),
            || Some(rapid::parse_skeleton_runs(&name, &skeleton, src)),
        ),
        false => (rapid::parse(&name, &skeleton.bytes), None),
    };
    let Ok(program) = program else {
        return Ok(None);
    };
    took(host, "reading the skeleton", started);
    // Anything refused here is refused again, and said, by the whole path.
    let Ok(arm) = checked_arm(plan, task, model, host) else {
        return Ok(None);
    };
    // A schedule names the whole program's targets: the program is read
    // whole from the skeleton for it. An estimate reads it in runs of cut
    // moves, which its walk reads from the file. Either gives each cut
    // literal's moment, kept for the correction.
    let (when, notes, first, later) = match &plan.when {
        TimeBasis::At(at) => (When::At(*at), Vec::new(), None, 0.0),
        TimeBasis::Start { default, .. } => {
            let Some(Ok(whole)) = runs else {
                return Ok(None);
            };
            let started = std::time::Instant::now();
            let Ok(base) = base_frame(task) else {
                return Ok(None);
            };
            let opts = estimate_options(plan, base).unwrap_or_default();
            let cut = (&skeleton, src);
            let Ok(Some(walked)) = schedule::estimate_cuts(&whole, cut, &arm.robot, &opts, false)
            else {
                return Ok(None);
            };
            took(host, "timing the program", started);
            let CutEstimate { estimate, literals } = walked;
            let when = When::Schedule {
                schedule: estimate.schedule,
                joints: Some(estimate.joint_schedule),
                default: *default,
            };
            let later = literals.latest();
            (
                when,
                estimate.notes,
                Some(First::Walked(whole, literals)),
                later,
            )
        }
        TimeBasis::Schedule { .. } => {
            let started = std::time::Instant::now();
            let Ok(whole) = rapid::parse_skeleton(&name, &skeleton, src) else {
                return Ok(None);
            };
            took(host, "reading the whole program from the skeleton", started);
            let Ok(base) = base_frame(task) else {
                return Ok(None);
            };
            let Ok((when, notes)) = when_and_notes(plan, &whole, &arm.robot, base) else {
                return Ok(None);
            };
            (when, notes, Some(First::Read(whole)), 0.0)
        }
    };
    let Ok((arm_name, warm, options)) = warm_run(plan, model, task, arm, (when, later), host)
    else {
        return Ok(None);
    };
    let times = match first {
        Some(first) => {
            let started = std::time::Instant::now();
            let t = match first {
                First::Read(whole) => CutTimes::new(&whole, &program, &skeleton, &options),
                First::Walked(whole, literals) => {
                    CutTimes::of_estimate(literals, &whole, &program, &options)
                }
            };
            let Some(t) = t else {
                return Ok(None);
            };
            took(host, "each target's moment", started);
            Some(t)
        }
        None => None,
    };
    let started = std::time::Instant::now();
    // A backup in the way is the whole path's to report, in its order (a
    // file corrected already is said first).
    let Ok(mut output) = sink.create(&out.display().to_string()) else {
        return Ok(None);
    };
    let streamed = {
        let mut buffered = std::io::BufWriter::with_capacity(1 << 20, &mut output);
        let run = (&options, times.as_ref());
        let s = correct_streamed(&program, &skeleton, src, &warm, run, &mut buffered)?;
        buffered.flush().map_err(|e| Error::io(out, &e))?;
        s
    };
    let Some(streamed) = streamed else {
        return Ok(None);
    };
    // Nothing changes: a file corrected in place stays as it is (and gets
    // no backup), as on the whole-program path; the output is the file as
    // it is.
    if !streamed.changed && !in_place {
        output
            .restart()
            .and_then(|_| output.write_all(src))
            .map_err(|e| Error::io(out, &e))?;
    }
    output.finish(streamed.changed || !in_place)?;
    took(host, "correcting and writing", started);
    for note in &notes {
        host.event(Event::Note(note));
    }
    for note in &task.notes {
        host.event(Event::TaskNote(note));
    }
    for w in &program.warnings {
        host.event(Event::Warning(w));
    }
    Ok(Some(Ran {
        task: task.clone(),
        arm: arm_name,
        inputs: Vec::new(),
        outcome: streamed.outcome,
    }))
}

/// What the first pass of a scheduled run read: the whole program from
/// the skeleton (for a schedule file), or the skeleton in runs and its
/// estimate's cut literals.
enum First {
    Read(Program),
    Walked(Program, CutVisits),
}

/// A file by name, not standard input, a folder or a device.
pub fn is_plain_file(p: &Path) -> bool {
    p != Path::new("-") && std::fs::metadata(p).is_ok_and(|m| m.is_file())
}

/// The bytes of `path`, memory-mapped: a program of 100 MB is read as the
/// work needs it, not copied first.
pub fn map_file(path: &Path) -> Result<memmap2::Mmap> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, &e))?;
    // SAFETY: the map is read while this run holds it; a program being
    // rewritten by another process as it is read is outside what any
    // reader can promise (the whole-program path would read a mix too).
    unsafe { memmap2::Mmap::map(&file) }.map_err(|e| Error::io(path, &e))
}
