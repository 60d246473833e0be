//! The CSV dialect of `docs/formats.md`, shared by every data file the
//! tool reads (heating records, schedules, measurements): one header row,
//! columns matched by name in any order, `#` comment lines, blank lines
//! ignored, every bad value reported with file, line and column.
//!
//! What a file must be to mean what it says is checked here, for every
//! reader at once: every row has as many fields as the header (a decimal
//! comma under a comma header splits `20,5` in two and shifts every field
//! after it), no column is named twice, the header is not repeated as a
//! row, and a number lies within the range of the unit its column's name
//! ends in (`data/csv_columns.toml`: `_min`, `_mm`). A reader that names
//! its columns ([`CsvTable::read`]) also gets its required columns
//! checked and the others reported as ignored.
//!
//! A foundation: imports only `error`.

use crate::error::{Error, Location, Result};
use serde::Deserialize;
use std::sync::OnceLock;

/// The ranges of the columns by unit (`data/csv_columns.toml`).
pub const CSV_COLUMNS_TOML: &str = include_str!("../data/csv_columns.toml");

/// The range of the numbers of one unit.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitRange {
    pub lowest: f64,
    pub highest: f64,
}

/// The ranges of `data/csv_columns.toml`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ranges {
    pub min: UnitRange,
    pub mm: UnitRange,
}

/// The embedded ranges, parsed once. A unit test parses the embedded file,
/// so the `expect` cannot fire on a tested build.
pub fn ranges() -> &'static Ranges {
    static RANGES: OnceLock<Ranges> = OnceLock::new();
    RANGES.get_or_init(|| {
        toml::from_str(CSV_COLUMNS_TOML).expect("the embedded data/csv_columns.toml is valid")
    })
}

/// The unit a column's name ends in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Unit {
    /// `_min`: minutes since the cold start.
    Minutes,
    /// `_mm`: a position in millimetres.
    Millimetres,
}

impl Unit {
    fn of(name: &str) -> Option<Unit> {
        if name.ends_with("_min") {
            Some(Unit::Minutes)
        } else if name.ends_with("_mm") {
            Some(Unit::Millimetres)
        } else {
            None
        }
    }

    fn range(self) -> &'static UnitRange {
        match self {
            Unit::Minutes => &ranges().min,
            Unit::Millimetres => &ranges().mm,
        }
    }
}

/// The columns a reader knows: those it needs and those it may use.
#[derive(Debug, Clone, Copy, Default)]
pub struct Columns<'a> {
    pub required: &'a [&'a str],
    pub optional: &'a [&'a str],
    /// Whether a row may end before optional columns, which it then
    /// leaves empty (a schedule's visit `p10,120` under
    /// `target,time_min,kind,end_min`); otherwise a short row is an error.
    pub short_rows: bool,
}

/// At most this many characters of a field are shown in a message: a
/// 10 MB field is not echoed.
const SHOWN_CHARS: usize = 40;

/// A field as a message shows it: at most [`SHOWN_CHARS`] characters.
fn excerpt(text: &str) -> String {
    match text.char_indices().nth(SHOWN_CHARS) {
        None => text.to_string(),
        Some((end, _)) => format!("{}… ({} bytes)", &text[..end], text.len()),
    }
}

/// A number as a message shows it: `9e9`, not ten digits.
fn shown(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// What separates a file's fields, as its header shows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Separator {
    /// `,` with a decimal point: the dialect of `docs/formats.md`.
    Comma,
    /// `;` with a decimal comma or point: what Excel writes where the
    /// comma is the decimal mark (much of Europe). Chosen where the header
    /// has a semicolon and no comma.
    Semicolon,
}

impl Separator {
    /// The separator of a header line: `;` where it has one and no comma
    /// (a comma header may not hold a semicolon's meaning, and a
    /// one-column file is read as commas).
    fn of_header(text: &str) -> Separator {
        if text.contains(';') && !text.contains(',') {
            Separator::Semicolon
        } else {
            Separator::Comma
        }
    }

