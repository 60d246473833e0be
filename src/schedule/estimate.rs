//! The estimate: walk the program's entry routine from a start time and
//! time each move, for when the user has no schedule of the real run.

use super::bounds::STEP_BUDGET;
use super::cold_joints::ColdJoints;
use super::file::lower;
use super::walk::{Flow, ReachAhead, TargetPoses, Walker};
use super::Schedule;
use crate::error::{Error, ErrorKind, Remedy, Result};
use crate::rapid::{Program, Routine, RoutineKind};
use crate::robot::Robot;

// ------------------------------------------------------------ estimation

/// What [`estimate`] walks: the entry routine, the start time, how many
/// times the entry routine runs.
#[derive(Debug, Clone, PartialEq)]
pub struct EstimateOptions {
    /// Entry routine (case-insensitive), `main` by default.
    pub entry: String,
    /// Minutes since the cold start at which the program starts.
    pub start_min: f64,
    /// How many times the entry routine runs back to back.
    pub cycles: u32,
    /// Where the robot's base stands in the world (MultiMove, a robot on a
    /// pedestal): targets are written in world and work-object frames.
    /// `None`: at the world origin.
    pub base_frame: Option<nalgebra::Isometry3<f64>>,
}

impl Default for EstimateOptions {
    fn default() -> Self {
        EstimateOptions {
            entry: "main".to_string(),
            start_min: 0.0,
            cycles: 1,
            base_frame: None,
        }
    }
}

/// The estimated schedule of a program.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Estimate {
    /// Every visit of every robtarget (identifiers of [`Program::targets`]).
    pub schedule: Schedule,
    /// Every visit of every jointtarget (MoveAbsJ), identifiers of
    /// [`Program::jointtargets`] (their own name space).
    pub joint_schedule: Schedule,
    /// From the start to the end of the last motion, minutes.
    pub duration_min: f64,
    /// The choices made where the program's run-time values decide (branch
    /// taken, loop counts, unknown procedures, ...), each with its place.
    pub notes: Vec<String>,
}

impl Estimate {
    /// The schedule as CSV (the format [`Schedule::read`] takes back):
    /// robtargets and jointtargets together, in time order. Where a
    /// jointtarget's identifier is also a robtarget's (inline `main#1` of
    /// both kinds), every row says its kind (`target,time_min,kind`), so
    /// that `correct --schedule` gives each its own visits.
    pub fn to_csv(&self) -> String {
        let clash = self
            .joint_schedule
            .targets()
            .any(|id| self.schedule.times(id).is_some());
        if clash {
            return self.typed_csv();
        }
        let mut all = self.schedule.clone();
        for id in self.joint_schedule.targets() {
            for &t in self.joint_schedule.times(id).unwrap_or(&[]) {
                all.visit(id, t);
            }
        }
        all.to_csv()
    }

