//! A heating record means what it says or is refused at its line and
//! column (issue 53): every row as many fields as the header, no column
//! twice, no header repeated, times and temperatures within their units'
//! ranges (data/csv_columns.toml, data/thermal/plausible.toml). The rules
//! are the shared CSV reader's; a heating record is where the hostile
//! sweep met them. Expected lines and columns are counted by hand or from
//! the generator's own layout, never from the reader.

use proptest::prelude::*;
use rapidtherm::thermal::HeatingRecord;

const HEADER: &str = "time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c";

fn refused(src: &str) -> (usize, usize, String) {
    let e = HeatingRecord::parse("rec.csv", src.as_bytes()).unwrap_err();
    let loc = e.location.clone().expect("a location");
    (loc.line, loc.col, e.message)
}

/// The reference recording as Excel writes it where the comma is the
/// decimal mark (`;` between fields, `20,5`): the same numbers as the
/// file with points, and the guess said.
#[test]
fn a_recording_written_the_european_way_reads_as_the_original() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/samples/heating_irb140_60pct.csv"
    );
    let original = std::fs::read_to_string(path).expect("the sample");
    let european: String = original
        .lines()
        .map(|l| {
            if l.starts_with('#') {
                l.to_string()
            } else {
                l.replace(',', ";").replace('.', ",")
            }
        })
        .collect::<Vec<_>>()
        .join("\r\n");
    assert!(
        european.contains(";20,"),
        "the conversion made decimal commas"
    );
    let a = HeatingRecord::parse("rec.csv", original.as_bytes()).expect("the original");
    let b = HeatingRecord::parse("rec.csv", european.as_bytes()).expect("read the European way");
    assert_eq!(a.times, b.times);
    assert_eq!(a.temps, b.temps);
    assert!(a.reading_notes.is_empty(), "{:?}", a.reading_notes);
    assert_eq!(b.reading_notes.len(), 1, "{:?}", b.reading_notes);
    assert!(b.reading_notes[0].contains("decimal mark"));
}

#[test]
fn decimal_commas_are_not_read_shifted() {
    // At minute 60, `20,5` was t1 = 20 and t2 = 5 (every field after it
    // one column on). The 8th field is `23`, at column 19 of line 3.
    let (line, col, msg) = refused(&format!(
        "{HEADER}\n0,7,7,7,7,7,7\n60,20,5,21,5,22,5,23,5,24,5,25,5\n"
    ));
    assert_eq!((line, col), (3, 19), "{msg}");
    assert!(msg.contains("13 fields, the header 7"), "{msg}");
}

#[test]
fn two_columns_of_one_name_are_refused() {
    let (line, col, msg) =
        refused("time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c,T1_C\n0,7,7,7,7,7,7,7\n");
    assert_eq!((line, col), (1, 40), "{msg}");
    assert!(msg.contains("columns 2 and 8"), "{msg}");
}

#[test]
fn times_beyond_a_year_are_refused() {
    let (line, col, msg) = refused(&format!("{HEADER}\n0,7,7,7,7,7,7\n9E+09,8,8,8,8,8,8\n"));
    assert_eq!((line, col), (3, 1), "{msg}");
    assert!(msg.contains("525600"), "{msg}");
}

#[test]
fn an_ambient_in_fahrenheit_is_named() {
    // 64.4 °F = 18 °C.
    let src = format!("{HEADER},ambient_c\n0,7,7,7,7,7,7,64.4\n");
    let (line, col, msg) = refused(&src);
    assert_eq!((line, col), (2, 15), "{msg}");
    assert!(msg.contains("64.4 °F is 18.0 °C"), "{msg}");
}

/// A change a careless or hostile writer makes to a good record.
#[derive(Debug, Clone)]
enum Change {
    None,
    /// A decimal point written as a comma, in data row `row`, field `col`.
    DecimalComma(usize, usize),
    /// A field more at the end of a row.
    ExtraField(usize),
    /// The last field of a row left out.
    DropField(usize),
    /// Column `col` of the header named again at the end (with a field).
    DuplicateColumn(usize),
    /// The header again before data row `row`.
    RepeatHeader(usize),
    /// The time of a row set to 9E+09.
    HugeTime(usize),
    /// A temperature in kelvin.
    Kelvin(usize, usize),
    /// The whole file in °F.
    Fahrenheit,
}