    fn char(self) -> char {
        match self {
            Separator::Comma => ',',
            Separator::Semicolon => ';',
        }
    }
}

/// A parsed CSV file: header names and rows of raw fields, each row keeping
/// the 1-based line it came from.
#[derive(Debug, Clone)]
pub struct CsvTable {
    pub file: String,
    /// What separates its fields (and so whether a comma in a number is
    /// its decimal mark).
    pub separator: Separator,
    pub header: Vec<String>,
    header_line: usize,
    header_offset: usize,
    pub rows: Vec<CsvRow>,
    /// The unit each column's name says, column by column.
    units: Vec<Option<Unit>>,
    /// What [`CsvTable::read`] assumed (columns it ignored), for the
    /// caller to show.
    pub warnings: Vec<String>,
    src: String,
}

#[derive(Debug, Clone)]
pub struct CsvRow {
    /// 1-based line number in the file.
    pub line: usize,
    pub fields: Vec<String>,
    /// Byte offset of the line's start in the file.
    offset: usize,
}

impl CsvTable {
    /// Parse `bytes` (the contents of `file`, used only in messages) as a
    /// file of the columns `columns`: [`CsvTable::parse`], then every
    /// required column present, and each column it does not know named in
    /// [`CsvTable::warnings`] as ignored.
    pub fn read(file: &str, bytes: &[u8], columns: &Columns) -> Result<CsvTable> {
        let mut table = CsvTable::parse_rows(file, bytes, Some(columns))?;
        for name in columns.required {
            table.require(name)?;
        }
        let mut known = columns.required.to_vec();
        known.extend(columns.optional);
        let ignored: Vec<String> = table
            .unknown_columns(&known)
            .into_iter()
            .map(|c| format!("{file}: column `{}` ignored", excerpt(&c)))
            .collect();
        table.warnings.extend(ignored);
        Ok(table)
    }

    /// Parse `bytes` (the contents of `file`, used only in messages): every
    /// row as many fields as the header, no column named twice, no row
    /// that repeats the header.
    pub fn parse(file: &str, bytes: &[u8]) -> Result<CsvTable> {
        CsvTable::parse_rows(file, bytes, None)
    }

    fn parse_rows(file: &str, bytes: &[u8], columns: Option<&Columns>) -> Result<CsvTable> {
        let src = std::str::from_utf8(bytes)
            .map_err(|e| {
                Error::input("CSV files must be UTF-8").at(Location::from_offset(
                    file,
                    bytes,
                    e.valid_up_to(),
                ))
            })?
            .to_string();
        // Lines are split here rather than by the csv crate so that line
        // numbers count comment and blank lines exactly; each line is one
        // record (quoted fields may hold commas, not line breaks).
        let mut header: Option<(Vec<String>, usize, usize)> = None;
        let mut separator = Separator::Comma;
        let mut rows = Vec::new();
        let mut offset = 0;
        for (index, raw) in src.split_inclusive('\n').enumerate() {
            let line = index + 1;
            let start = offset;
            offset += raw.len();
            let mut text = raw.trim_end_matches(['\n', '\r']);
            if index == 0 {
                // Excel and Notepad start UTF-8 files with a byte-order
                // mark; it is not part of the first column's name.
                text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
            }
            let trimmed = text.trim_start();
            if trimmed.is_empty() || trimmed.starts_with('#') {
                continue;
            }
            if header.is_none() {
                separator = Separator::of_header(text);
            }
            let fields = split_record(text, separator)
                .map_err(|e| Error::input_at(file, line, 1, format!("malformed CSV: {e}")))?;
            if header.is_none() {
                header = Some((
                    fields.iter().map(|f| f.to_ascii_lowercase()).collect(),
                    line,
                    start,
                ));
            } else {
                rows.push(CsvRow {
                    line,
                    fields,
                    offset: start,
                });
            }
        }
        let (header, header_line, header_offset) =
            header.ok_or_else(|| Error::input_at(file, 1, 1, "empty file: no header row"))?;
        let units = header.iter().map(|h| Unit::of(h)).collect();
        // Said, since it is a guess from the header: a reader of the
        // output sees how its numbers were read.
        let warnings = match separator {
            Separator::Comma => Vec::new(),
            Separator::Semicolon => vec![format!(
                "{file}: fields separated by `;` (the header has no comma): a comma in a number is read as its decimal mark"
            )],
        };
        let table = CsvTable {
            file: file.to_string(),
            separator,
            header,
            header_line,
            header_offset,
            rows,
            units,
            warnings,
            src,
        };
        table.check_header()?;
        for row in &table.rows {
            table.check_row(row, columns)?;
        }
        Ok(table)
    }

