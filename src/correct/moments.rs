//! When each target is corrected for: the moments a target is reached
//! (one fixed moment, or its times in a schedule) and which visit counts.

use super::When;
use crate::error::{Error, Remedy, Result};
use crate::model::Moment;
use crate::rapid::Program;
use crate::schedule::{Schedule, Visit};
use std::collections::HashSet;

/// The moments a target is reached.
pub(super) fn moments_of(when: &When, id: &str) -> Result<Vec<Moment>> {
    moments_in(when, id, false)
}

/// The moments a jointtarget is reached.
pub(super) fn joint_moments_of(when: &When, id: &str) -> Result<Vec<Moment>> {
    moments_in(when, id, true)
}

pub(super) fn moments_in(when: &When, id: &str, joint: bool) -> Result<Vec<Moment>> {
    match when {
        When::At(m) => Ok(vec![*m]),
        When::Schedule {
            schedule,
            joints,
            default,
        } => match joints
            .as_ref()
            .filter(|_| joint)
            .unwrap_or(schedule)
            .times(id)
        {
            Some(times) => Ok(times.iter().map(|&t| Moment::Minute(t)).collect()),
            None => default.map(|m| vec![m]).ok_or_else(|| {
                Error::input(format!("the schedule has no time for target {id}"))
                    .with_remedy(Remedy::GiveDefaultTime)
            }),
        },
    }
}

/// The moment a robtarget is corrected for: [`pick`] of [`moments_of`],
/// without making the list of its visits (a streamed run asks for a
/// million targets). `times`: its times in `when`'s schedule, looked up
/// by the caller (who needs them too).
pub(super) fn picked_moment(
    when: &When,
    id: &str,
    times: Option<&[f64]>,
    visit: Visit,
) -> Result<Moment> {
    if let (When::Schedule { .. }, Some(times)) = (when, times) {
        return Ok(Moment::Minute(visit.pick(times)));
    }
    // One moment (`--at`, or the default), or the error.
    moments_of(when, id).map(|m| pick(&m, visit))
}

pub(super) fn pick(moments: &[Moment], visit: Visit) -> Moment {
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
    let ids: HashSet<String> = program
        .targets()
        .iter()
        .map(|t| t.id.as_str())
        .chain(program.jointtargets().iter().map(|j| j.id.as_str()))
        .map(str::to_ascii_lowercase)
        .collect();
    for id in schedule.targets() {
        if !ids.contains(&id.to_ascii_lowercase()) {
            return Err(Error::input(format!(
                "the schedule names target `{id}`, which the program does not have"
            )));
        }
    }
    Ok(())
}
