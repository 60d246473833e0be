//! What every target of a run shares: the program's frames, usages and
//! constants, the warm robot's states, the options; built once per run.

use super::cold_prints::ColdPrints;
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
use crate::schedule::ColdJoints;
use nalgebra::Isometry3;
use std::collections::{HashMap, HashSet};
use std::sync::{Mutex, OnceLock};

/// What every target of a run shares: the program's frames and usages, the
/// warm robot's states, the options.
pub(super) struct Run<'a> {
    pub program: &'a Program,
    pub warm: &'a WarmRobot,
    pub states: States<'a>,
    pub options: &'a Options,
    /// What the program alone decides: its frames, the uses of its
    /// targets, configuration monitoring, constants and calls.
    pub set: Prepared<'a>,
    /// Choices made on the way that the user should know about, each with
    /// the place of the target it was made for (the targets are solved
    /// on every core: said in the program's order).
    pub notes: Mutex<Vec<((usize, usize), String)>>,
    /// Where names are declared and read, for splitting targets (built
    /// when first needed).
    pub names: OnceLock<Names>,
    /// The cold joints the run's walk found, where it had one
    /// ([`crate::schedule::estimate_with_joints`]).
    pub cold_joints: Option<ColdJoints>,
}

/// What a run shares that the program alone decides (its frames, the
/// uses of its targets, configuration monitoring, constants, calls):
/// made before the warm robot and the times are known, so that a
/// `--start` run makes it beside its walk.
pub(crate) struct Prepared<'a> {
    program: &'a Program,
    /// What it was made for: the entry routine and the base frame.
    entry: String,
    base_frame: Option<Isometry3<f64>>,
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
    /// Data the program reaches by name at run time (`GetDataVal`).
    pub by_name: crate::resolve::ByName,
    pub constants: Constants<'a>,
    /// Every function call of the program by where it starts.
    pub calls: HashMap<usize, &'a FunctionCall>,
    pub expressions: Expressions<'a>,
    /// The notes of its making, for the run's.
    notes: Vec<((usize, usize), String)>,
}

impl<'a> Prepared<'a> {
    /// What `program` alone decides for a run whose walk starts at the
    /// routine `entry`, its robot's base at `base_frame` (the world
    /// origin: `None`).
    pub fn of(
        program: &'a Program,
        entry: &str,
        base_frame: Option<&Isometry3<f64>>,
    ) -> Result<Prepared<'a>> {
        let frames = match base_frame {
            Some(base) => Frames::of_program(program).map(|f| f.placed(base)),
            None => Frames::of_program(program),
        };
        let lookup = MoveLookup::new(program);
        let uses = uses_with(program, &lookup);
        let monitoring = Monitoring::of(program, entry);
        let unmonitored = unmonitored_targets(program, &uses, &monitoring);
        let notes = unsettled_note(program, &monitoring, entry);
        Ok(Prepared {
            program,
            entry: entry.to_string(),
            base_frame: base_frame.copied(),
            frames: frames?,
            lookup,
            uses,
            monitoring,
            unmonitored,
            writes: runtime_writes(program),
            unsettled_frames: crate::resolve::unsettled_frame_parameters(program),
            by_name: crate::resolve::ByName::of(program),
            constants: Constants::of(program),
            calls: calls_by_offset(program),
            expressions: Expressions::of(program),
            notes,
        })
    }

    /// Whether it was made for a run of `program` with `options`.
    pub fn fits(&self, program: &Program, options: &Options) -> bool {
        std::ptr::eq(self.program, program)
            && self.entry == entry_of(options)
            && self.base_frame == options.base_frame
    }
}

/// What a run corrects with: the warm robot, the options, and what was
/// made ahead of it ([`Precomputed`]).
pub(crate) struct CorrectWith<'a, 'p> {
    pub warm: &'a WarmRobot,
    pub options: &'a Options,
    pub ahead: Precomputed<'p>,
}

impl<'a, 'p> CorrectWith<'a, 'p> {
    pub fn new(warm: &'a WarmRobot, options: &'a Options, ahead: Precomputed<'p>) -> Self {
        CorrectWith {
            warm,
            options,
            ahead,
        }
    }

    /// Nothing made ahead: the run makes all it needs.
    pub fn fresh(warm: &'a WarmRobot, options: &'a Options) -> Self {
        CorrectWith::new(warm, options, Precomputed::default())
    }
}

/// What a caller made before a run: what the program alone decides
/// (beside an estimate's walk, or its error) and each file's cold
/// fingerprint (beside the parse). What is missing, or was made for
/// another program or other options, the run makes itself.
#[derive(Default)]
pub(crate) struct Precomputed<'a> {
    pub prepared: Option<Result<Prepared<'a>>>,
    pub colds: Option<ColdPrints>,
    /// The cold joints the walk that timed the run found.
    pub cold_joints: Option<ColdJoints>,
}

impl<'a> Precomputed<'a> {
    /// The run's set-up and its files' fingerprints: as made ahead where
    /// they fit, else made now (both on two cores where both are
    /// missing: a file of 100 MB takes a twentieth of a second to hash).
    pub fn setup_and_prints(
        self,
        program: &'a Program,
        options: &Options,
    ) -> Result<(Prepared<'a>, Vec<String>)> {
        let prepared = match self.prepared.transpose()? {
            Some(p) if p.fits(program, options) => Some(p),
            _ => None,
        };
        let colds = self.colds.filter(|c| c.fits(program));
        let make = || Prepared::of(program, entry_of(options), options.base_frame.as_ref());
        match (prepared, colds) {
            (Some(p), Some(c)) => Ok((p, c.into_prints())),
            (Some(p), None) => Ok((p, ColdPrints::of_program(program).into_prints())),
            (None, Some(c)) => Ok((make()?, c.into_prints())),
            (None, None) => {
                let (p, c) = rayon::join(make, || ColdPrints::of_program(program));
                Ok((p?, c.into_prints()))
            }
        }
    }
}