fn change(rows: usize) -> impl Strategy<Value = Change> {
    prop_oneof![
        Just(Change::None),
        (0..rows, 0..7usize).prop_map(|(r, c)| Change::DecimalComma(r, c)),
        (0..rows).prop_map(Change::ExtraField),
        (0..rows).prop_map(Change::DropField),
        (0..7usize).prop_map(Change::DuplicateColumn),
        (0..rows).prop_map(Change::RepeatHeader),
        (0..rows).prop_map(Change::HugeTime),
        (0..rows, 1..7usize).prop_map(|(r, c)| Change::Kelvin(r, c)),
        Just(Change::Fahrenheit),
    ]
}

/// A good record: rows of a time (minutes, increasing from 0) and six
/// temperatures (°C), each with one decimal.
fn record() -> impl Strategy<Value = Vec<[f64; 7]>> {
    (2usize..12).prop_flat_map(|n| {
        prop::collection::vec((0.1f64..30.0, prop::array::uniform6(15.0f64..40.0)), n).prop_map(
            |rows| {
                let mut t = 0.0;
                rows.iter()
                    .enumerate()
                    .map(|(k, (step, temps))| {
                        if k > 0 {
                            t += (step * 10.0).round() / 10.0 + 0.1;
                        }
                        let mut r = [(t * 10.0f64).round() / 10.0; 7];
                        for i in 0..6 {
                            r[i + 1] = (temps[i] * 10.0).round() / 10.0;
                        }
                        r
                    })
                    .collect()
            },
        )
    })
}

/// Each value with one decimal, as `{:.1}` writes it.
fn fields(row: &[f64; 7]) -> Vec<String> {
    row.iter().map(|v| format!("{v:.1}")).collect()
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// A good record is read as written; every change is refused at the
    /// line it made (the header is line 1, data row k line k + 2, one
    /// more after a repeated header).
    #[test]
    fn a_record_is_read_as_written_or_refused_where_changed(
        (rows, change) in record().prop_flat_map(|r| {
            let n = r.len();
            (Just(r), change(n))
        })
    ) {
        let mut header: Vec<String> = HEADER.split(',').map(str::to_string).collect();
        let mut lines: Vec<Vec<String>> = rows.iter().map(fields).collect();
        let mut expect_line = None;
        match change {
            Change::None => {}
            Change::DecimalComma(r, c) => {
                lines[r][c] = lines[r][c].replace('.', ",");
                expect_line = Some(r + 2);
            }
            Change::ExtraField(r) => {
                lines[r].push("1.0".into());
                expect_line = Some(r + 2);
            }
            Change::DropField(r) => {
                lines[r].pop();
                expect_line = Some(r + 2);
            }
            Change::DuplicateColumn(c) => {
                header.push(header[c].to_ascii_uppercase());
                for l in &mut lines {
                    l.push("20.0".into());
                }
                expect_line = Some(1);
            }
            Change::RepeatHeader(r) => {
                lines.insert(r, header.clone());
                expect_line = Some(r + 2);
            }
            Change::HugeTime(r) => {
                // Every later time too, so that time still increases.
                for l in &mut lines[r..] {
                    l[0] = "9E+09".into();
                }
                expect_line = Some(r + 2);
            }
            Change::Kelvin(r, c) => {
                lines[r][c] = format!("{:.2}", rows[r][c] + 273.15);
                expect_line = Some(r + 2);
            }
            Change::Fahrenheit => {
                for (l, row) in lines.iter_mut().zip(&rows) {
                    for c in 1..7 {
                        l[c] = format!("{:.1}", row[c] * 9.0 / 5.0 + 32.0);
                    }
                }
                // The first row is the cold start (minute 0): 15 °C or
                // more is 59 °F or more, beyond a room's 55 °C.
                expect_line = Some(2);
            }
        }
        let mut text = header.join(",");
        text.push('\n');
        for l in &lines {
            text.push_str(&l.join(","));
            text.push('\n');
        }
        let read = HeatingRecord::parse("rec.csv", text.as_bytes());
        match expect_line {
            None => {
                let r = read.map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
                prop_assert_eq!(r.len(), rows.len());
                for (k, row) in rows.iter().enumerate() {
                    prop_assert_eq!(r.times[k], row[0]);
                    for a in 0..6 {
                        prop_assert_eq!(r.temps[a][k], row[a + 1]);
                    }
                }
            }
            Some(line) => {
                let e = match read {
                    Ok(_) => return Err(TestCaseError::fail(format!("{change:?} taken:\n{text}"))),
                    Err(e) => e,
                };
                let at = e.location.clone().expect("a location");
                prop_assert_eq!(at.line, line, "{:?}: {}\n{}", change, e, text);
            }
        }
    }
}
