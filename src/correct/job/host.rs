//! What a job needs of its caller: someone to tell what happens
//! ([`Host`], which words each [`Event`] as it likes) and somewhere to
//! write the corrected files ([`Sink`]). The library writes no file and
//! prints nothing itself.

use crate::error::Result;
use crate::rapid::{LaneTally, Warning};
use crate::resolve::arm::TaskArm;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Something a job has to say, as data.
#[derive(Debug)]
pub enum Event<'a> {
    /// What reading a task's backup noticed (a module listed but missing).
    TaskNote(&'a str),
    /// The files a task reads.
    Reads { task: &'a str, files: &'a [PathBuf] },
    /// The arm a task moves, and what chose it; `not_a_backup`: the
    /// folder that would have been the task's backup but holds neither
    /// BACKINFO nor SYSPAR (`Task::not_a_backup`), so that an arm taken by
    /// default can be said to be no backup's.
    Arm {
        task: &'a str,
        arm: &'a TaskArm,
        not_a_backup: Option<&'a Path>,
    },
    /// A remark of the reader on the input, at its place.
    Warning(&'a Warning),
    /// What the parse's fast lane began to read and left to the grammar,
    /// by reason (a program that reads slowly says why).
    Lane {
        task: &'a str,
        files: &'a [String],
        tally: &'a LaneTally,
    },
    /// A choice the estimate or the correction made that the user should
    /// know about.
    Note(&'a str),
    /// The model and arm a task is corrected with, as the marker names
    /// them; `on_lengths`: the IRB 140's thermal defaults on another
    /// arm's lengths.
    ThermalModel {
        task: &'a str,
        label: &'a str,
        on_lengths: bool,
    },
    /// The model's tracker frame belongs to the instrument it was
    /// diagnosed with: left out of the correction.
    InstrumentLeftOut { task: &'a str },
    /// A task that moves no robot, left alone; `moves`: how many move
    /// instructions it holds all the same (its targets are then left cold).
    NotMotion { task: &'a str, moves: usize },
    /// How long a step took.
    Took { what: &'a str, elapsed: Duration },
    /// Targets solved so far of a task's total: (0, total) when the first
    /// is started, (total, total) when the last is done.
    Progress { done: usize, total: usize },
}

/// Who a job tells what happens.
pub trait Host {
    fn event(&mut self, e: Event<'_>);
}

/// Where a job's corrected files go.
pub trait Sink {
    /// An output for the corrected version of `name` (an input file, or
    /// the one destination), filled as the job writes it and kept only
    /// once [`OutputFile::finish`]ed; dropped unfinished, it is thrown away.
    fn create(&mut self, name: &str) -> Result<Box<dyn OutputFile>>;
}

/// One corrected file being written.
pub trait OutputFile: std::io::Write + Send {
    /// Throw away what was written and start again.
    fn restart(&mut self) -> std::io::Result<()>;
    /// Keep what was written. `changed`: whether the program changes (a
    /// file that does not may be left as it is).
    fn finish(self: Box<Self>, changed: bool) -> Result<()>;
}

/// A job's starting time of a step, said when it ends.
pub(super) fn took(host: &mut dyn Host, what: &str, started: std::time::Instant) {
    host.event(Event::Took {
        what,
        elapsed: started.elapsed(),
    });
}