    /// No column named twice, and none unnamed: one of two `t1_c` columns
    /// would be used and the other silently dropped.
    fn check_header(&self) -> Result<()> {
        for (k, name) in self.header.iter().enumerate() {
            if name.is_empty() && self.header.len() > 1 {
                return Err(
                    Error::input(format!("column {} of the header has no name", k + 1))
                        .at(self.header_location(k)),
                );
            }
            if let Some(first) = self.header[..k].iter().position(|h| h == name) {
                return Err(Error::input(format!(
                    "column `{}` is named twice (columns {} and {}): which one is meant?",
                    excerpt(name),
                    first + 1,
                    k + 1
                ))
                .at(self.header_location(k)));
            }
        }
        Ok(())
    }

    /// A row with as many fields as the header (fewer only where
    /// `columns` lets a row end before optional columns), and not the
    /// header again (two files joined).
    fn check_row(&self, row: &CsvRow, columns: Option<&Columns>) -> Result<()> {
        let (n, m) = (row.fields.len(), self.header.len());
        if n > m {
            let mut why = format!(
                "this row has {n} fields, the header {m}: the field `{}` has no column",
                excerpt(&row.fields[m])
            );
            if row.fields.iter().all(|f| looks_numeric(f)) {
                why.push_str(
                    "; decimal commas? Under a header separated by commas rapidtherm reads `20.5`, and a field split at its comma shifts every field after it; a file separated by `;` may keep its decimal commas",
                );
            }
            return Err(Error::input(why).at(self.field_location(row, m)));
        }
        if n < m {
            let missing = &self.header[n..];
            let allowed = columns.is_some_and(|c| {
                c.short_rows
                    && missing
                        .iter()
                        .all(|h| c.optional.iter().any(|o| o.eq_ignore_ascii_case(h)))
            });
            if !allowed {
                let names: Vec<String> = missing
                    .iter()
                    .map(|h| format!("`{}`", excerpt(h)))
                    .collect();
                let mut at = self.field_location(row, n.saturating_sub(1));
                at.col = at.col.max(1) + row.fields.last().map_or(0, |f| f.chars().count());
                let what = match names.as_slice() {
                    [one] => format!("column {one} is missing"),
                    many => format!("columns {} are missing", many.join(", ")),
                };
                return Err(Error::input(format!(
                    "this row has {n} fields, the header {m}: {what}"
                ))
                .at(at));
            }
        }
        if n == m
            && row
                .fields
                .iter()
                .zip(&self.header)
                .all(|(f, h)| f.eq_ignore_ascii_case(h))
        {
            return Err(Error::input(
                "this row repeats the header: two files joined? Each file has one header row",
            )
            .at(self.field_location(row, 0)));
        }
        Ok(())
    }

    /// Location of column `k` of the header.
    fn header_location(&self, k: usize) -> Location {
        self.line_location(self.header_line, 0).with_offset_hint(
            &self.src,
            self.header_offset,
            k,
            self.separator,
        )
    }

