//! The schedule: every visit of every target, read from and written to
//! the `target,time_min` CSV file of `docs/formats.md`, and which
//! visit a correction is for.

use super::names::{ProgramNames, TargetType};
use crate::csv_table::{Columns, CsvRow, CsvTable};
use crate::digest::Encoder;
use crate::error::{Error, Result};
use std::borrow::Cow;
use std::sync::{Arc, OnceLock};

/// Which of a target's several visits its correction is computed for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WhichVisit {
    First,
    #[default]
    Mean,
    Last,
}

impl WhichVisit {
    /// The time chosen among `times` (which must not be empty).
    pub fn pick(self, times: &[f64]) -> f64 {
        match self {
            WhichVisit::First => times.iter().copied().fold(f64::INFINITY, f64::min),
            WhichVisit::Last => times.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            WhichVisit::Mean => times.iter().sum::<f64>() / times.len() as f64,
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

/// A span of time over which the robot stands (no program running, the
/// motors cooling): `[from_min, to_min)` since the cold start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IdleSpan {
    pub from_min: f64,
    pub to_min: f64,
}

/// When each target is reached: every visit of every target, in minutes,
/// and the spans over which the robot stood. Identifiers are kept as
/// written (lookups ignore case, as RAPID does).
#[derive(Clone, Default)]
pub struct Schedule {
    /// Identifiers in first-visit order, for stable output; `None`: a
    /// target recorded by number and not yet named
    /// ([`Schedule::visit_number`]).
    order: Vec<Option<Arc<str>>>,
    /// Each identifier's visits, place by place with `order`.
    visits: Vec<Times>,
    /// How a target's place in `order` is found (behind a pointer: a
    /// run's time basis holds two schedules by value).
    lookups: Box<Lookups>,
    /// The idle spans, in increasing time, none overlapping another and
    /// none holding a visit (a robot that stands reaches no target).
    idle: Vec<IdleSpan>,
}

/// How a target's place in a schedule's `order` is found.
#[derive(Clone)]
struct Lookups {
    /// Places by identifier (compared without case), made when a lookup
    /// by name first needs it: a schedule an estimate recorded by target
    /// number is read by target number, and hashing its million names
    /// five times over was a fifth of `--start`.
    by_name: OnceLock<hashbrown::HashTable<u32>>,
    /// A program's target number to its place plus one (0: not visited):
    /// where the schedule was recorded by target number
    /// ([`Schedule::visit_target`]).
    by_target: Vec<u32>,
}

impl Default for Lookups {
    fn default() -> Lookups {
        Lookups {
            by_name: OnceLock::new(),
            by_target: Vec::new(),
        }
    }
}

/// Two schedules are equal when they hold the same visits in the same
/// first-visit order and the same idle spans, however they were recorded.
impl PartialEq for Schedule {
    fn eq(&self, other: &Self) -> bool {
        self.order == other.order && self.visits == other.visits && self.idle == other.idle
    }
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
            .entries(self.targets().zip(self.visits.iter().map(Times::as_slice)))
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

/// The hash of an identifier as RAPID compares names (the program's own
/// table of names hashes alike).
fn name_hash(id: &str) -> u64 {
    crate::rapid::targets::name_hash(id.as_bytes())
}

/// The identifier at a place of `order` (a target not yet named: none,
/// the empty text).
fn id_of(place: &Option<Arc<str>>) -> &str {
    place.as_deref().unwrap_or("")
}

/// The table of places by identifier of `order`.
fn name_table(order: &[Option<Arc<str>>]) -> hashbrown::HashTable<u32> {
    let mut table = hashbrown::HashTable::with_capacity(order.len());
    for (k, id) in order.iter().enumerate() {
        // Places fit a u32: a schedule holds fewer targets than that.
        table.insert_unique(name_hash(id_of(id)), k as u32, |&j: &u32| {
            name_hash(id_of(&order[j as usize]))
        });
    }
    table
}

impl Schedule {
    pub fn new() -> Schedule {
        Schedule::default()
    }

    /// The place of identifier `id` in `order`.
    fn place(&self, id: &str) -> Option<usize> {
        let table = self.lookups.by_name.get_or_init(|| name_table(&self.order));
        table
            .find(name_hash(id), |&k| {
                id_of(&self.order[k as usize]).eq_ignore_ascii_case(id)
            })
            .map(|&k| k as usize)
    }

    /// A new identifier at the end of `order` (none: to be named), with
    /// its first visit.
    fn push_new(&mut self, id: Option<Arc<str>>, time_min: f64) -> usize {
        let k = self.order.len();
        if let Some(table) = self.lookups.by_name.get_mut() {
            let order = &self.order;
            table.insert_unique(name_hash(id_of(&id)), k as u32, |&j: &u32| {
                name_hash(id_of(&order[j as usize]))
            });
        }
        self.order.push(id);
        self.visits.push(Times::One(time_min));
        k
    }

    /// Record one visit of `target` at `time_min`.
    pub fn visit(&mut self, target: &str, time_min: f64) {
        match self.place(target) {
            Some(k) => self.visits[k].push(time_min),
            None => {
                self.push_new(Some(Arc::from(target)), time_min);
            }
        }
    }

    /// Record one visit of the program's target number `index`, whose
    /// identifier `id` gives (asked for at its first visit only), at
    /// `time_min`. The identifiers of a program's targets are unique in
    /// it, so a schedule recorded this way is read by target number
    /// ([`Schedule::times_of`]) without looking up names.
    pub fn visit_target(&mut self, index: usize, time_min: f64, id: impl FnOnce() -> Arc<str>) {
        self.visit_place(index, time_min, || Some(id()));
    }

    /// A visit of target number `index`, its identifier (where it has one
    /// yet) asked for at its first visit only.
    fn visit_place(&mut self, index: usize, time_min: f64, id: impl FnOnce() -> Option<Arc<str>>) {
        let by_target = &mut self.lookups.by_target;
        if by_target.len() <= index {
            by_target.resize(index + 1, 0);
        }
        match by_target[index] {
            0 => {
                let k = self.push_new(id(), time_min);
                self.lookups.by_target[index] = k as u32 + 1;
            }
            k => self.visits[k as usize - 1].push(time_min),
        }
    }

    /// [`Schedule::visit_target`] without the identifier, which
    /// [`Schedule::name_targets`] gives every such target afterwards, on
    /// every core: reading a million identifiers one visit at a time was
    /// a tenth of a walk's time, on one core. Until then, the target is
    /// found by its number alone.
    pub(crate) fn visit_number(&mut self, index: usize, time_min: f64) {
        // No identifier, not a shared empty one: a clone of one `Arc` per
        // visit waited for its count's cache line wherever another core
        // touched a neighbour of it (a tenth of a walk, by chance of the
        // heap's layout).
        self.visit_place(index, time_min, || None);
    }

    /// The identifiers of the targets [`Schedule::visit_number`]
    /// recorded, from `id` of their numbers.
    pub(crate) fn name_targets(&mut self, id: impl Fn(usize) -> Arc<str> + Sync) {
        use rayon::prelude::*;
        let mut numbers = vec![usize::MAX; self.order.len()];
        for (i, &k) in self.lookups.by_target.iter().enumerate() {
            if k > 0 {
                numbers[k as usize - 1] = i;
            }
        }
        self.order
            .par_iter_mut()
            .zip(numbers.par_iter())
            .with_min_len(4096)
            .filter(|(o, &i)| i != usize::MAX && o.is_none())
            .for_each(|(o, &i)| *o = Some(id(i)));
        if self.lookups.by_name.get().is_some() {
            self.lookups.by_name = OnceLock::new();
        }
    }

    /// Room for `n` more targets.
    pub(crate) fn reserve(&mut self, n: usize) {
        self.order.reserve(n);
        self.visits.reserve(n);
    }

    /// All visit times of a target, in the order recorded.
    pub fn times(&self, target: &str) -> Option<&[f64]> {
        self.place(target).map(|k| self.visits[k].as_slice())
    }

    /// Whether the program's target number `index` was visited as such
    /// ([`Schedule::visit_target`], [`Schedule::visit_number`]): once its
    /// identifier is given, [`Schedule::times_of`] finds its visits.
    pub(crate) fn has_number(&self, index: usize) -> bool {
        self.lookups.by_target.get(index).is_some_and(|&k| k > 0)
    }

    /// All visit times of the program's target number `index`, whose
    /// identifier is `id`: by number where the schedule was recorded by
    /// number and the identifier there is the same (a schedule of another
    /// program is read by name), else by name.
    pub fn times_of(&self, index: usize, id: &str) -> Option<&[f64]> {
        if let Some(&k) = self.lookups.by_target.get(index) {
            let k = k as usize;
            if k > 0 && id_of(&self.order[k - 1]).eq_ignore_ascii_case(id) {
                return Some(self.visits[k - 1].as_slice());
            }
        }
        self.times(id)
    }

    /// Every visit's minute, target by target.
    pub fn all_times(&self) -> impl Iterator<Item = f64> + '_ {
        self.visits
            .iter()
            .flat_map(|t| t.as_slice().iter().copied())
    }

    /// Target identifiers in the order they were first visited.
    pub fn targets(&self) -> impl ExactSizeIterator<Item = &str> + '_ {
        self.order.iter().map(id_of)
    }

    /// Identifiers in first-visit order, each with its visit times.
    pub fn entries(&self) -> impl Iterator<Item = (&str, &[f64])> + '_ {
        self.targets().zip(self.visits.iter().map(Times::as_slice))
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
            .entries()
            .flat_map(|(id, times)| times.iter().map(move |&t| (id, t)))
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
        encode_visits(e, self.order.len(), self.entries());
    }

