//! When each target is corrected for: the moments a target is reached
//! (one fixed moment, or its times in a schedule) and which visit counts.

use super::When;
use crate::error::{Error, Remedy, Result, Subject};
use crate::model::Moment;
use crate::rapid::Program;
use crate::schedule::{Schedule, WhichVisit};
use smallvec::SmallVec;

/// The moments a target is reached: most are reached at one (every one
/// at a fixed moment), held without an allocation each.
pub(super) type Moments = SmallVec<[Moment; 2]>;

/// The moments robtarget `index` (identifier `id`) is reached.
pub(super) fn moments_of(when: &When, index: usize, id: &str) -> Result<Moments> {
    moments_in(when, index, id, false)
}

/// The moments jointtarget `index` (identifier `id`) is reached.
pub(super) fn joint_moments_of(when: &When, index: usize, id: &str) -> Result<Moments> {
    moments_in(when, index, id, true)
}

/// The moments target `index` of its kind (a jointtarget's where `joint`)
/// is reached: by its number where the schedule was recorded by number
/// (an estimate's), else by its identifier `id`.
pub(super) fn moments_in(when: &When, index: usize, id: &str, joint: bool) -> Result<Moments> {
    match when {
        When::At(m) => Ok(smallvec::smallvec![*m]),
        When::Schedule {
            schedule,
            joints,
            default,
            ..
        } => match joints
            .as_ref()
            .filter(|_| joint)
            .unwrap_or(schedule)
            .times_of(index, id)
        {
            Some(times) => Ok(times.iter().map(|&t| Moment::Minute(t)).collect()),
            // The target is the error's subject, not its message: a
            // schedule that misses 20,000 targets is one cause, said once
            // with the others counted.
            None => default.map(|m| smallvec::smallvec![m]).ok_or_else(|| {
                let subject = if joint {
                    Subject::JointTarget(id.to_string())
                } else {
                    Subject::Target(id.to_string())
                };
                Error::input("the schedule has no time for it")
                    .about(subject)
                    .with_remedy(Remedy::GiveDefaultTime)
            }),
        },
    }
}

pub(super) fn pick(moments: &[Moment], visit: WhichVisit) -> Moment {
    // One moment (every target of a run at a fixed moment): no list made.
    if let [Moment::Minute(t)] = moments {
        return Moment::Minute(visit.pick(&[*t]));
    }
    let minutes: Vec<f64> = moments
        .iter()
        .filter_map(|m| match m {
            Moment::Minute(t) => Some(*t),
            Moment::Steady => None,
        })
        .collect();
    if minutes.len() < moments.len() || minutes.is_empty() {
        Moment::Steady
    } else {
        Moment::Minute(visit.pick(&minutes))
    }
}

pub(super) fn minute_of(m: Moment) -> Option<f64> {
    match m {
        Moment::Minute(t) => Some(t),
        Moment::Steady => None,
    }
}

/// Every identifier of the schedule must name a target of the program.
/// The program's identifiers are gathered once (lower case, as RAPID
/// ignores case): a lookup per schedule entry in the list of targets made
/// a schedule of every target quadratic.
pub(super) fn check_schedule_names(program: &Program, schedule: &Schedule) -> Result<()> {
    // Identifiers only: the targets' numbers are not read for this.
    let targets = program.targets();
    let mut ids: foldhash::HashSet<String> = foldhash::HashSet::default();
    ids.reserve(targets.len() + program.jointtargets().len());
    let mut id = String::new();
    for i in 0..targets.len() {
        if targets.id_into(i, &mut id).is_some() {
            id.make_ascii_lowercase();
            ids.insert(std::mem::take(&mut id));
        }
    }
    ids.extend(
        program
            .jointtargets()
            .iter()
            .map(|j| j.id.to_ascii_lowercase()),
    );
    for id in schedule.targets() {
        if !ids.contains(&id.to_ascii_lowercase()) {
            return Err(Error::input(format!(
                "the schedule names target `{id}`, which the program does not have"
            )));
        }
    }
    Ok(())
}