    /// Every visit with its kind, in time order (robtargets first at a
    /// tie, then first-visit order).
    fn typed_csv(&self) -> String {
        let mut rows: Vec<(f64, usize, &str, &str)> = Vec::new();
        let n = self.schedule.targets().len();
        for (i, (name, times)) in self.schedule.entries().enumerate() {
            rows.extend(times.iter().map(|&t| (t, i, name, "robtarget")));
        }
        for (j, (name, times)) in self.joint_schedule.entries().enumerate() {
            rows.extend(times.iter().map(|&t| (t, n + j, name, "jointtarget")));
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut out = String::from("target,time_min,kind\n");
        for (t, _, name, kind) in rows {
            out.push_str(&super::file::csv_field(name));
            out.push_str(&format!(",{t:.4},{kind}\n"));
        }
        out
    }
}

/// Estimate when each target of `program` is reached by walking the entry
/// routine from `opts.start_min`, timing each move from its distance and
/// speed on the nominal (cold) `robot`.
///
/// Documented choices (each one made is listed in [`Estimate::notes`]):
/// - the robot starts at the calibration pose (all joints 0);
/// - IF/ELSEIF/TEST: conditions the program fixes (constants, FOR
///   variables, arguments, `Present`) are evaluated; otherwise the first
///   branch whose condition may be true is taken;
/// - WHILE runs its body once unless its condition is known FALSE; a
///   backward GOTO is not taken (its loop is timed once); forward GOTOs are;
/// - FOR loops with bounds the program fixes run in full, others once;
/// - VAR and PERS numbers are run-time values (unknown); robtarget
///   variables assigned in the walk (`p := Offs(...)`) are followed;
/// - WaitTime counts; WaitUntil, WaitDI and other waits on signals take 0 s;
/// - a move with `\Conc` lets the program run on while the robot moves;
/// - acceleration and zones are ignored (each move at its programmed speed,
///   `VelSet` applied);
/// - a move to a derived target (`Offs(p10,...)`, `main@2`) is a visit of
///   that derived target; a base (`p10`) never reached itself gets the
///   visits of the targets derived from it.
///
/// Errors: no entry routine; a program whose walk exceeds 50 million
/// statements; a target moved to that is not finite, out of reach (no
/// joint solution within the limits) or, a jointtarget, outside the joint
/// limits: each
/// such target is checked before its move is timed, the walk goes on, and
/// the error lists every one (up to [`crate::error::MAX_RELATED`], each
/// at its place) rather than timing any of them.
pub fn estimate(program: &Program, robot: &Robot, opts: &EstimateOptions) -> Result<Estimate> {
    // No joints kept: nothing would take them.
    walked(program, robot, opts, false).map(|(e, _)| e)
}

/// [`estimate`], with the cold joints its walk found for the literal
/// targets it moved to: a correction of the same program takes them
/// rather than solve each again.
pub fn estimate_with_joints(
    program: &Program,
    robot: &Robot,
    opts: &EstimateOptions,
) -> Result<(Estimate, ColdJoints)> {
    walked(program, robot, opts, true)
}

/// The estimate, and where `keep`, the cold joints its walk found.
fn walked(
    program: &Program,
    robot: &Robot,
    opts: &EstimateOptions,
    keep: bool,
) -> Result<(Estimate, ColdJoints)> {
    start_checked(opts)?;
    let (module, routine) = find_entry(program, &opts.entry)?;
    let poses = std::sync::Arc::new(TargetPoses::read(program));
    let walk = |ahead: Option<ReachAhead>| -> Result<Walker> {
        let mut w = Walker::new(program, robot, opts.base_frame.as_ref())?;
        w.poses = poses.clone();
        w.deferred = ahead;
        walk_cycles(&mut w, (module, routine), opts)?;
        Ok(w)
    };
    // Whether each target can be reached is asked of the arm on another
    // core while the walk goes on (what is left after it, on every
    // core); should one not be, the walk is taken again asking at each
    // move, which finds it (and every other) in its place and does not
    // time its move, as the controller would not run it.
    let (mut w, (reached, found)) =
        std::thread::scope(|scope| -> Result<(Walker, (bool, Option<_>))> {
            let slots = if keep {
                ColdJoints::slots(program)
            } else {
                Vec::new()
            };
            let mut w = walk(Some(ReachAhead::start(scope, robot, slots)))?;
            let answers = match w.deferred.take() {
                Some(d) => d.finish(robot),
                None => (false, None),
            };
            Ok((w, answers))
        })?;
    // The joints found stand whatever the walk finds next: each is the IK
    // of its pose.
    let pairs = std::mem::take(&mut w.pairs);
    let found = found.map(|slots| ColdJoints::new(program, pairs, slots));
    if !reached {
        w = walk(None)?;
    }
    let errors = std::mem::take(&mut w.errors);
    if let Some(e) = errors.into_error(|n| {
        Error::new(
            ErrorKind::Unreachable,
            format!("{n} targets cannot be timed: each is out of reach or not finite"),
        )
    }) {
        return Err(e);
    }
    let mut estimate = finished(&mut w, opts)?;
    clashes(&mut estimate);
    Ok((estimate, found.unwrap_or_default()))
}

fn start_checked(opts: &EstimateOptions) -> Result<()> {
    if !opts.start_min.is_finite() || opts.start_min < 0.0 {
        return Err(Error::usage(format!(
            "start time {} min: must be a finite number of minutes since the cold start, not negative",
            opts.start_min
        )));
    }
    Ok(())
}

/// The entry routine walked `opts.cycles` times from `opts.start_min`.
fn walk_cycles<'p>(
    w: &mut Walker<'p>,
    (module, routine): (usize, &'p Routine),
    opts: &EstimateOptions,
) -> Result<()> {
    let start_s = opts.start_min * 60.0;
    w.clock = start_s;
    w.robot_free = start_s;
    for cycle in 0..opts.cycles {
        let before = w.steps;
        let flow = w.call_routine(module, routine, Vec::new(), 0)?;
        if matches!(flow, Flow::Exit) {
            break;
        }
        // Every cycle walks what the first did: a count of cycles the
        // budget cannot hold is refused now, not after minutes of walking
        // and gigabytes of visits.
        let per_cycle = w.steps - before;
        if cycle == 0 && per_cycle.saturating_mul(u64::from(opts.cycles)) > STEP_BUDGET {
            return Err(Error::usage(format!(
                "{} cycles of {} would walk {} statements ({per_cycle} each), past the walk's limit of {STEP_BUDGET}: give fewer cycles",
                opts.cycles,
                routine.name,
                per_cycle.saturating_mul(u64::from(opts.cycles))
            )));
        }
    }
    Ok(())
}

/// The estimate of a walk that found every target timed.
fn finished(w: &mut Walker, opts: &EstimateOptions) -> Result<Estimate> {
    let start_s = opts.start_min * 60.0;
    let end_s = w.clock.max(w.robot_free);
    if !end_s.is_finite() {
        return Err(Error::input(
            "the program's waits add up to more time than can be counted (a WaitTime of astronomic length?)",
        ));
    }
    w.finish();
    Ok(Estimate {
        schedule: std::mem::take(&mut w.schedule),
        joint_schedule: std::mem::take(&mut w.joint_schedule),
        duration_min: (end_s - start_s) / 60.0,
        notes: std::mem::take(&mut w.notes),
    })
}

/// A note for each jointtarget whose identifier is a robtarget's that
/// `e`'s schedule holds.
fn clashes(e: &mut Estimate) {
    if e.joint_schedule.is_empty() {
        return;
    }
    // The robtargets' identifiers scanned once against the few
    // jointtargets': no table of a million robtarget names is made for a
    // home position's MoveAbsJ.
    let joints: std::collections::HashSet<String> = e
        .joint_schedule
        .targets()
        .map(|id| lower(id).into_owned())
        .collect();
    let both: std::collections::HashSet<String> = e
        .schedule
        .targets()
        .map(lower)
        .filter(|id| joints.contains(id.as_ref()))
        .map(|id| id.into_owned())
        .collect();
    for id in e.joint_schedule.targets() {
        if both.contains(lower(id).as_ref()) {
            e.notes.push(format!(
                "jointtarget {id} has the identifier of robtarget {id} (two name spaces, one schedule file): the CSV says each row's kind"
            ));
        }
    }
}

pub(super) fn find_entry<'p>(program: &'p Program, entry: &str) -> Result<(usize, &'p Routine)> {
    for (mi, m) in program.modules.iter().enumerate() {
        if let Some(r) = m
            .routines
            .iter()
            .find(|r| r.kind == RoutineKind::Proc && r.name.eq_ignore_ascii_case(entry))
        {
            return Ok((mi, r));
        }
    }
    let procs: Vec<&str> = program
        .modules
        .iter()
        .flat_map(|m| &m.routines)
        .filter(|r| r.kind == RoutineKind::Proc && r.params.is_empty())
        .map(|r| r.name.as_ref())
        .collect();
    let mut e = Error::input(format!(
        "no procedure `{entry}` in the program: nothing to walk"
    ));
    if !procs.is_empty() {
        e = e.with_note(format!(
            "procedures without parameters: {}",
            procs.join(", ")
        ));
        e = e.with_remedy(Remedy::ChooseEntry);
    }
    Err(e)
}