    /// Number of visits of all targets.
    pub fn visit_count(&self) -> usize {
        self.visits.iter().map(|t| t.as_slice().len()).sum()
    }

    /// Read a schedule file (`target,time_min[,kind][,end_min]`). Several
    /// rows may name one target: each is a visit. A row of kind `idle` is
    /// a span over which the robot stood, from `time_min` to `end_min`
    /// (its target left empty). Every visit row is taken, whatever its
    /// kind: [`Schedule::read_file`] keeps the two name spaces apart and
    /// checks the rows against a program.
    pub fn read(file: &str, bytes: &[u8]) -> Result<Schedule> {
        let rows = read_rows(file, bytes, None)?;
        Ok(rows.build(|_| true))
    }

    /// Read a schedule file as [`Schedule::read`] does, keeping the
    /// robtargets' and the jointtargets' visits apart where any row says
    /// its kind (`joints` is then the jointtargets' visits: the rows of
    /// kind `jointtarget` and those without a kind; `schedule` the
    /// others). Given `names`, the program's, every row must name a target
    /// of the program of its kind, and a row without a kind a target of
    /// one kind, not of both; each error at its row.
    pub fn read_file(
        file: &str,
        bytes: &[u8],
        names: Option<&ProgramNames>,
    ) -> Result<ScheduleFile> {
        let rows = read_rows(file, bytes, names)?;
        let typed = rows.visits.iter().any(|v| v.1.is_some());
        let (schedule, joints) = if typed {
            (
                rows.build(|k| k != Some(TargetType::Jointtarget)),
                Some(rows.build(|k| k != Some(TargetType::Robtarget))),
            )
        } else {
            (rows.build(|_| true), None)
        };
        Ok(ScheduleFile {
            schedule,
            joints,
            warnings: rows.warnings,
        })
    }

