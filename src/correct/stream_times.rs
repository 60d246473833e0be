//! When the targets of a streamed run are reached where that is a schedule
//! (`--start`, `--schedule`): the schedule names targets as the whole
//! program does, the streamed run reads the skeleton's targets and the cut
//! moves' literals apart. This is the first of the two passes: each cut
//! literal's moment is worked out and kept (a number per literal, in file
//! order), and the schedule is given the skeleton's identifiers for the
//! skeleton's own targets (its inline literals are numbered without the
//! cut ones). A schedule file names every target: the whole program is
//! read from the skeleton ([`parse_skeleton`]) to look each up
//! ([`CutTimes::new`]). An estimate is walked on the skeleton with its cut
//! moves in runs, read from the file as the walk meets them
//! ([`estimate_cuts`]), and gives each literal's visits by its number
//! ([`CutTimes::of_estimate`]).
//!
//! [`parse_skeleton`]: crate::rapid::parse_skeleton
//! [`estimate_cuts`]: crate::schedule::estimate_cuts

use super::moments::picked_moment;
use super::options::{schedule_basis, Options, When};
use crate::model::Moment;
use crate::rapid::fastmove::Skeleton;
use crate::rapid::{Program, TargetKind};
#[cfg(doc)]
use crate::schedule::CutEstimate;
use crate::schedule::{CutVisits, Schedule};
use std::collections::HashSet;

/// The moments of a streamed run's targets; see the module doc.
pub struct CutTimes {
    /// The run's options for the skeleton: its schedule keyed by the
    /// skeleton's identifiers.
    pub(super) options: Options,
    /// Each cut literal's moment, in file order.
    pub(super) moments: Vec<Moment>,
    /// An estimate's cut literals' visits, which its schedule does not
    /// hold: the corrected file's marker records them with it.
    pub(super) literals: Option<CutVisits>,
}

impl CutTimes {
    /// What the corrected file's marker records of the run's schedule,
    /// where `options` are the run's: its schedule's fingerprint, with the
    /// cut literals' visits where the schedule does not hold them (taken
    /// while the first moves are corrected: for a million targets, a
    /// tenth of a second).
    pub(super) fn basis(&self, options: &Options) -> String {
        match (&self.literals, &options.when) {
            (
                Some(literals),
                When::Schedule {
                    schedule,
                    joints,
                    default,
                },
            ) => schedule_basis(|e| literals.encode_whole(schedule, e), joints, default),
            _ => options.when.basis(),
        }
    }
}

impl CutTimes {
    /// The moments of the targets of `whole` (the file read from its
    /// skeleton `skeleton`, whose kept bytes parsed as `program`) under
    /// `options`' schedule. `None` where the whole path has something to
    /// say (a target the schedule does not time and no default, a name
    /// the schedule has and the program not) or the two readings do not
    /// line up: the caller then leaves the run to the whole path, which
    /// says it.
    pub fn new(
        whole: &Program,
        program: &Program,
        skeleton: &Skeleton,
        options: &Options,
    ) -> Option<CutTimes> {
        let (schedule, joints, _) = schedules(options)?;
        // The estimate's jointtargets are the program's (a name of it the
        // program has as a robtarget only is left to the whole path).
        if let Some(j) = joints {
            let ids: HashSet<String> = whole
                .jointtargets()
                .iter()
                .map(|j| j.id.to_ascii_lowercase())
                .collect();
            if !j
                .targets()
                .iter()
                .all(|id| ids.contains(&id.to_ascii_lowercase()))
            {
                return None;
            }
        }
        // Every name of the schedule must be a target's: counted as the
        // targets are looked up (a set of a million names was a tenth of
        // the run). A robtarget and a jointtarget may share a name.
        let joint_ids: HashSet<String> = match joints {
            Some(_) => HashSet::new(),
            None => whole
                .jointtargets()
                .iter()
                .map(|j| j.id.to_ascii_lowercase())
                .collect(),
        };
        let mut named = 0;
        let mut count = |id: &str, timed: bool| {
            if timed && (joint_ids.is_empty() || !joint_ids.contains(&id.to_ascii_lowercase())) {
                named += 1;
            }
        };
        // The next cut, by its place (targets come in file order).
        let mut cut = 0;
        let mut kept = program.targets().iter();
        let mut rekeyed = Schedule::new();
        let literals: usize = skeleton.literals.iter().map(|&n| usize::from(n)).sum();
        let mut cut_literals = Vec::with_capacity(literals);
        for t in whole.targets() {
            let at = t.origin.pos.offset;
            while cut < skeleton.cuts.len() && skeleton.place_of_cut(cut) < at {
                cut += 1;
            }
            if t.kind == TargetKind::Inline
                && cut < skeleton.cuts.len()
                && skeleton.place_of_cut(cut) == at
            {
                let times = schedule.times(&t.id);
                count(&t.id, times.is_some());
                let moment = picked_moment(&options.when, &t.id, times, options.visit).ok()?;
                cut_literals.push(moment);
                continue;
            }
            // The skeleton's target at the same place: its identifier is
            // the skeleton's own.
            let k = kept.next()?;
            if k.kind != t.kind || k.origin.pos.offset != t.origin.pos.offset {
                return None;
            }
            let times = schedule.times(&t.id);
            count(&t.id, times.is_some());
            for &m in times.unwrap_or(&[]) {
                rekeyed.visit(&k.id, m);
            }
        }
        let joint_named = joint_ids
            .iter()
            .filter(|id| schedule.times(id).is_some())
            .count();
        if kept.next().is_some()
            || cut_literals.len() != literals
            || named + joint_named != schedule.targets().len()
        {
            return None;
        }
        Some(CutTimes {
            options: skeleton_options(options, rekeyed, whole, program)?,
            moments: cut_literals,
            literals: None,
        })
    }