    /// Index of a column, matched without regard to case.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header
            .iter()
            .position(|h| h.eq_ignore_ascii_case(name))
    }

    /// Index of a column that must be present.
    pub fn require(&self, name: &str) -> Result<usize> {
        self.column(name).ok_or_else(|| {
            let names: Vec<String> = self.header.iter().map(|h| excerpt(h)).collect();
            Error::input(format!(
                "missing required column `{name}` (the header has: {})",
                names.join(", ")
            ))
            .at(self.line_location(self.header_line, 0))
        })
    }

    /// Header names not in `known`: docs/formats.md says to ignore them with a
    /// warning, which the caller shows.
    pub fn unknown_columns(&self, known: &[&str]) -> Vec<String> {
        self.header
            .iter()
            .filter(|h| !known.iter().any(|k| k.eq_ignore_ascii_case(h)))
            .cloned()
            .collect()
    }

    /// The raw text of a field, or an error if the row is too short.
    pub fn text<'a>(&self, row: &'a CsvRow, col: usize) -> Result<&'a str> {
        row.fields.get(col).map(String::as_str).ok_or_else(|| {
            Error::input(format!(
                "row has {} fields, column `{}` is missing",
                row.fields.len(),
                excerpt(&self.header[col])
            ))
            .at(self.field_location(row, row.fields.len().saturating_sub(1)))
        })
    }

    /// A finite number in a field, within the range of its column's unit
    /// (`data/csv_columns.toml`).
    pub fn number(&self, row: &CsvRow, col: usize) -> Result<f64> {
        let text = self.text(row, col)?;
        let v = match self.decimal_point(text).parse::<f64>() {
            Ok(v) if v.is_finite() => v,
            _ => {
                return Err(Error::input(format!(
                    "column `{}`: `{}` is not a finite number",
                    excerpt(&self.header[col]),
                    excerpt(text)
                ))
                .at(self.field_location(row, col)))
            }
        };
        match self.units.get(col).copied().flatten() {
            Some(unit) => self.in_range(v, unit, row, col),
            None => Ok(v),
        }
    }

    /// A number's text with a decimal point: a semicolon file's decimal
    /// comma (`20,5`) made a point; a comma file's fields hold none.
    fn decimal_point<'t>(&self, text: &'t str) -> std::borrow::Cow<'t, str> {
        if self.separator == Separator::Semicolon
            && text.matches(',').count() == 1
            && !text.contains('.')
        {
            std::borrow::Cow::Owned(text.replacen(',', ".", 1))
        } else {
            std::borrow::Cow::Borrowed(text)
        }
    }

    /// `v` if within the range of `unit`, else an error at the field.
    fn in_range(&self, v: f64, unit: Unit, row: &CsvRow, col: usize) -> Result<f64> {
        let r = unit.range();
        if (r.lowest..=r.highest).contains(&v) {
            return Ok(v);
        }
        let name = excerpt(&self.header[col]);
        let why = match unit {
            Unit::Minutes if v < 0.0 => format!(
                "`{name}` is {}: minutes since the cold start cannot be negative (a time before the cold start)",
                shown(v)
            ),
            Unit::Minutes => format!(
                "`{name}` is {} min: not a time since a cold start (rapidtherm takes 0 to {} min, a year)",
                shown(v),
                r.highest
            ),
            Unit::Millimetres => format!(
                "`{name}` = {} mm is not a plausible position (more than {} m from the origin): a unit or column mistake?",
                shown(v),
                r.highest.max(-r.lowest) / 1000.0
            ),
        };
        Err(Error::input(why).at(self.field_location(row, col)))
    }

    /// An optional numeric column: `None` when absent from the header.
    pub fn optional_number(&self, row: &CsvRow, col: Option<usize>) -> Result<Option<f64>> {
        col.map(|c| self.number(row, c)).transpose()
    }

    /// Location of field `col` of `row` (column = character position of the
    /// field's first character).
    pub fn field_location(&self, row: &CsvRow, col: usize) -> Location {
        self.line_location(row.line, col).with_offset_hint(
            &self.src,
            row.offset,
            col,
            self.separator,
        )
    }

    fn line_location(&self, line: usize, _col: usize) -> Location {
        Location {
            file: self.file.clone(),
            line,
            col: 1,
            line_text: self
                .src
                .lines()
                .nth(line.saturating_sub(1))
                .unwrap_or("")
                .into(),
        }
    }

    /// Check that a time column never decreases; the error names the row
    /// where it goes back.
    pub fn check_increasing(&self, col: usize) -> Result<()> {
        let mut last: Option<f64> = None;
        for row in &self.rows {
            let t = self.number(row, col)?;
            if let Some(prev) = last {
                if t < prev {
                    return Err(Error::input(format!(
                        "`{}` goes backwards: {t} after {prev}",
                        excerpt(&self.header[col])
                    ))
                    .at(self.field_location(row, col)));
                }
            }
            last = Some(t);
        }
        Ok(())
    }
}

