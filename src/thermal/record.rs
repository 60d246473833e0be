//! Heating records (`time_min,t1_c,...,t6_c[,ambient_c]`, docs/formats.md) and
//! the profile that interpolates them: measured temperatures of the actual
//! run, used directly instead of a model.

use super::plausible::{check, check_room};
use super::HeatingProfile;
use crate::csv_table::CsvTable;
use crate::error::{Error, Location, Result};
use crate::thermal::MotorTemps;

/// Column names of a heating record, axis by axis.
pub const AXIS_COLUMNS: [&str; 6] = ["t1_c", "t2_c", "t3_c", "t4_c", "t5_c", "t6_c"];
pub const TIME_COLUMN: &str = "time_min";
pub const AMBIENT_COLUMN: &str = "ambient_c";

/// A parsed heating record: motor temperatures against minutes since the
/// cold start, rows in non-decreasing time.
#[derive(Debug, Clone)]
pub struct HeatingRecord {
    pub times: Vec<f64>,
    /// `temps[axis][row]`, axis 0 = axis 1.
    pub temps: [Vec<f64>; 6],
    pub ambient: Option<Vec<f64>>,
    /// Extra columns, ignored (the caller shows the warning).
    pub ignored_columns: Vec<String>,
    /// How the file was read where it was guessed (a `;` file's decimal
    /// commas), for the caller to say.
    pub reading_notes: Vec<String>,
    table: CsvTable,
    axis_col: [usize; 6],
}

impl HeatingRecord {
    /// Parse the contents of `file`. Every error names the file, line and
    /// column: missing column, a value that is not a finite number, time
    /// going backwards or negative, no data rows.
    pub fn parse(file: &str, bytes: &[u8]) -> Result<HeatingRecord> {
        let table = CsvTable::parse(file, bytes)?;
        let tcol = table.require(TIME_COLUMN)?;
        let mut axis_col = [0; 6];
        for (slot, name) in axis_col.iter_mut().zip(AXIS_COLUMNS) {
            *slot = table.require(name)?;
        }
        let acol = table.column(AMBIENT_COLUMN);
        let mut known = vec![TIME_COLUMN, AMBIENT_COLUMN];
        known.extend(AXIS_COLUMNS);
        let ignored_columns = table.unknown_columns(&known);

        if table.rows.is_empty() {
            return Err(
                Error::input(format!("{file}: the heating record has no data rows")).at(Location {
                    file: file.to_string(),
                    line: 1,
                    col: 1,
                    line_text: Box::default(),
                }),
            );
        }
        table.check_increasing(tcol)?;
        let n = table.rows.len();
        let mut times = Vec::with_capacity(n);
        let mut temps: [Vec<f64>; 6] = std::array::from_fn(|_| Vec::with_capacity(n));
        let mut ambient = acol.map(|_| Vec::with_capacity(n));
        for row in &table.rows {
            let t = table.number(row, tcol)?;
            if t < 0.0 {
                return Err(Error::input(format!(
                    "`{TIME_COLUMN}` is {t}: minutes since the cold start cannot be negative"
                ))
                .at(table.field_location(row, tcol)));
            }
            times.push(t);
            for (axis, &c) in axis_col.iter().enumerate() {
                let v = table.number(row, c)?;
                let v = check(v, || table.field_location(row, c))?;
                // At the cold start the motors stand at the room's
                // temperature: a room's bounds hold there, and a file in
                // °F (a 20 °C room is 68 °F) is found at its first row.
                if t == 0.0 {
                    check_room(v, || table.field_location(row, c)).map_err(|e| {
                        e.with_note(
                            "at the cold start (minute 0) a motor is at the room's temperature",
                        )
                    })?;
                }
                temps[axis].push(v);
            }
            if let (Some(a), Some(c)) = (ambient.as_mut(), acol) {
                let v = table.number(row, c)?;
                a.push(check_room(v, || table.field_location(row, c))?);
            }
        }
        Ok(HeatingRecord {
            times,
            temps,
            ambient,
            ignored_columns,
            reading_notes: table.warnings.clone(),
            table,
            axis_col,
        })
    }

    pub fn file(&self) -> &str {
        &self.table.file
    }

