//! A correction run as the user asked for it, every choice read and
//! checked before any input is opened: when the targets are reached, what
//! to do with the result, which model and arms. The command line builds
//! one from its arguments (every usage error is raised there); the job
//! ([`super::job`]) runs it.

use super::check::CheckRule;
use crate::model::Moment;
use crate::resolve::arm::{ArmSpec, Placing};
use crate::schedule::WhichVisit;
use std::path::PathBuf;

/// What a `correct` run makes, each job with its own plan: the
/// run-time job reads no time of the targets, so its plan has none.
#[derive(Debug, Clone)]
pub enum CorrectJob {
    /// The targets corrected for when they are reached ([`super::job`]).
    Correct(CorrectPlan),
    /// A module that corrects on the controller as the program runs, and
    /// the program rewritten to call it ([`super::runtime::job`]).
    Runtime(RuntimePlan),
}

impl CorrectJob {
    /// What the run does with the programs it makes.
    pub fn action(&self) -> &Action {
        match self {
            CorrectJob::Correct(p) => &p.action,
            CorrectJob::Runtime(p) => &p.action,
        }
    }

    /// The arm of each task and the model that warms it.
    pub fn arms(&self) -> &ArmChoice {
        match self {
            CorrectJob::Correct(p) => &p.arms,
            CorrectJob::Runtime(p) => &p.arms,
        }
    }
}

/// A planned correction.
#[derive(Debug, Clone)]
pub struct CorrectPlan {
    pub when: TimeBasis,
    /// Which visit a target reached several times is corrected for.
    pub visit: WhichVisit,
    pub arms: ArmChoice,
    /// Write numbers in place of literals written with named constants or
    /// expressions.
    pub expand_expressions: bool,
    /// Split targets moved to with several tools or work objects.
    pub split_shared: bool,
    pub action: Action,
    /// Pictures are drawn from every target's row: the run keeps them.
    pub keep_rows: bool,
}

/// A planned rewrite for correction at run time (`--runtime`).
#[derive(Debug, Clone)]
pub struct RuntimePlan {
    /// The module's name, a RAPID identifier (checked as the plan is
    /// made).
    pub module: String,
    pub arms: ArmChoice,
    /// Never [`Action::Check`]: a check has no numbers to compare before
    /// the controller runs.
    pub action: Action,
}

/// The arm each task moves and the model that warms it: what every job
/// of `correct` corrects for.
#[derive(Debug, Clone)]
pub struct ArmChoice {
    pub model: ModelSource,
    /// Arms named for every task or for one task of a backup.
    pub specs: Vec<ArmSpec>,
    /// Use the IRB 140's thermal defaults on an arm whose own are unknown.
    pub irb140_thermal: bool,
    /// Whether a task its backup does not place may stand at the origin.
    pub placing: Placing,
}

/// When the targets are reached.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeBasis {
    /// Every target at one moment.
    At(Moment),
    /// The times of a schedule file (`target,time_min`); `default` for the
    /// targets it does not list.
    Schedule {
        file: PathBuf,
        default: Option<Moment>,
    },
    /// The times estimated by walking the program from minute `start_min`.
    Start {
        start_min: f64,
        entry: String,
        cycles: u32,
        default: Option<Moment>,
    },
}

impl TimeBasis {
    /// The schedule file, where one is read.
    pub fn schedule_file(&self) -> Option<&std::path::Path> {
        match self {
            TimeBasis::Schedule { file, .. } => Some(file),
            _ => None,
        }
    }
}

/// What the run does with the corrected program.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Report every target; write nothing.
    Report,
    /// List what the check finds; write nothing.
    Check(CheckRule),
    /// The change as a diff, and the check's list where asked; write
    /// nothing.
    Diff { check: Option<CheckRule> },
    /// Write the corrected program.
    Write(Destination),
}

impl Action {
    /// The suffix each original keeps, where the inputs are rewritten in
    /// place with a backup.
    pub fn backup(&self) -> Option<String> {
        match self {
            Action::Write(Destination::InPlace { backup }) => backup.clone(),
            _ => None,
        }
    }
}

/// Where a corrected program goes.
#[derive(Debug, Clone, PartialEq)]
pub enum Destination {
    /// One file (one input).
    File(PathBuf),
    /// Standard output (one input).
    Stdout,
    /// Over the inputs themselves, each original kept as FILE + `backup`
    /// where given.
    InPlace { backup: Option<String> },
}

impl Destination {
    /// The program files a run on `tasks` (those that move a robot)
    /// writes here: the one file, or each task's files in place; none to
    /// standard output. Known before any task is read.
    pub fn files(&self, tasks: &[&crate::rapid::task::Task]) -> Vec<PathBuf> {
        match self {
            Destination::File(out) => vec![out.clone()],
            Destination::Stdout => Vec::new(),
            Destination::InPlace { .. } => tasks
                .iter()
                .flat_map(|t| t.modules.iter().cloned())
                .collect(),
        }
    }
}

/// The model a run uses.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelSource {
    /// The embedded IRB 140 model and heating profile.
    Default,
    /// An embedded model by name (`default`, `base`).
    Named(String),
    /// A model file.
    File(PathBuf),
}
