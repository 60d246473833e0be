//! When the targets of a streamed run are reached where that is a schedule
//! (`--start`, `--schedule`): the schedule names targets as the whole
//! program does, the streamed run reads the skeleton's targets and the cut
//! moves' literals apart. This is the first of the two passes: the whole
//! program read from the skeleton ([`parse_skeleton`]) lists every target
//! with its identifier; each cut literal's moment is looked up and kept
//! (a number per target, in file order), and the schedule is given the
//! skeleton's identifiers for the skeleton's own targets (its inline
//! literals are numbered without the cut ones).
//!
//! [`parse_skeleton`]: crate::rapid::parse_skeleton

use super::moments::picked_moment;
use super::{Options, When};
use crate::model::Moment;
use crate::rapid::fastmove::Skeleton;
use crate::rapid::{Program, TargetKind};
use crate::schedule::Schedule;
use std::collections::HashSet;

/// The moments of a streamed run's targets; see the module doc.
pub struct CutTimes {
    /// The run's options for the skeleton: its schedule keyed by the
    /// skeleton's identifiers.
    pub(super) options: Options,
    /// The whole program as the first pass read it: the second corrects
    /// each cut literal from its target here rather than reading its
    /// numbers again (a fifth of the work on every core).
    pub(super) whole: Program,
    /// Each cut literal, in file order: its moment, and its target's
    /// index in `whole`.
    pub(super) literals: Vec<(Moment, usize)>,
}

impl CutTimes {
    /// The moments of the targets of `whole` (the file read from its
    /// skeleton `skeleton`, whose kept bytes parsed as `program`) under
    /// `options`' schedule. `None` where the whole path has something to
    /// say (a target the schedule does not time and no default, a name
    /// the schedule has and the program not) or the two readings do not
    /// line up: the caller then leaves the run to the whole path, which
    /// says it. `whole` is kept: the second pass reads the cut literals
    /// from it.
    pub fn new(
        whole: Program,
        program: &Program,
        skeleton: &Skeleton,
        options: &Options,
    ) -> Option<CutTimes> {
        let When::Schedule {
            schedule,
            joints,
            default,
        } = &options.when
        else {
            return None;
        };
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
        for (i, t) in whole.targets().iter().enumerate() {
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
                cut_literals.push((moment, i));
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
        // Jointtargets keep their identifiers (no cut move holds one);
        // their times are kept apart from the robtargets', whose keys
        // changed.
        if whole.jointtargets().len() != program.jointtargets().len()
            || whole
                .jointtargets()
                .iter()
                .zip(program.jointtargets())
                .any(|(a, b)| a.id != b.id)
        {
            return None;
        }
        let from = joints.as_ref().unwrap_or(schedule);
        let mut joint_times = Schedule::new();
        for j in program.jointtargets() {
            for &m in from.times(&j.id).unwrap_or(&[]) {
                joint_times.visit(&j.id, m);
            }
        }
        Some(CutTimes {
            options: Options {
                when: When::Schedule {
                    schedule: rekeyed,
                    joints: Some(joint_times),
                    default: *default,
                },
                visit: options.visit,
                expand_expressions: options.expand_expressions,
                model_label: options.model_label.clone(),
                base_frame: options.base_frame,
                split_shared: options.split_shared,
            },
            whole,
            literals: cut_literals,
        })
    }
}