    pub fn len(&self) -> usize {
        self.times.len()
    }

    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Location of the value of `axis` (0-based) in data row `row`, for
    /// errors about the data (too few points, a fit that fails).
    pub fn location(&self, row: usize, axis: usize) -> Location {
        let row = row.min(self.table.rows.len().saturating_sub(1));
        match (self.table.rows.get(row), self.axis_col.get(axis)) {
            (Some(r), Some(&c)) => self.table.field_location(r, c),
            _ => Location {
                file: self.table.file.clone(),
                line: 1,
                col: 1,
                line_text: Box::default(),
            },
        }
    }
}

/// Measured temperatures used directly: linear interpolation in time between
/// the rows of a heating record. Outside the recorded window it refuses,
/// unless built with [`RecordedProfile::holding_ends`], which holds the first
/// and last rows' values (a choice the user makes explicitly).
#[derive(Debug, Clone)]
pub struct RecordedProfile {
    times: Vec<f64>,
    temps: Vec<MotorTemps>,
    file: String,
    hold_ends: bool,
}

impl RecordedProfile {
    pub fn new(record: &HeatingRecord) -> RecordedProfile {
        RecordedProfile {
            times: record.times.clone(),
            temps: (0..record.len())
                .map(|i| std::array::from_fn(|a| record.temps[a][i]))
                .collect(),
            file: record.file().to_string(),
            hold_ends: false,
        }
    }

    /// Hold the end values outside the recorded window instead of refusing.
    pub fn holding_ends(mut self) -> RecordedProfile {
        self.hold_ends = true;
        self
    }

    /// First and last recorded minute.
    pub fn window(&self) -> (f64, f64) {
        (
            self.times.first().copied().unwrap_or(0.0),
            self.times.last().copied().unwrap_or(0.0),
        )
    }
}

impl HeatingProfile for RecordedProfile {
    fn temps_at(&self, t_min: f64) -> Result<MotorTemps> {
        let (lo, hi) = self.window();
        let (first, last) = match (self.temps.first(), self.temps.last()) {
            (Some(f), Some(l)) => (*f, *l),
            _ => return Err(Error::input(format!("{}: no recorded rows", self.file))),
        };
        if !t_min.is_finite() {
            return Err(Error::usage(format!(
                "time {t_min} min is not a finite number"
            )));
        }
        if t_min < lo || t_min > hi {
            if self.hold_ends {
                return Ok(if t_min < lo { first } else { last });
            }
            return Err(Error::new(
                crate::error::ErrorKind::Unsupported,
                format!(
                    "minute {t_min} is outside the recording {} ({lo} to {hi} min)",
                    self.file
                ),
            )
            .with_note("measured temperatures are only known inside the recorded window")
            .with_remedy(crate::error::Remedy::FitBeyondRecording));
        }
        // First row strictly after t; the segment is [k-1, k].
        let k = self.times.partition_point(|&x| x <= t_min);
        if k == 0 {
            return Ok(first);
        }
        if k >= self.times.len() {
            return Ok(last);
        }
        let (t0, t1) = (self.times[k - 1], self.times[k]);
        let (a, b) = (self.temps[k - 1], self.temps[k]);
        let w = if t1 > t0 {
            (t_min - t0) / (t1 - t0)
        } else {
            1.0
        };
        Ok(std::array::from_fn(|i| a[i] + w * (b[i] - a[i])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c";

    fn rec(body: &str) -> Result<HeatingRecord> {
        HeatingRecord::parse("h.csv", format!("# c\n{HEADER}\n{body}").as_bytes())
    }

    #[test]
    fn parses_rows_and_interpolates() {
        let r = rec("0,7,7,7,7,7,7\n10,9,11,13,15,17,19\n").unwrap();
        assert_eq!(r.len(), 2);
        let p = RecordedProfile::new(&r);
        let mid = p.temps_at(2.5).unwrap();
        assert_eq!(mid, [7.5, 8.0, 8.5, 9.0, 9.5, 10.0]);
        assert_eq!(p.temps_at(10.0).unwrap()[5], 19.0);
        let e = p.temps_at(10.5).unwrap_err();
        assert!(e.message.contains("outside the recording"));
        assert_eq!(p.clone().holding_ends().temps_at(99.0).unwrap()[0], 9.0);
    }

    #[test]
    fn negative_time_is_located() {
        let e = rec("0,7,7,7,7,7,7\n-1,7,7,7,7,7,7\n").unwrap_err();
        let loc = e.location.unwrap();
        assert_eq!((loc.line, loc.col), (4, 1));
    }

    #[test]
    fn no_rows_is_an_error() {
        assert!(rec("").unwrap_err().message.contains("no data rows"));
    }
}