    /// The moments of the targets of an estimate of the file read from
    /// its skeleton in runs (`whole`), whose kept bytes parsed as
    /// `program`: its cut `literals`' visits, and `options` the run's,
    /// their schedule the estimate's (see [`CutEstimate`]). `None` where
    /// a literal is not timed or the two readings do not line up (the
    /// caller then leaves the run to the whole path).
    pub fn of_estimate(
        literals: CutVisits,
        whole: &Program,
        program: &Program,
        options: &Options,
    ) -> Option<CutTimes> {
        let (schedule, _, _) = schedules(options)?;
        // A literal never reached takes the default, if there is one (the
        // whole path names it where there is none).
        let moments = (0..literals.len())
            .map(|l| picked_moment(&options.when, "", literals.times(l), options.visit).ok())
            .collect::<Option<Vec<Moment>>>()?;
        // The whole program's reading in runs holds the skeleton's targets
        // alone, under the whole program's identifiers.
        if whole.targets().len() != program.targets().len() {
            return None;
        }
        let mut rekeyed = Schedule::new();
        for (t, k) in whole.targets().iter().zip(program.targets()) {
            if k.kind != t.kind || k.origin.pos.offset != t.origin.pos.offset {
                return None;
            }
            for &m in schedule.times(&t.id).unwrap_or(&[]) {
                rekeyed.visit(&k.id, m);
            }
        }
        Some(CutTimes {
            options: skeleton_options(options, rekeyed, whole, program)?,
            moments,
            literals: Some(literals),
        })
    }
}

/// The robtargets' schedule of `options`, the jointtargets' where kept
/// apart, and the default moment; `None` at one moment.
type Schedules<'a> = (&'a Schedule, &'a Option<Schedule>, Option<Moment>);

fn schedules(options: &Options) -> Option<Schedules<'_>> {
    match &options.when {
        When::Schedule {
            schedule,
            joints,
            default,
        } => Some((schedule, joints, *default)),
        When::At(_) => None,
    }
}

/// The run's `options` for the skeleton (its kept bytes parsed as
/// `program`, the file read from it as `whole`): its robtargets' schedule
/// `rekeyed`, its jointtargets' times as the run's; `None` where the two
/// readings' jointtargets differ.
fn skeleton_options(
    options: &Options,
    rekeyed: Schedule,
    whole: &Program,
    program: &Program,
) -> Option<Options> {
    let (schedule, joints, default) = schedules(options)?;
    let joints = joint_times(whole, program, joints.as_ref().unwrap_or(schedule))?;
    Some(Options {
        when: When::Schedule {
            schedule: rekeyed,
            joints: Some(joints),
            default,
        },
        visit: options.visit,
        expand_expressions: options.expand_expressions,
        model_label: options.model_label.clone(),
        base_frame: options.base_frame,
        split_shared: options.split_shared,
    })
}

/// The jointtargets' times of `from` for the skeleton: they keep their
/// identifiers (no cut move holds one), their times kept apart from the
/// robtargets', whose keys changed. `None`: the two readings differ.
fn joint_times(whole: &Program, program: &Program, from: &Schedule) -> Option<Schedule> {
    if whole.jointtargets().len() != program.jointtargets().len()
        || whole
            .jointtargets()
            .iter()
            .zip(program.jointtargets())
            .any(|(a, b)| a.id != b.id)
    {
        return None;
    }
    let mut times = Schedule::new();
    for j in program.jointtargets() {
        for &m in from.times(&j.id).unwrap_or(&[]) {
            times.visit(&j.id, m);
        }
    }
    Some(times)
}