/// The routine a run's walk starts from: an estimate's, else `main`.
pub(crate) fn entry_of(options: &Options) -> &str {
    match &options.when {
        When::Schedule {
            source: ScheduleSource::Estimate(request),
            ..
        } => request.entry.as_str(),
        _ => "main",
    }
}

impl<'a> Run<'a> {
    /// The run of `prepared`'s program with `warm` and `options` (which it
    /// must fit: [`Prepared::fits`]).
    pub fn with(mut prepared: Prepared<'a>, warm: &'a WarmRobot, options: &'a Options) -> Run<'a> {
        let mut states = warm.states();
        // Every target at one moment: its state worked out once. (An
        // error is said where a target asks for it, as before.)
        if let When::At(m) = options.when {
            let _ = states.remember(m);
        }
        Run {
            program: prepared.program,
            warm,
            states,
            options,
            notes: Mutex::new(std::mem::take(&mut prepared.notes)),
            set: prepared,
            names: OnceLock::new(),
            cold_joints: None,
        }
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
        self.set.constants.num(e, site)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::correct::program::{correct, correct_in_memory};
    use crate::model::{Model, Moment};
    use crate::robot::Robot;
    use crate::schedule::{EstimateOptions, Schedule};

    /// A `--start` correction with its walk's cold joints, and the
    /// outputs of one that solves them itself.
    fn with_and_without_joints(
        tamper: bool,
    ) -> (
        crate::correct::outcome::Outcome,
        crate::correct::outcome::Outcome,
        usize,
    ) {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/cam_contour.mod");
        let bytes = std::fs::read(path).expect("sample");
        let program = crate::rapid::parse("cam_contour.mod", &bytes).expect("parses");
        let robot = Robot::irb140();
        let opts = EstimateOptions::default();
        let (estimate, joints) =
            crate::schedule::estimate_with_joints(&program, &robot, &opts).expect("walks");
        let found = joints.found();
        let joints = if tamper { joints.shifted() } else { joints };
        let horizon = estimate.schedule.all_times().fold(0.0, f64::max);
        let warm = WarmRobot::new(robot, &Model::default(), horizon).expect("model");
        let options = Options::new(When::Schedule {
            schedule: estimate.schedule,
            joints: Some(estimate.joint_schedule),
            default: None,
            source: ScheduleSource::Estimate(Box::new(opts)),
        });
        let own = correct(&program, &warm, &options, &mut |_, _| {}).expect("corrects");
        let ahead = Precomputed {
            prepared: None,
            colds: None,
            cold_joints: Some(joints),
        };
        let given = correct_in_memory(
            &program,
            CorrectWith::new(&warm, &options, ahead),
            &mut |_, _| {},
        )
        .expect("corrects");
        (own, given, found)
    }

    /// The joints the walk found change nothing: the run corrects as one
    /// that solves each target itself.
    #[test]
    fn the_walks_cold_joints_change_nothing() {
        let (own, given, found) = with_and_without_joints(false);
        assert!(found > 10, "the walk kept joints for {found} targets");
        assert_eq!(given.outputs, own.outputs);
        assert_eq!(given.notes, own.notes);
    }

    /// The run takes them: joints that are not the IK's are caught where
    /// they are taken (a check of debug builds, the tests'; it stops the
    /// run's workers, and so the run).
    #[test]
    #[cfg(debug_assertions)]
    fn the_walks_cold_joints_are_taken() {
        let run = std::panic::catch_unwind(|| with_and_without_joints(true));
        assert!(
            run.is_err(),
            "joints turned by a milliradian were not taken"
        );
    }

    /// A preparation fits the run it was made for (an estimate's entry
    /// routine, the base frame); one made for another is made again, and
    /// the run corrects as one that made its own.
    #[test]
    fn a_preparation_made_for_other_options_is_made_again() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/two_modules.mod");
        let bytes = std::fs::read(path).expect("sample");
        let program = crate::rapid::parse("two_modules.mod", &bytes).expect("parses");
        let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).expect("model");
        let at = Options::new(When::At(Moment::Minute(120.0)));
        let estimate = |entry: &str| {
            Options::new(When::Schedule {
                schedule: Schedule::default(),
                joints: None,
                default: Some(Moment::Minute(120.0)),
                source: ScheduleSource::Estimate(Box::new(EstimateOptions {
                    entry: entry.to_string(),
                    ..EstimateOptions::default()
                })),
            })
        };
        let base = Isometry3::translation(0.0, 0.0, 250.0);
        let made = |entry: &str, base: Option<&Isometry3<f64>>| {
            Prepared::of(&program, entry, base).expect("prepared")
        };
        assert!(made("main", None).fits(&program, &at));
        assert!(made("Cycle", None).fits(&program, &estimate("Cycle")));
        assert!(!made("Cycle", None).fits(&program, &at));
        assert!(!made("main", None).fits(&program, &estimate("Cycle")));
        assert!(!made("main", Some(&base)).fits(&program, &at));
        let own = correct(&program, &warm, &at, &mut |_, _| {}).expect("corrects");
        for p in [made("main", None), made("Cycle", Some(&base))] {
            let given = correct_in_memory(
                &program,
                CorrectWith::new(
                    &warm,
                    &at,
                    Precomputed {
                        prepared: Some(Ok(p)),
                        colds: None,
                        cold_joints: None,
                    },
                ),
                &mut |_, _| {},
            )
            .expect("corrects");
            assert_eq!(given.outputs, own.outputs);
            assert_eq!(given.notes, own.notes);
        }
    }
}
