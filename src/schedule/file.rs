//! The schedule: every visit of every target, read from and written to
//! the `target,time_min` CSV file of `docs/formats.md`, and which
//! visit a correction is for.

use crate::csv_table::{CsvRow, CsvTable};
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

/// `f` of `id` in lower case, lowered on the stack where it is short: a
/// million targets looked up by a RobotStudio-style name (`Target_10`)
/// made a million copies.
fn with_lower<R>(id: &str, f: impl FnOnce(&str) -> R) -> R {
    let mut buf = [0u8; 64];
    if let Some(b) = buf.get_mut(..id.len()) {
        b.copy_from_slice(id.as_bytes());
        b.make_ascii_lowercase();
        // Lowering ASCII letters keeps UTF-8 valid.
        if let Ok(key) = std::str::from_utf8(b) {
            return f(key);
        }
    }
    f(&lower(id))
}

/// A span of time over which the robot stands (no program running, the
/// motors cooling): `[from_min, to_min)` since the cold start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IdleSpan {
    pub from_min: f64,
    pub to_min: f64,
}

/// When each target is reached: every visit of every target, in minutes,
/// and the spans over which the robot stood. Keys are target identifiers
/// as written (lookups ignore case, as RAPID does).
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
    /// The idle spans, in increasing time, none overlapping another and
    /// none holding a visit (a robot that stands reaches no target).
    idle: Vec<IdleSpan>,
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
        let seen = with_lower(target, |key| match self.visits.get_mut(key) {
            Some(entry) => {
                entry.push(time_min);
                true
            }
            None => false,
        });
        if seen {
            return;
        }
        let key = lower(target);
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
        with_lower(target, |key| self.visits.get(key).map(Times::as_slice))
    }

    /// Target identifiers in the order they were first visited.
    pub fn targets(&self) -> &[Arc<str>] {
        &self.order
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The spans over which the robot stood, in increasing time.
    pub fn idle_spans(&self) -> &[IdleSpan] {
        &self.idle
    }

    /// Add the idle spans `spans` (checked as [`Schedule::read`] checks a
    /// file's: in increasing time, not overlapping, holding no visit).
    pub fn set_idle_spans(&mut self, spans: Vec<IdleSpan>) -> Result<()> {
        check_spans(&spans)?;
        for (id, t) in self
            .order
            .iter()
            .flat_map(|id| self.times(id).unwrap_or(&[]).iter().map(move |&t| (id, t)))
        {
            if let Some(span) = span_holding(&spans, t) {
                return Err(visit_in_span(id, t, span));
            }
        }
        self.idle = spans;
        Ok(())
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

    /// Read a schedule file (`target,time_min[,kind][,end_min]`). Several
    /// rows may name one target: each is a visit. A row of kind `idle` is
    /// a span over which the robot stood, from `time_min` to `end_min`
    /// (its target left empty).
    pub fn read(file: &str, bytes: &[u8]) -> Result<Schedule> {
        let table = CsvTable::parse(file, bytes)?;
        let target = table.require("target")?;
        let time = table.require("time_min")?;
        let kind = table.column("kind");
        let end = table.column("end_min");
        let mut schedule = Schedule::new();
        // Each idle span with the row it came from, for the errors of
        // the checks that need every span and visit.
        let mut spans: Vec<(IdleSpan, usize)> = Vec::new();
        let mut visits: Vec<(usize, f64)> = Vec::new();
        let end_of = |row: &CsvRow| -> Result<Option<f64>> {
            match end {
                Some(e) if !field(row, end).is_empty() => table.number(row, e).map(Some),
                _ => Ok(None),
            }
        };
        for (r, row) in table.rows.iter().enumerate() {
            let name = table.text(row, target)?;
            let t = table.number(row, time)?;
            if t < 0.0 {
                return Err(Error::input(format!(
                    "time {t} min is before the cold start (times are minutes since it)"
                ))
                .at(table.field_location(row, time)));
            }
            let row_kind = RowKind::parse(field(row, kind)).ok_or_else(|| {
                Error::input(format!(
                    "unknown kind `{}` (known: idle, robtarget, jointtarget, or empty for a visit)",
                    field(row, kind)
                ))
                .at(table.field_location(row, kind.unwrap_or(target)))
            })?;
            match row_kind {
                RowKind::Idle => {
                    if !name.is_empty() {
                        return Err(Error::input(
                            "an idle span names no target (leave `target` empty)",
                        )
                        .at(table.field_location(row, target)));
                    }
                    let to = end_of(row)?.ok_or_else(|| {
                        Error::input("an idle span needs its end, `end_min`")
                            .at(table.field_location(row, end.unwrap_or(time)))
                    })?;
                    if to <= t {
                        return Err(Error::input(format!(
                            "an idle span ends at minute {to}, not after its start {t}"
                        ))
                        .at(table.field_location(row, end.unwrap_or(time))));
                    }
                    spans.push((
                        IdleSpan {
                            from_min: t,
                            to_min: to,
                        },
                        r,
                    ));
                }
                RowKind::Visit => {
                    if name.is_empty() {
                        return Err(Error::input("empty target identifier")
                            .at(table.field_location(row, target)));
                    }
                    if let (Some(e), Some(_)) = (end, end_of(row)?) {
                        return Err(Error::input(
                            "a visit has no end: `end_min` belongs to idle spans",
                        )
                        .at(table.field_location(row, e)));
                    }
                    schedule.visit(name, t);
                    visits.push((r, t));
                }
            }
        }
        spans.sort_by(|a, b| a.0.from_min.total_cmp(&b.0.from_min));
        for pair in spans.windows(2) {
            if pair[1].0.from_min < pair[0].0.to_min {
                let row = &table.rows[pair[1].1];
                return Err(Error::input(format!(
                    "this idle span (from minute {}) overlaps the one from minute {} to {}",
                    pair[1].0.from_min, pair[0].0.from_min, pair[0].0.to_min
                ))
                .at(table.field_location(row, time)));
            }
        }
        let only: Vec<IdleSpan> = spans.iter().map(|(s, _)| *s).collect();
        for (r, t) in visits {
            if let Some(span) = span_holding(&only, t) {
                let row = &table.rows[r];
                let name = table.text(row, target)?;
                return Err(visit_in_span(name, t, span).at(table.field_location(row, time)));
            }
        }
        schedule.idle = only;
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
        let visits = csv_of(rows);
        if self.idle.is_empty() {
            return visits;
        }
        // With stops, the two columns that say them; the visits' rows
        // leave them empty.
        let mut out = String::from("target,time_min,kind,end_min\n");
        for line in visits.lines().skip(1) {
            out.push_str(line);
            out.push_str(",,\n");
        }
        for s in &self.idle {
            out.push_str(&format!(",{:.4},idle,{:.4}\n", s.from_min, s.to_min));
        }
        out
    }
}

/// An optional column's field, trimmed; empty where the column is absent
/// or the row ends before it (`p10,1.5` in a file whose header names it).
fn field(row: &CsvRow, col: Option<usize>) -> &str {
    col.and_then(|c| row.fields.get(c)).map_or("", |f| f.trim())
}

/// What a schedule row is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RowKind {
    /// A visit of a target (no kind, or the target's kind).
    Visit,
    /// A span over which the robot stood.
    Idle,
}