/// Whether a field could be (part of) a number: digits, signs, points,
/// exponents (a decimal comma's halves are).
fn looks_numeric(field: &str) -> bool {
    !field.is_empty()
        && field
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E'))
}

/// One CSV line as trimmed fields, quotes removed.
fn split_record(text: &str, separator: Separator) -> std::result::Result<Vec<String>, csv::Error> {
    // Numeric data lines have no quotes: split them directly, and leave
    // quoting rules to the csv crate (a reader per line costs ~20 µs).
    if !text.contains('"') {
        return Ok(text
            .split(separator.char())
            .map(|f| f.trim().to_string())
            .collect());
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .delimiter(separator.char() as u8)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut record = csv::StringRecord::new();
    reader.read_record(&mut record)?;
    Ok(record.iter().map(str::to_string).collect())
}

trait WithOffsetHint {
    fn with_offset_hint(
        self,
        src: &str,
        line_offset: usize,
        field: usize,
        separator: Separator,
    ) -> Location;
}

impl WithOffsetHint for Location {
    /// Set `col` to the start of field number `field` on the line starting at
    /// `line_offset`, counting separators outside double quotes.
    fn with_offset_hint(
        mut self,
        src: &str,
        line_offset: usize,
        field: usize,
        separator: Separator,
    ) -> Location {
        let line = src[line_offset.min(src.len())..]
            .lines()
            .next()
            .unwrap_or("");
        let mut in_quotes = false;
        let mut seen = 0;
        let mut col = 1;
        for (i, c) in line.chars().enumerate() {
            if seen == field {
                col = i + 1;
                break;
            }
            match c {
                '"' => in_quotes = !in_quotes,
                c if c == separator.char() && !in_quotes => {
                    seen += 1;
                    col = i + 2;
                }
                _ => {}
            }
        }
        // Skip leading blanks so the caret points at the value itself.
        let skip = line.chars().skip(col - 1).take_while(|c| *c == ' ').count();
        self.col = col + skip;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = "# comment\ntime_min, t1_c ,extra\n\n0,7.0,a\n# mid\n5, x ,b\n";

    /// What Excel writes where the comma is the decimal mark: `;` between
    /// fields, `20,5` for twenty and a half.
    const EUROPEAN: &str = "time_min;t1_c;note\n0;20,5;\"a;b\"\n2,5;21;x\n";

    #[test]
    fn a_semicolon_file_is_read_with_its_decimal_commas_and_said() {
        let t = CsvTable::parse("eu.csv", EUROPEAN.as_bytes()).unwrap();
        assert_eq!(t.separator, Separator::Semicolon);
        assert_eq!(t.header, vec!["time_min", "t1_c", "note"]);
        let numbers: Vec<(f64, f64)> = t
            .rows
            .iter()
            .map(|r| (t.number(r, 0).unwrap(), t.number(r, 1).unwrap()))
            .collect();
        assert_eq!(numbers, vec![(0.0, 20.5), (2.5, 21.0)]);
        assert_eq!(
            t.text(&t.rows[0], 2).unwrap(),
            "a;b",
            "a quoted `;` is text"
        );
        assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
        assert!(t.warnings[0].contains("decimal mark"), "{:?}", t.warnings);
    }

    #[test]
    fn a_semicolon_files_bad_number_is_located_at_its_own_field() {
        let t = CsvTable::parse("eu.csv", b"time_min;t1_c\n0;20,5\n1;2,0,1\n").unwrap();
        let e = t.number(&t.rows[1], 1).unwrap_err().to_string();
        assert!(e.contains("eu.csv:3:3"), "{e}");
        assert!(e.contains("`2,0,1` is not a finite number"), "{e}");
    }

    #[test]
    fn a_comma_file_keeps_refusing_a_decimal_comma() {
        let e = CsvTable::parse("h.csv", b"time_min,t1_c\n0,20,5\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("decimal commas?"), "{e}");
        let t = CsvTable::parse("h.csv", b"time_min,t1_c\n0,20.5\n").unwrap();
        assert_eq!(t.separator, Separator::Comma);
        assert!(t.warnings.is_empty());
    }

    #[test]
    fn columns_by_name_and_comments_skipped() {
        let t = CsvTable::parse("h.csv", SAMPLE.as_bytes()).unwrap();
        assert_eq!(t.header, vec!["time_min", "t1_c", "extra"]);
        assert_eq!(t.rows.len(), 2);
        assert_eq!(t.rows[0].line, 4);
        assert_eq!(t.rows[1].line, 6);
        assert_eq!(t.unknown_columns(&["time_min", "t1_c"]), vec!["extra"]);
        let c = t.require("T1_C").unwrap();
        assert_eq!(t.number(&t.rows[0], c).unwrap(), 7.0);
    }

    #[test]
    fn bad_number_names_line_and_column() {
        let t = CsvTable::parse("h.csv", SAMPLE.as_bytes()).unwrap();
        let e = t.number(&t.rows[1], 1).unwrap_err();
        let loc = e.location.unwrap();
        assert_eq!((loc.line, loc.col), (6, 4));
        assert!(e.message.contains("`x` is not a finite number"));
    }

    #[test]
    fn nan_is_rejected_and_missing_column_named() {
        let t = CsvTable::parse("h.csv", b"time_min,t1_c\n0,NaN\n").unwrap();
        assert!(t.number(&t.rows[0], 1).is_err());
        let e = t.require("t2_c").unwrap_err();
        assert!(e.message.contains("t2_c"));
        assert_eq!(e.location.unwrap().line, 1);
    }

    #[test]
    fn a_byte_order_mark_is_not_part_of_the_first_column() {
        let t = CsvTable::parse("h.csv", "\u{FEFF}time_min,t1_c\n0,7\n".as_bytes()).unwrap();
        assert_eq!(t.header, vec!["time_min", "t1_c"]);
        assert!(t.require("time_min").is_ok());
    }

    #[test]
    fn the_embedded_ranges_are_data_csv_columns() {
        // data/csv_columns.toml: a year of minutes, 100 m either way.
        let r = ranges();
        assert_eq!((r.min.lowest, r.min.highest), (0.0, 525_600.0));
        assert_eq!((r.mm.lowest, r.mm.highest), (-100_000.0, 100_000.0));
        let t = CsvTable::parse("s.csv", b"target,time_min\np10,9E+09\n").unwrap();
        let e = t.number(&t.rows[0], 1).unwrap_err();
        assert_eq!(e.location.unwrap().col, 5);
    }

    #[test]
    fn time_going_backwards_is_located() {
        let t = CsvTable::parse("h.csv", b"time_min\n0\n2\n1\n").unwrap();
        let e = t.check_increasing(0).unwrap_err();
        assert_eq!(e.location.unwrap().line, 4);
    }
}
