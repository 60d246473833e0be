//! The CSV dialect of `docs/formats.md`, shared by every data file the
//! tool reads (heating records, schedules, measurements): one header row,
//! columns matched by name in any order, `#` comment lines, blank lines
//! ignored, every bad value reported with file, line and column.
//!
//! A foundation: imports only `error`.

use crate::error::{Error, Location, Result};

/// A parsed CSV file: header names and rows of raw fields, each row keeping
/// the 1-based line it came from.
#[derive(Debug, Clone)]
pub struct CsvTable {
    pub file: String,
    pub header: Vec<String>,
    header_line: usize,
    pub rows: Vec<CsvRow>,
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
    /// Parse `bytes` (the contents of `file`, used only in messages).
    pub fn parse(file: &str, bytes: &[u8]) -> Result<CsvTable> {
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
        let mut header: Option<(Vec<String>, usize)> = None;
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
            let fields = split_record(text)
                .map_err(|e| Error::input_at(file, line, 1, format!("malformed CSV: {e}")))?;
            if header.is_none() {
                header = Some((
                    fields.iter().map(|f| f.to_ascii_lowercase()).collect(),
                    line,
                ));
            } else {
                rows.push(CsvRow {
                    line,
                    fields,
                    offset: start,
                });
            }
        }
        let (header, header_line) =
            header.ok_or_else(|| Error::input_at(file, 1, 1, "empty file: no header row"))?;
        Ok(CsvTable {
            file: file.to_string(),
            header,
            header_line,
            rows,
            src,
        })
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
            Error::input(format!(
                "missing required column `{name}` (the header has: {})",
                self.header.join(", ")
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
                self.header[col]
            ))
            .at(self.field_location(row, row.fields.len().saturating_sub(1)))
        })
    }

    /// A finite number in a field.
    pub fn number(&self, row: &CsvRow, col: usize) -> Result<f64> {
        let text = self.text(row, col)?;
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(Error::input(format!(
                "column `{}`: `{}` is not a finite number",
                self.header[col], text
            ))
            .at(self.field_location(row, col))),
        }
    }

    /// An optional numeric column: `None` when absent from the header.
    pub fn optional_number(&self, row: &CsvRow, col: Option<usize>) -> Result<Option<f64>> {
        col.map(|c| self.number(row, c)).transpose()
    }

    /// Location of field `col` of `row` (column = character position of the
    /// field's first character).
    pub fn field_location(&self, row: &CsvRow, col: usize) -> Location {
        self.line_location(row.line, col)
            .with_offset_hint(&self.src, row.offset, col)
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
                        self.header[col]
                    ))
                    .at(self.field_location(row, col)));
                }
            }
            last = Some(t);
        }
        Ok(())
    }
}

/// One CSV line as trimmed fields, quotes removed.
fn split_record(text: &str) -> std::result::Result<Vec<String>, csv::Error> {
    // Numeric data lines have no quotes: split them directly, and leave
    // quoting rules to the csv crate (a reader per line costs ~20 µs).
    if !text.contains('"') {
        return Ok(text.split(',').map(|f| f.trim().to_string()).collect());
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut record = csv::StringRecord::new();
    reader.read_record(&mut record)?;
    Ok(record.iter().map(str::to_string).collect())
}

trait WithOffsetHint {
    fn with_offset_hint(self, src: &str, line_offset: usize, field: usize) -> Location;
}

impl WithOffsetHint for Location {
    /// Set `col` to the start of field number `field` on the line starting at
    /// `line_offset`, counting commas outside double quotes.
    fn with_offset_hint(mut self, src: &str, line_offset: usize, field: usize) -> Location {
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
                ',' if !in_quotes => {
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
    fn time_going_backwards_is_located() {
        let t = CsvTable::parse("h.csv", b"time_min\n0\n2\n1\n").unwrap();
        let e = t.check_increasing(0).unwrap_err();
        assert_eq!(e.location.unwrap().line, 4);
    }
}