impl RowKind {
    fn parse(text: &str) -> Option<RowKind> {
        let t = text.trim();
        if t.is_empty()
            || t.eq_ignore_ascii_case("robtarget")
            || t.eq_ignore_ascii_case("jointtarget")
        {
            Some(RowKind::Visit)
        } else if t.eq_ignore_ascii_case("idle") {
            Some(RowKind::Idle)
        } else {
            None
        }
    }
}

/// Spans in increasing time, none overlapping the next.
fn check_spans(spans: &[IdleSpan]) -> Result<()> {
    for s in spans {
        if !(s.from_min >= 0.0 && s.to_min > s.from_min && s.to_min.is_finite()) {
            return Err(Error::input(format!(
                "an idle span from minute {} to {} is not a span after the cold start",
                s.from_min, s.to_min
            )));
        }
    }
    for pair in spans.windows(2) {
        if pair[1].from_min < pair[0].to_min {
            return Err(Error::input(format!(
                "the idle span from minute {} overlaps the one from minute {} to {}",
                pair[1].from_min, pair[0].from_min, pair[0].to_min
            )));
        }
    }
    Ok(())
}

/// The span that holds minute `t` strictly inside (a visit at a span's
/// start or end is the last before the stop or the first after it).
fn span_holding(spans: &[IdleSpan], t: f64) -> Option<IdleSpan> {
    let k = spans.partition_point(|s| s.from_min < t);
    k.checked_sub(1).map(|i| spans[i]).filter(|s| t < s.to_min)
}

fn visit_in_span(target: &str, t: f64, span: IdleSpan) -> Error {
    Error::input(format!(
        "target `{target}` is reached at minute {t}, while the robot stands (idle from minute {} to {})",
        span.from_min, span.to_min
    ))
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
