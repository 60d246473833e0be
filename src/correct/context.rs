//! What every target of a run shares: the program's frames, usages and
//! constants, the warm robot's states, the options; built once per run.

use super::derived::calls_by_offset;
use super::expressions::Expressions;
use super::names::Names;
use super::options::{Options, ScheduleSource, When};
use crate::error::{Location, Result};
use crate::model::{States, WarmRobot};
use crate::rapid::constants::{Constants, Site};
use crate::rapid::{Expr, FunctionCall, Program, Target};
use crate::resolve::dataflow::{runtime_writes, Write};
use crate::resolve::monitoring::{Monitor, Monitoring};
use crate::resolve::{uses_with, Frames, MoveLookup, Uses};
use std::collections::{HashMap, HashSet};
use std::sync::{Mutex, OnceLock};

/// What every target of a run shares: the program's frames and usages, the
/// warm robot's states, the options.
pub(super) struct Run<'a> {
    pub program: &'a Program,
    pub warm: &'a WarmRobot,
    pub states: States<'a>,
    pub options: &'a Options,
    pub frames: Frames,
    /// What the moves' target arguments are looked up in (built once for
    /// the uses here and the moves' fates).
    pub lookup: MoveLookup<'a>,
    pub uses: Uses<'a>,
    /// Configuration monitoring at every move (`ConfL`, `ConfJ`).
    pub monitoring: Monitoring,
    /// The targets no move of which runs with configuration monitoring
    /// on for certain, by (file, byte offset) of the target: `Off` where
    /// every move runs with it off (the controller does not hold them to
    /// their robconf), `Unsettled` where the walk cannot tell for some
    /// (held, and said so).
    pub unmonitored: HashMap<(usize, usize), Monitor>,
    /// Robtarget and jointtarget variables the run writes, by lower-case
    /// name.
    pub writes: HashMap<String, Write>,
    /// Tooldata and wobjdata parameters some call leaves to the run, by
    /// (routine, parameter), lower case: a target moved to with one is
    /// left alone.
    pub unsettled_frames: HashSet<(String, String)>,
    pub constants: Constants<'a>,
    /// Every function call of the program by where it starts.
    pub calls: HashMap<usize, &'a FunctionCall>,
    pub expressions: Expressions<'a>,
    /// Choices made on the way that the user should know about, each with
    /// the place of the target it was made for (the targets are solved
    /// on every core: said in the program's order).
    pub notes: Mutex<Vec<((usize, usize), String)>>,
    /// Where names are declared and read, for splitting targets (built
    /// when first needed).
    pub names: OnceLock<Names>,
}

impl<'a> Run<'a> {
    pub fn new(program: &'a Program, warm: &'a WarmRobot, options: &'a Options) -> Result<Run<'a>> {
        let mut states = warm.states();
        // Every target at one moment: its state worked out once. (An
        // error is said where a target asks for it, as before.)
        if let When::At(m) = options.when {
            let _ = states.remember(m);
        }
        let lookup = MoveLookup::new(program);
        let uses = uses_with(program, &lookup);
        let entry = match &options.when {
            When::Schedule {
                source: ScheduleSource::Estimate(request),
                ..
            } => request.entry.as_str(),
            _ => "main",
        };
        let monitoring = Monitoring::of(program, entry);
        let unmonitored = unmonitored_targets(program, &uses, &monitoring);
        let run_notes = unsettled_note(program, &monitoring, entry);
        Ok(Run {
            program,
            warm,
            states,
            options,
            frames: match &options.base_frame {
                Some(base) => Frames::of_program(program)?.placed(base),
                None => Frames::of_program(program)?,
            },
            lookup,
            uses,
            monitoring,
            unmonitored,
            writes: runtime_writes(program),
            unsettled_frames: crate::resolve::unsettled_frame_parameters(program),
            constants: Constants::of(program),
            calls: calls_by_offset(program),
            expressions: Expressions::of(program),
            notes: Mutex::new(run_notes),
            names: OnceLock::new(),
        })
    }

    /// A choice made for the target at `place` (file, byte offset) that
    /// the user should know about; said once.
    pub fn note(&self, place: (usize, usize), text: String) {
        if let Ok(mut notes) = self.notes.lock() {
            if !notes.iter().any(|(_, n)| *n == text) {
                notes.push((place, text));
            }
        }
    }

    /// The notes, in the program's order.
    pub fn notes(&self) -> Vec<String> {
        let mut notes = match self.notes.lock() {
            Ok(n) => n.clone(),
            Err(_) => Vec::new(),
        };
        notes.sort_by_key(|n| n.0);
        notes.into_iter().map(|(_, n)| n).collect()
    }

    /// The value of a number in the program as written at `target`
    /// (literals and constants).
    pub fn eval(&self, target: &Target, e: &Expr) -> Option<f64> {
        let site = Site {
            module: &target.origin.module,
            routine: target.origin.routine.as_deref(),
        };
        self.constants.num(e, site)
    }
}

/// The targets every move of which runs with configuration monitoring
/// off (none where nothing switches it off).
fn unmonitored_targets(
    program: &Program,
    uses: &Uses,
    monitoring: &Monitoring,
) -> HashMap<(usize, usize), Monitor> {
    let mut out = HashMap::new();
    if !monitoring.ever_off() {
        return out;
    }
    for (i, target) in program.targets().iter().enumerate() {
        // One move with monitoring on holds the robconf: the target is
        // monitored whatever its other moves do.
        let mut held: Option<Monitor> = None;
        for u in uses.of(i) {
            let m = monitoring
                .at(u.file(), u.offset(), u.instruction())
                .unwrap_or(Monitor::On);
            held = Some(match (held, m) {
                (_, Monitor::On) | (Some(Monitor::On), _) => Monitor::On,
                (Some(Monitor::Unsettled), _) | (_, Monitor::Unsettled) => Monitor::Unsettled,
                _ => Monitor::Off,
            });
        }
        if let Some(m @ (Monitor::Off | Monitor::Unsettled)) = held {
            out.insert((target.origin.file, target.origin.pos.offset), m);
        }
    }
    out
}

/// The note of a run where the walk cannot settle configuration
/// monitoring at some moves: they are taken as monitored.
fn unsettled_note(
    program: &Program,
    monitoring: &Monitoring,
    entry: &str,
) -> Vec<((usize, usize), String)> {
    let unsettled = monitoring.unsettled(program);
    let Some((file, offset, instruction)) = unsettled.first() else {
        return Vec::new();
    };
    let at = Location::from_offset(&program.files[*file], program.source(*file), *offset);
    let more = match unsettled.len() - 1 {
        0 => String::new(),
        n => format!(" and {n} more move(s)"),
    };
    vec![(
        (*file, *offset),
        format!(
            "configuration monitoring at {instruction} ({} line {}){more} cannot be settled by a walk from {entry}: ConfL/ConfJ \\Off is in effect on some paths to it only, so it is taken as on (the robconf is held)",
            at.file, at.line
        ),
    )]
}
