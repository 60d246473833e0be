//! `correct FILE -o OUT` or `--in-place` (`--at`, `--start` or
//! `--schedule`) on a program of millions of moves: the file
//! memory-mapped, its moves cut out by the
//! fast recogniser, the rest parsed whole, the corrected file written as
//! it is produced (see `docs/streaming.md`); with a schedule, the whole
//! program read from the skeleton first, to time each target. Any other
//! run, and any program the fast path declines, takes the whole-program
//! path unchanged.

use super::correct::{
    checked_arm, default_moment, estimate_options, moment, note_still, summary_text,
    warm_run_until, when_and_notes, CorrectArgs,
};
use super::messages::{self, note};
use super::output::{self, Filled};
use super::Status;
use rapidtherm::correct::stream::correct_streamed;
use rapidtherm::correct::{CutTimes, When};
use rapidtherm::error::{Error, Result};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::rapid::task::Task;
use rapidtherm::rapid::Program;
use rapidtherm::schedule::{self, CutEstimate, CutVisits};
use std::io::{Seek, Write};
use std::path::Path;
use std::thread::JoinHandle;

/// Run `correct` streamed where it applies; `None`: it does not (or the
/// fast path declined), and nothing was written or printed.
pub fn correct(
    args: &CorrectArgs,
    model: &Model,
    motion: &[Task],
    still: &[Task],
) -> Result<Option<Status>> {
    // The pictures need every target's correction, which a streamed run
    // does not keep: with --plot the whole path runs, and draws them. A
    // schedule on standard input can be read once only, and the whole
    // path must have it should the streamed run decline.
    if args.plot.is_some() || args.when.schedule.as_deref() == Some(Path::new("-")) {
        return Ok(None);
    }
    let [task] = motion else {
        return Ok(None);
    };
    let [path] = task.modules.as_slice() else {
        return Ok(None);
    };
    // `--in-place` writes the file it reads: the new file is renamed over
    // it when complete, while the old one stays mapped (on Unix, where a
    // file renamed over keeps its readers' view).
    let out = match (&args.output, args.in_place) {
        (Some(out), _) => out,
        (None, true) if cfg!(unix) => path,
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
    let estimated = args.when.at.is_none() && args.when.schedule.is_none();
    let skeleton = match estimated {
        true => rapid::fastmove::skeleton_with_poses(src),
        false => rapid::fastmove::skeleton(src),
    };
    messages::took("cutting the moves out", started);
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
    messages::took("reading the skeleton", started);
    // Anything refused here is refused again, and said, by the whole path.
    let Ok(arm) = checked_arm(args, task, model) else {
        return Ok(None);
    };
    // A schedule names the whole program's targets: the program is read
    // whole from the skeleton for it. An estimate reads it in runs of cut
    // moves, which its walk reads from the file. Either gives each cut
    // literal's moment, kept for the correction.
    let (when, notes, first, later) = match (&args.when.at, &args.when.schedule, args.when.start) {
        (Some(at), _, _) => {
            let Ok(when) = moment(at, "--at").map(When::At) else {
                return Ok(None);
            };
            (when, Vec::new(), None, 0.0)
        }
        (None, None, Some(start)) => {
            let Some(Ok(whole)) = runs else {
                return Ok(None);
            };
            let started = std::time::Instant::now();
            let (Ok(base), Ok(default)) = (super::tasks::base_frame(task), default_moment(args))
            else {
                return Ok(None);
            };
            let opts = estimate_options(args, start, base);
            let cut = (&skeleton, src);
            let Ok(Some(walked)) = schedule::estimate_cuts(&whole, cut, &arm.robot, &opts, false)
            else {
                return Ok(None);
            };
            messages::took("timing the program", started);
            let CutEstimate { estimate, literals } = walked;
            let when = When::Schedule {
                schedule: estimate.schedule,
                joints: Some(estimate.joint_schedule),
                default,
            };
            let later = literals.latest();
            (
                when,
                estimate.notes,
                Some(First::Walked(whole, literals)),
                later,
            )
        }
        _ => {
            let started = std::time::Instant::now();
            let Ok(whole) = rapid::parse_skeleton(&name, &skeleton, src) else {
                return Ok(None);
            };
            messages::took("reading the whole program from the skeleton", started);
            let Ok(base) = super::tasks::base_frame(task) else {
                return Ok(None);
            };
            let Ok((when, notes)) = when_and_notes(args, &whole, &arm.robot, base) else {
                return Ok(None);
            };
            (when, notes, Some(First::Read(whole)), 0.0)
        }
    };
    let Ok((_, warm, options)) = warm_run_until(args, model, task, arm, when, later) else {
        return Ok(None);
    };
    let times = match first {
        Some(first) => {
            let started = std::time::Instant::now();
            let t = match first {
                First::Read(whole) => {
                    let t = CutTimes::new(&whole, &program, &skeleton, &options);
                    // Not needed again; freeing the reading of a million
                    // targets takes a tenth of a second, and the run's
                    // memory was at its peak already.
                    std::mem::forget(whole);
                    t
                }
                First::Walked(whole, literals) => {
                    CutTimes::of_estimate(literals, &whole, &program, &options)
                }
            };
            let Some(t) = t else {
                return Ok(None);
            };
            messages::took("each target's moment", started);
            Some(t)
        }
        None => None,
    };
    let started = std::time::Instant::now();
    let backup = args.backup.as_deref();
    // A backup in the way is the whole path's to report, in its order (a
    // file corrected already is said first).
    if backup.is_some_and(|b| output::check_backup_free(&output::backup_path(out, b)).is_err()) {
        return Ok(None);
    }
    let streamed = output::write_atomic_with(out, backup, |file| {
        let mut sink = std::io::BufWriter::with_capacity(
            1 << 20,
            Writeback {
                file: &mut *file,
                unsynced: 0,
                syncing: None,
            },
        );
        let run = (&options, times.as_ref());
        let Some(s) = correct_streamed(&program, &skeleton, src, &warm, run, &mut sink)? else {
            return Ok(Filled::Declined);
        };
        drop(sink);
        if s.changed {
            return Ok(Filled::Written(s));
        }
        // Nothing changes: a file corrected in place stays as it is (and
        // gets no backup), as on the whole-program path; the output is the
        // file as it is.
        if args.in_place {
            return Ok(Filled::Unchanged(s));
        }
        file.set_len(0)
            .and_then(|_| file.rewind())
            .and_then(|_| file.write_all(src))
            .map_err(|e| Error::io(out, &e))?;
        Ok(Filled::Written(s))
    })?;
    let Some(streamed) = streamed else {
        return Ok(None);
    };
    messages::took("correcting and writing", started);
    // Freeing the whole reading of a million targets takes a tenth of a
    // second, and the schedules kept with it (a map and a moment per
    // target) a few hundredths more; the run ends here, and its memory was
    // at its peak already. (Declined, they are freed before the
    // whole-program path runs.)
    std::mem::forget((times, options));
    for note in &notes {
        note!("{note}");
    }
    for note in &task.notes {
        note!("{note}");
    }
    for w in &program.warnings {
        messages::warning_at(w);
    }
    note_still(still);
    messages::lines(&summary_text(&streamed.outcome));
    Ok(Some(Status::Success))
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

/// The output file, its pages sent to the disk by another thread as it
/// grows: the sync that makes the atomic write durable then finds little
/// left (for a tenth of a gigabyte it took 0.15 s after the last byte).
/// A background sync's error is the next flush's.
struct Writeback<'a> {
    file: &'a mut std::fs::File,
    unsynced: usize,
    syncing: Option<JoinHandle<std::io::Result<()>>>,
}

/// Bytes written between two background syncs.
const WRITEBACK_BYTES: usize = 16 << 20;

impl Writeback<'_> {
    /// The background sync's outcome, once it has finished.
    fn join(&mut self) -> std::io::Result<()> {
        match self.syncing.take().map(JoinHandle::join) {
            Some(Ok(result)) => result,
            Some(Err(_)) => Err(std::io::Error::other("the background sync failed")),
            None => Ok(()),
        }
    }
}

impl Write for Writeback<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.unsynced += n;
        if self.unsynced >= WRITEBACK_BYTES
            && self.syncing.as_ref().is_none_or(JoinHandle::is_finished)
        {
            self.join()?;
            let file = self.file.try_clone()?;
            self.syncing = Some(std::thread::spawn(move || file.sync_data()));
            self.unsynced = 0;
        }
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()?;
        self.join()
    }
}

impl Drop for Writeback<'_> {
    fn drop(&mut self) {
        // Not flushed: the run failed or declined, and says so itself.
        let _ = self.join();
    }
}
