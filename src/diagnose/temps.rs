//! Where the temperatures that drive the thermal effects come from, and
//! the rule that none is assumed: a thermal effect is a candidate only
//! where the data carry motor temperatures, the model names a heating
//! record of this arm, or the caller says that the session starts cold and
//! follows a named profile. Otherwise every row is held at the reference
//! temperature (no heating of another arm drives anything) and a change
//! over time is a drift in time ([`super::drift`]).

use super::fit::Problem;
use crate::error::{Error, Result};
use crate::thermal::TempHistory;
use serde::Serialize;

/// Where the rows' temperatures were taken from when the data were
/// prepared ([`super::prepare::Prepared::temps`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TempOrigin {
    /// The data's motor-temperature columns.
    Measured,
    /// The model's heating record (`[heating] recording`), a path.
    Recording(String),
    /// The model's heating profile by name (`[heating] profile`): a warm-up
    /// from a cold start at the first row, which the data do not say.
    Profile(String),
}

/// A warm-up profile the caller may say the session follows from a cold
/// start at its first row (`--assume-cold-start PROFILE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColdStart {
    /// The embedded IRB 140 warm-up (`data/irb140/heating.toml`), the
    /// model file's `profile = "default"`.
    Irb140,
}

impl ColdStart {
    /// Every profile by its name.
    pub const ALL: [ColdStart; 1] = [ColdStart::Irb140];

    /// The name the caller gives.
    pub fn name(self) -> &'static str {
        match self {
            ColdStart::Irb140 => "irb140",
        }
    }

    /// The model file's name of the same profile.
    fn model_profile(self) -> &'static str {
        match self {
            ColdStart::Irb140 => "default",
        }
    }

    /// The profile named `name` (`irb140`, or the model file's `default`).
    pub fn from_name(name: &str) -> Result<ColdStart> {
        ColdStart::ALL
            .into_iter()
            .find(|c| c.name() == name || c.model_profile() == name)
            .ok_or_else(|| {
                Error::usage(format!(
                    "unknown warm-up profile `{name}` (known: {})",
                    ColdStart::ALL.map(|c| c.name()).join(", ")
                ))
            })
    }
}

/// Which source drove the temperatures of a diagnosis (JSON
/// `temperatures`).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "source", rename_all = "kebab-case")]
pub enum TempSource {
    /// The data's motor-temperature columns.
    Measured,
    /// The heating record the model names.
    HeatingRecord { recording: String },
    /// Assumed, as the caller said: the session starts cold at its first
    /// row and follows this profile.
    AssumedColdStart { profile: String },
    /// None: no temperature columns, no heating record, and no cold start
    /// said. No thermal effect is a candidate; the rows are held at the
    /// reference temperature.
    None,
}

impl TempSource {
    /// The source of a diagnosis of rows prepared from `origin`, with the
    /// caller's `cold_start`. A cold start said for another profile than
    /// the model's is refused.
    pub fn of(origin: &TempOrigin, cold_start: Option<ColdStart>) -> Result<TempSource> {
        Ok(match (origin, cold_start) {
            (TempOrigin::Measured, _) => TempSource::Measured,
            (TempOrigin::Recording(r), _) => TempSource::HeatingRecord {
                recording: r.clone(),
            },
            (TempOrigin::Profile(p), Some(c)) if c.model_profile() == p => {
                TempSource::AssumedColdStart {
                    profile: c.name().to_string(),
                }
            }
            (TempOrigin::Profile(p), Some(c)) => {
                return Err(Error::usage(format!(
                    "the session is said to follow the `{}` warm-up, but the model's heating profile is `{p}`",
                    c.name()
                )))
            }
            (TempOrigin::Profile(_), None) => TempSource::None,
        })
    }

    /// Whether temperatures drive anything: thermal effects are candidates.
    pub fn drives(&self) -> bool {
        *self != TempSource::None
    }

    /// The source in words, for the report.
    pub fn words(&self) -> String {
        match self {
            TempSource::Measured => "Temperatures: the data's motor-temperature columns.".into(),
            TempSource::HeatingRecord { recording } => {
                format!("Temperatures: the model's heating record `{recording}` (no temperature columns in the data).")
            }
            TempSource::AssumedColdStart { profile } => format!(
                "Temperatures: assumed, as asked: the session starts cold at its first row and follows the `{profile}` warm-up (no temperature columns in the data)."
            ),
            TempSource::None => "Temperatures: none (no temperature columns, no heating record, no cold start said): no thermal effect is a candidate, and a change over time is reported as a drift in time.".into(),
        }
    }
}

/// The rule for rows prepared from `origin` (the one rule of the
/// diagnosis, of its saved model's score and of `gap`): where nothing says
/// where the temperatures come from (no columns, no heating record, no
/// cold start said by `cold_start`), every row of `problem` is held at the
/// reference temperature. Returns the source the rows now follow.
pub fn as_said(
    problem: &mut Problem,
    origin: &TempOrigin,
    cold_start: Option<ColdStart>,
) -> Result<TempSource> {
    let source = TempSource::of(origin, cold_start)?;
    if !source.drives() {
        *problem = held_cold(problem);
    }
    Ok(source)
}

/// `problem` with every row at the reference temperature: nothing heats.
pub fn held_cold(problem: &Problem) -> Problem {
    let t_ref = problem.base.thermal.t_ref;
    let mut p = problem.clone();
    for r in &mut p.rows {
        r.temps = [t_ref; 6];
    }
    let recs: Vec<_> = p.rows.iter().map(|r| (r.time_min, r.temps)).collect();
    p.history = TempHistory::from_records(&recs, t_ref);
    p
}