    /// The schedule as CSV, one row per visit in time order: the format
    /// [`Schedule::read`] takes back.
    pub fn to_csv(&self) -> String {
        let mut rows: Vec<(f64, usize, &str)> = Vec::new();
        for (i, (name, times)) in self.entries().enumerate() {
            rows.extend(times.iter().map(|&t| (t, i, name)));
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

/// A schedule file read: the robtargets' visits, the jointtargets'
/// where the file keeps them apart, and what the reader assumed.
#[derive(Debug, Clone, PartialEq)]
pub struct ScheduleFile {
    /// The robtargets' visits (every visit where no row says its kind).
    pub schedule: Schedule,
    /// The jointtargets' visits, where a row says its kind; `None`: they
    /// are looked up in `schedule`.
    pub joints: Option<Schedule>,
    /// Columns ignored, for the caller to show.
    pub warnings: Vec<String>,
}

/// The columns of a schedule file.
const COLUMNS: Columns<'static> = Columns {
    required: &["target", "time_min"],
    optional: &["kind", "end_min"],
    // `p10,120` under `target,time_min,kind,end_min`: a visit leaves the
    // idle spans' columns empty (docs/formats.md's example).
    short_rows: true,
};

/// A schedule file's rows, checked: each visit's row, kind and minute.
struct Rows {
    table: CsvTable,
    target: usize,
    visits: Vec<(usize, Option<TargetType>, f64)>,
    idle: Vec<IdleSpan>,
    warnings: Vec<String>,
}

impl Rows {
    /// The schedule of the visits whose kind `keep` takes, with the idle
    /// spans.
    fn build(&self, keep: impl Fn(Option<TargetType>) -> bool) -> Schedule {
        let mut schedule = Schedule::new();
        for &(r, kind, t) in &self.visits {
            if keep(kind) {
                schedule.visit(&self.table.rows[r].fields[self.target], t);
            }
        }
        schedule.idle = self.idle.clone();
        schedule
    }
}

/// The rows of a schedule file, every one checked (against the
/// program's `names` where given).
fn read_rows(file: &str, bytes: &[u8], names: Option<&ProgramNames>) -> Result<Rows> {
    let mut table = CsvTable::read(file, bytes, &COLUMNS)?;
    let target = table.require("target")?;
    let time = table.require("time_min")?;
    let kind = table.column("kind");
    let end = table.column("end_min");
    // Each idle span with the row it came from, for the errors of the
    // checks that need every span and visit.
    let mut spans: Vec<(IdleSpan, usize)> = Vec::new();
    let mut visits: Vec<(usize, Option<TargetType>, f64)> = Vec::new();
    let end_of = |row: &CsvRow| -> Result<Option<f64>> {
        match end {
            Some(e) if !field(row, end).is_empty() => table.number(row, e).map(Some),
            _ => Ok(None),
        }
    };
    for (r, row) in table.rows.iter().enumerate() {
        let name = table.text(row, target)?;
        let t = table.number(row, time)?;
        let row_kind = RowKind::parse(field(row, kind)).ok_or_else(|| {
            Error::input(format!(
                "unknown kind `{}` (known: idle, robtarget, jointtarget, or empty for a visit)",
                excerpt(field(row, kind))
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
            RowKind::WhichVisit(target_kind) => {
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
                if let Some(names) = names {
                    check_name(names, name, target_kind)
                        .map_err(|e| e.at(table.field_location(row, target)))?;
                }
                visits.push((r, target_kind, t));
            }
        }
    }
    spans.sort_by(|a, b| a.0.from_min.total_cmp(&b.0.from_min));
    for pair in spans.windows(2) {
        // A span that begins where another ends is one stop written as
        // two, or a typo of a time: neither may touch.
        if pair[1].0.from_min <= pair[0].0.to_min {
            let row = &table.rows[pair[1].1];
            let how = if pair[1].0.from_min < pair[0].0.to_min {
                "overlaps"
            } else {
                "touches"
            };
            return Err(Error::input(format!(
                "this idle span (from minute {}) {how} the one from minute {} to {}: spans may neither overlap nor touch (one stop is one span)",
                pair[1].0.from_min, pair[0].0.from_min, pair[0].0.to_min
            ))
            .at(table.field_location(row, time)));
        }
    }
    let only: Vec<IdleSpan> = spans.iter().map(|(s, _)| *s).collect();
    for &(r, _, t) in &visits {
        if let Some(span) = span_holding(&only, t) {
            let row = &table.rows[r];
            let name = table.text(row, target)?;
            return Err(visit_in_span(name, t, span).at(table.field_location(row, time)));
        }
    }
    let warnings = std::mem::take(&mut table.warnings);
    Ok(Rows {
        table,
        target,
        visits,
        idle: only,
        warnings,
    })
}

/// Whether the program's `names` hold `id` as a row of `kind` means it:
/// of that kind, or, without a kind, of one kind only.
fn check_name(names: &ProgramNames, id: &str, kind: Option<TargetType>) -> Result<()> {
    let shown = excerpt(id);
    match kind {
        Some(k) if names.has(k, id) => Ok(()),
        Some(k) => {
            let other = match k {
                TargetType::Robtarget => TargetType::Jointtarget,
                TargetType::Jointtarget => TargetType::Robtarget,
            };
            let mut why = format!(
                "this row names {} `{shown}`, which the program does not have",
                k.name()
            );
            if names.has(other, id) {
                why.push_str(&format!(
                    " (it has a {} of that name: its visits are not this one's)",
                    other.name()
                ));
            }
            Err(Error::input(why))
        }
        None => match (
            names.has(TargetType::Robtarget, id),
            names.has(TargetType::Jointtarget, id),
        ) {
            (true, false) | (false, true) => Ok(()),
            (true, true) => Err(Error::input(format!(
                "`{shown}` names both a robtarget and a jointtarget of the program (two name spaces): say which in a `kind` column"
            ))),
            (false, false) => Err(Error::input(format!(
                "the schedule names target `{shown}`, which the program does not have"
            ))),
        },
    }
}

/// A field as a message shows it: at most 40 characters.
fn excerpt(text: &str) -> String {
    match text.char_indices().nth(40) {
        None => text.to_string(),
        Some((end, _)) => format!("{}…", &text[..end]),
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
    /// A visit of a target, of the kind the row says (none: either).
    WhichVisit(Option<TargetType>),
    /// A span over which the robot stood.
    Idle,
}

impl RowKind {
    fn parse(text: &str) -> Option<RowKind> {
        let t = text.trim();
        if t.is_empty() {
            Some(RowKind::WhichVisit(None))
        } else if t.eq_ignore_ascii_case("robtarget") {
            Some(RowKind::WhichVisit(Some(TargetType::Robtarget)))
        } else if t.eq_ignore_ascii_case("jointtarget") {
            Some(RowKind::WhichVisit(Some(TargetType::Jointtarget)))
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
        if pair[1].from_min <= pair[0].to_min {
            return Err(Error::input(format!(
                "the idle span from minute {} overlaps or touches the one from minute {} to {} (one stop is one span)",
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
pub(super) fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}
