//! The schedule: every visit of every target, read from and written to
//! the `target,time_min` CSV file of `docs/formats.md`, and which
//! visit a correction is for.

use crate::csv_table::CsvTable;
use crate::digest::Encoder;
use crate::error::{Error, Result};
use std::borrow::Cow;
use std::sync::Arc;

/// Which of a target's several visits its correction is computed for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Visit {
    First,
    #[default]
    Mean,
    Last,
}

impl Visit {
    /// The time chosen among `times` (which must not be empty).
    pub fn pick(self, times: &[f64]) -> f64 {
        match self {
            Visit::First => times.iter().copied().fold(f64::INFINITY, f64::min),
            Visit::Last => times.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Visit::Mean => times.iter().sum::<f64>() / times.len() as f64,
        }
    }
}

/// An identifier in lower case, copied only where it is not (a program's
/// inline identifiers, `main#1234`, mostly are: a schedule of a million
/// visits made a million copies).
pub(super) fn lower(id: &str) -> Cow<'_, str> {
    if id.bytes().any(|b| b.is_ascii_uppercase()) {
        Cow::Owned(id.to_ascii_lowercase())
    } else {
        Cow::Borrowed(id)
    }
}

/// When each target is reached: every visit of every target, in minutes.
/// Keys are target identifiers as written (lookups ignore case, as RAPID
/// does).
#[derive(Clone, Default, PartialEq)]
pub struct Schedule {
    /// By lower-case identifier (hashed: a schedule of a million targets
    /// spent most of its time comparing identifiers in a sorted map).
    visits: foldhash::HashMap<Arc<str>, Times>,
    /// Identifiers in first-visit order, for stable output: the map's key
    /// itself where that is in lower case already (a program's inline
    /// targets, `main#1234`), so that a target's first visit allocates
    /// once, not three times (a third of timing a CAM program).
    order: Vec<Arc<str>>,
}

/// A target's visit times: most targets are visited once.
#[derive(Clone, PartialEq)]
enum Times {
    One(f64),
    Many(Vec<f64>),
}

impl Times {
    fn as_slice(&self) -> &[f64] {
        match self {
            Times::One(t) => std::slice::from_ref(t),
            Times::Many(ts) => ts,
        }
    }

    fn push(&mut self, t: f64) {
        match self {
            Times::One(first) => *self = Times::Many(vec![*first, t]),
            Times::Many(ts) => ts.push(t),
        }
    }
}

impl std::fmt::Debug for Schedule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_map()
            .entries(
                self.order
                    .iter()
                    .map(|id| (id, self.times(id).unwrap_or(&[]))),
            )
            .finish()
    }
}

/// The tag of the schedules' byte encoding, and its version: see
/// [`encode_visits`].
pub const SCHEDULE_ENCODING: &str = "rapidtherm schedule 1";

/// A schedule's visits in its byte encoding, version 1 (what a corrected
/// file's marker fingerprints; see `docs/correct.md`): the number of
/// targets (u32), then for each target in first-visit order its
/// identifier in lower case (text: its length in bytes as a u32, then its
/// UTF-8 bytes), its number of visits (u32) and each visit's minute (the
/// bits of an f64), in the order visited; integers little-endian. A
/// target's identifier is compared without regard to case, as RAPID
/// compares names: `P10` and `p10` encode alike.
pub fn encode_visits<'a>(
    e: &mut Encoder,
    targets: usize,
    visits: impl Iterator<Item = (&'a str, &'a [f64])>,
) {
    e.u32(u32::try_from(targets).unwrap_or(u32::MAX));
    for (id, times) in visits {
        e.text(&lower(id));
        e.u32(u32::try_from(times.len()).unwrap_or(u32::MAX));
        for &t in times {
            e.f64(t);
        }
    }
}

impl Schedule {
    pub fn new() -> Schedule {
        Schedule::default()
    }

    /// Record one visit of `target` at `time_min`.
    pub fn visit(&mut self, target: &str, time_min: f64) {
        let key = lower(target);
        if let Some(entry) = self.visits.get_mut(&*key) {
            entry.push(time_min);
            return;
        }
        let id: Arc<str> = Arc::from(target);
        let key = match key {
            Cow::Borrowed(_) => id.clone(),
            Cow::Owned(key) => Arc::from(key),
        };
        self.visits.insert(key, Times::One(time_min));
        self.order.push(id);
    }

    /// Room for `n` more targets.
    pub(crate) fn reserve(&mut self, n: usize) {
        self.visits.reserve(n);
        self.order.reserve(n);
    }

    /// All visit times of a target, in the order recorded.
    pub fn times(&self, target: &str) -> Option<&[f64]> {
        self.visits.get(&*lower(target)).map(Times::as_slice)
    }

    /// Target identifiers in the order they were first visited.
    pub fn targets(&self) -> &[Arc<str>] {
        &self.order
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The schedule in its byte encoding ([`encode_visits`]).
    pub fn encode(&self, e: &mut Encoder) {
        let visits = self
            .order
            .iter()
            .map(|id| (&**id, self.times(id).unwrap_or(&[])));
        encode_visits(e, self.order.len(), visits);
    }

    /// Number of visits of all targets.
    pub fn visit_count(&self) -> usize {
        self.visits.values().map(|t| t.as_slice().len()).sum()
    }

    /// Read a schedule file (`target,time_min`). Several rows may name one
    /// target: each is a visit.
    pub fn read(file: &str, bytes: &[u8]) -> Result<Schedule> {
        let table = CsvTable::parse(file, bytes)?;
        let target = table.require("target")?;
        let time = table.require("time_min")?;
        let mut schedule = Schedule::new();
        for row in &table.rows {
            let name = table.text(row, target)?;
            if name.is_empty() {
                return Err(
                    Error::input("empty target identifier").at(table.field_location(row, target))
                );
            }
            let t = table.number(row, time)?;
            if t < 0.0 {
                return Err(Error::input(format!(
                    "time {t} min is before the cold start (times are minutes since it)"
                ))
                .at(table.field_location(row, time)));
            }
            schedule.visit(name, t);
        }
        Ok(schedule)
    }

    /// The schedule as CSV, one row per visit in time order: the format
    /// [`Schedule::read`] takes back.
    pub fn to_csv(&self) -> String {
        let mut rows: Vec<(f64, usize, &str)> = Vec::new();
        for (i, name) in self.order.iter().enumerate() {
            if let Some(times) = self.times(name) {
                rows.extend(times.iter().map(|&t| (t, i, &**name)));
            }
        }
        csv_of(rows)
    }
}

/// The `target,time_min` file of visits (minutes, the target's place in
/// first-visit order, its identifier), in time order.
pub(super) fn csv_of(mut rows: Vec<(f64, usize, &str)>) -> String {
    rows.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut out = String::from("target,time_min\n");
    for (t, _, name) in rows {
        out.push_str(&csv_field(name));
        out.push_str(&format!(",{t:.4}\n"));
    }
    out
}

/// A CSV field, quoted where it holds a comma or a quote (`pGrid{2,1}`).
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}
