//! The schedule: every visit of every target, read from and written to
//! the `target,time_min` CSV file of `docs/formats.md`, and which
//! visit a correction is for.

use crate::csv_table::CsvTable;
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

/// As the sorted map the visits were kept in: a corrected file's marker
/// records a schedule by a fingerprint of this text.
impl std::fmt::Debug for Schedule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let order: Vec<&str> = self.order.iter().map(|id| &**id).collect();
        fmt_visits(f, self.entries(), &order)
    }
}

/// A schedule's `Debug` text from its visits by lower-case identifier
/// (in any order) and its identifiers in first-visit order.
pub(super) fn fmt_visits(
    f: &mut std::fmt::Formatter<'_>,
    visits: Vec<(&str, &[f64])>,
    order: &[&str],
) -> std::fmt::Result {
    use std::fmt::Write;
    // Sorted by their first 16 bytes as one number first: a program's
    // identifiers share long prefixes (`main#1234`), and comparing
    // them byte by byte was half of fingerprinting a schedule.
    let mut keyed: Vec<_> = visits
        .into_iter()
        .map(|(k, v)| (leading_bytes(k), k, v))
        .collect();
    keyed.sort_unstable_by(|a, b| a.0.cmp(&b.0).then_with(|| a.1.cmp(b.1)));
    if f.alternate() {
        /// The visits in key order, written as a map.
        struct Sorted<'a>(Vec<(&'a str, &'a [f64])>);
        impl std::fmt::Debug for Sorted<'_> {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.debug_map().entries(self.0.iter().copied()).finish()
            }
        }
        let sorted = keyed.into_iter().map(|(_, k, v)| (k, v)).collect();
        return f
            .debug_struct("Schedule")
            .field("visits", &Sorted(sorted))
            .field("order", &order)
            .finish();
    }
    // The text the builders write (`Schedule { visits: {"a": [1.0]},
    // order: ["A"] }`), put together here and passed on a page at a
    // time: through the builders, a million targets' pieces were a
    // hundred million calls, most of fingerprinting a schedule.
    let mut page = String::with_capacity(PAGE + 256);
    page.push_str("Schedule { visits: {");
    for (i, (_, k, v)) in keyed.iter().enumerate() {
        if i > 0 {
            page.push_str(", ");
        }
        write!(page, "{k:?}: [")?;
        for (j, t) in v.iter().enumerate() {
            if j > 0 {
                page.push_str(", ");
            }
            write!(page, "{t:?}")?;
        }
        page.push(']');
        if page.len() >= PAGE {
            f.write_str(&page)?;
            page.clear();
        }
    }
    page.push_str("}, order: [");
    for (i, id) in order.iter().enumerate() {
        if i > 0 {
            page.push_str(", ");
        }
        write!(page, "{id:?}")?;
        if page.len() >= PAGE {
            f.write_str(&page)?;
            page.clear();
        }
    }
    page.push_str("] }");
    f.write_str(&page)
}

/// Bytes of a schedule's `Debug` text passed on at once.
const PAGE: usize = 1 << 15;

/// The first 16 bytes of `s` as a big-endian number, zeros after its end:
/// two strings whose numbers differ are in the order of their numbers
/// (equal numbers say nothing).
fn leading_bytes(s: &str) -> u128 {
    let mut b = [0u8; 16];
    let n = s.len().min(16);
    b[..n].copy_from_slice(&s.as_bytes()[..n]);
    u128::from_be_bytes(b)
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

    /// Every target's visits, by lower-case identifier, in no order.
    pub(super) fn entries(&self) -> Vec<(&str, &[f64])> {
        self.visits
            .iter()
            .map(|(k, v)| (&**k, v.as_slice()))
            .collect()
    }

    /// Target identifiers in the order they were first visited.
    pub fn targets(&self) -> &[Arc<str>] {
        &self.order
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
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
