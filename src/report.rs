//! Rendering of tabular results for people (aligned table) and scripts
//! (CSV, JSON). Commands build rows of strings; this module lays them out.
//!
//! A foundation: imports nothing of the library. Which format a run prints
//! is the CLI's choice.

pub mod json;

/// Column alignment in the table format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    Left,
    Right,
}

/// Lay out rows as a plain-text table: columns padded to their widest cell,
/// two spaces apart, header underlined with dashes. Numbers are usually
/// right-aligned so that decimal points line up.
pub fn render_table(header: &[&str], align: &[Align], rows: &[Vec<String>]) -> String {
    let mut cells = Rows::default();
    for row in rows {
        for cell in row {
            cells.cell(cell);
        }
        cells.end_row();
    }
    let mut out = Vec::new();
    // Writing to a Vec cannot fail.
    let _ = write_table(&mut out, header, align, &[cells]);
    String::from_utf8(out).unwrap_or_default()
}

/// Rows of cells as they are made, their text in one buffer: a table of
/// a million rows is one string, not sixteen million.
#[derive(Debug, Default)]
pub struct Rows {
    text: String,
    /// Where each cell ends, counted from its row's start in `text`: four
    /// bytes a cell, not eight (a row is far below 4 GiB: its cells come
    /// from files whose offsets are 32-bit), which were a sixth of a
    /// million-row listing's page faults.
    ends: Vec<u32>,
    /// Where each row ends: in `ends` and in `text`.
    rows: Vec<RowEnd>,
}

#[derive(Debug, Clone, Copy, Default)]
struct RowEnd {
    cells: usize,
    text: usize,
}

impl Rows {
    /// The buffer the next cell is written into; [`Rows::end_cell`] ends
    /// it.
    pub fn text(&mut self) -> &mut String {
        &mut self.text
    }

    /// End the cell written since the last one. (How wide it is, the
    /// table works out once all rows are made: [`Rows::widths`].)
    pub fn end_cell(&mut self) {
        let row = self.rows.last().map_or(0, |r| r.text);
        self.ends
            .push(u32::try_from(self.text.len() - row).unwrap_or(u32::MAX));
    }

    /// The widest cell of each column, in characters: from the cells'
    /// ends alone where the text is ASCII (a listing's always is).
    pub fn widths(&self) -> Vec<usize> {
        let mut width: Vec<usize> = Vec::new();
        let ascii = self.text.is_ascii();
        for i in 0..self.len() {
            for (col, cell) in self.row(i).enumerate() {
                let n = if ascii {
                    cell.len()
                } else {
                    cell.chars().count()
                };
                match width.get_mut(col) {
                    Some(w) => *w = (*w).max(n),
                    None => width.push(n),
                }
            }
        }
        width
    }

    /// A whole cell.
    pub fn cell(&mut self, s: &str) {
        self.text.push_str(s);
        self.end_cell();
    }

    pub fn end_row(&mut self) {
        self.rows.push(RowEnd {
            cells: self.ends.len(),
            text: self.text.len(),
        });
    }

    /// How many rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Room for `rows` rows of `cells` cells and `text` bytes: a part of
    /// a large listing is made without growing (copying) its buffers.
    pub fn with_capacity(rows: usize, cells: usize, text: usize) -> Rows {
        Rows {
            text: String::with_capacity(text),
            ends: Vec::with_capacity(rows * cells),
            rows: Vec::with_capacity(rows),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Forget every row, keeping the buffers.
    pub fn clear(&mut self) {
        self.text.clear();
        self.ends.clear();
        self.rows.clear();
    }

    /// The cells of row `i` (none past the last).
    pub fn row(&self, i: usize) -> impl Iterator<Item = &str> {
        let before = match i {
            0 => RowEnd::default(),
            _ => self.rows.get(i - 1).copied().unwrap_or_default(),
        };
        let last = self.rows.get(i).map_or(before.cells, |r| r.cells);
        let ends = self.ends.get(before.cells..last).unwrap_or_default();
        let text = self.text.get(before.text..).unwrap_or_default();
        let starts = std::iter::once(0).chain(ends.iter().map(|&e| e as usize));
        starts
            .zip(ends)
            .map(move |(a, &b)| text.get(a..b as usize).unwrap_or_default())
    }
}

/// [`render_table`] written out as it is laid out, of rows made in parts
/// (by several threads): the columns as wide as the widest cell of all.
/// The parts' lines are laid out on every core, a few parts at a time.
pub fn write_table(
    out: &mut dyn std::io::Write,
    header: &[&str],
    align: &[Align],
    parts: &[Rows],
) -> std::io::Result<()> {
    use rayon::prelude::*;
    let mut width: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for part in parts.par_iter().map(Rows::widths).collect::<Vec<_>>() {
        for (w, p) in width.iter_mut().zip(&part) {
            *w = (*w).max(*p);
        }
    }
    let layout = Layout {
        width: &width,
        align,
    };
    let mut buf = String::new();
    layout.line(&mut buf, header.iter().copied());
    let rule: Vec<String> = width.iter().map(|w| "-".repeat(*w)).collect();
    layout.line(&mut buf, rule.iter().map(String::as_str));
    out.write_all(buf.as_bytes())?;
    // The lines of a few parts at a time, laid out into buffers kept from
    // one group to the next: fresh ones were a page fault every 4 kB of a
    // 150 MB listing (a third of a million targets' page faults).
    let mut texts: Vec<String> = Vec::new();
    for group in parts.chunks(2 * rayon::current_num_threads().max(1)) {
        texts.resize_with(texts.len().max(group.len()), String::new);
        group
            .par_iter()
            .zip(texts.par_iter_mut())
            .for_each(|(part, text)| {
                text.clear();
                for i in 0..part.len() {
                    layout.line(text, part.row(i));
                }
            });
        for t in &texts[..group.len()] {
            out.write_all(t.as_bytes())?;
        }
    }
    Ok(())
}

/// How a table's lines are laid out.
struct Layout<'a> {
    width: &'a [usize],
    align: &'a [Align],
}

impl Layout<'_> {
    /// One line of `cells` at the end of `out`: padded, two spaces apart,
    /// no blanks at its end.
    fn line<'c>(&self, out: &mut String, cells: impl Iterator<Item = &'c str>) {
        const SPACES: &str = "                                                                ";
        let pad = |out: &mut String, mut n: usize| {
            while n > 0 {
                let k = n.min(SPACES.len());
                out.push_str(&SPACES[..k]);
                n -= k;
            }
        };
        let ncol = self.width.len();
        let start = out.len();
        // Blanks owed before the next cell's text: the two between cells
        // and a left-aligned cell's padding, written with the next one's
        // (one copy of blanks a cell, not three).
        let mut owed = 0;
        for (i, cell) in cells.enumerate().take(ncol) {
            let n = if cell.is_ascii() {
                cell.len()
            } else {
                cell.chars().count()
            };
            let fill = self.width[i] - n;
            if self.align.get(i).copied().unwrap_or(Align::Left) == Align::Right {
                pad(out, owed + fill);
                out.push_str(cell);
                owed = 2;
            } else {
                pad(out, owed);
                out.push_str(cell);
                owed = fill + 2;
            }
        }
        let end = start + out[start..].trim_end().len();
        out.truncate(end);
        out.push('\n');
    }
}

/// Rows as CSV (RFC 4180 quoting where a cell needs it).
pub fn render_csv(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    // Writing to a Vec cannot fail.
    let _ = w.write_record(header);
    for row in rows {
        let _ = w.write_record(row);
    }
    let bytes = w.into_inner().unwrap_or_default();
    String::from_utf8(bytes).unwrap_or_default()
}

/// Write `v` as `{v}` writes it (the shortest text that reads back as
/// the same number), `-0` as `0`.
pub fn shortest(buf: &mut String, v: f64) {
    use std::fmt::Write as _;
    let start = buf.len();
    let _ = write!(buf, "{v}");
    if &buf[start..] == "-0" {
        buf.truncate(start);
        buf.push('0');
    }
}

/// [`shortest`] of the number a decimal literal reads as, from its text
/// alone (`+420.080` → `420.08`, `-.5` → `-0.5`, `-0.0` → `0`): without
/// formatting a float, which is most of the time a listing of a million
/// targets takes. Only for literals without exponent of at most 15
/// significant digits (counting zeros after the point), where it is
/// exact: two such decimals never read as the same `f64`, so the literal
/// is the one shortest text of its value. `false` (nothing written)
/// otherwise.
pub fn shortest_of_literal(buf: &mut String, text: &str) -> bool {
    shortest_of_literal_bytes(buf, text.as_bytes())
}

/// [`shortest_of_literal`] of a literal's bytes as the file holds them
/// (a listing reads its numbers' text from the file).
pub fn shortest_of_literal_bytes(buf: &mut String, text: &[u8]) -> bool {
    let (negative, digits) = match text.first() {
        Some(b'-') => (true, &text[1..]),
        Some(b'+') => (false, &text[1..]),
        _ => (false, text),
    };
    let (int, frac) = match digits.iter().position(|&c| c == b'.') {
        Some(p) => (&digits[..p], &digits[p + 1..]),
        None => (digits, &digits[digits.len()..]),
    };
    if int.is_empty() && frac.is_empty()
        || !int.iter().all(u8::is_ascii_digit)
        || !frac.iter().all(u8::is_ascii_digit)
    {
        return false;
    }
    let int = &int[int.iter().position(|&c| c != b'0').unwrap_or(int.len())..];
    let frac = &frac[..frac.iter().rposition(|&c| c != b'0').map_or(0, |p| p + 1)];
    if int.len() + frac.len() > 15 {
        return false;
    }
    if int.is_empty() && frac.is_empty() {
        buf.push('0');
        return true;
    }
    if negative {
        buf.push('-');
    }
    if int.is_empty() {
        buf.push('0');
    }
    buf.push_str(ascii(int));
    if !frac.is_empty() {
        buf.push('.');
        buf.push_str(ascii(frac));
    }
    true
}

/// Digits, checked to be: ASCII.
fn ascii(digits: &[u8]) -> &str {
    std::str::from_utf8(digits).unwrap_or_default()
}

/// [`shortest`] of `(v * 1e4).round() / 1e4`, what a listing shows of an
/// angle (to 0.0001°). The quotient of the rounded integer by 10⁴ is the
/// `f64` nearest to that decimal, and so (it has at most 15 significant
/// digits) prints as it: written from the integer, without formatting a
/// float.
pub fn shortest_to_4_places(buf: &mut String, v: f64) {
    let r = (v * 1e4).round();
    if r.is_nan() || r.abs() >= 1e15 {
        shortest(buf, r / 1e4);
        return;
    }
    let k = r as i64;
    if k < 0 {
        buf.push('-');
    }
    let (int, mut frac) = (k.unsigned_abs() / 10_000, k.unsigned_abs() % 10_000);
    buf.push_str(itoa::Buffer::new().format(int));
    if frac > 0 {
        let mut places = 4;
        while frac % 10 == 0 {
            frac /= 10;
            places -= 1;
        }
        buf.push('.');
        let mut digits = itoa::Buffer::new();
        let digits = digits.format(frac);
        for _ in digits.len()..places {
            buf.push('0');
        }
        buf.push_str(digits);
    }
}

/// A length in mm with a fixed number of decimals, `-0.000` printed as
/// `0.000` so that golden files do not flip on rounding noise.
pub fn mm(value: f64, decimals: usize) -> String {
    let s = format!("{value:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_aligns_columns() {
        let rows = vec![
            vec!["p10".to_string(), "1.5".to_string()],
            vec!["main#12".to_string(), "-10.25".to_string()],
        ];
        let t = render_table(&["target", "dx"], &[Align::Left, Align::Right], &rows);
        assert_eq!(
            t,
            "target       dx\n-------  ------\np10         1.5\nmain#12  -10.25\n"
        );
    }

    /// Widths are characters, not bytes (a Latin-1 name read as UTF-8),
    /// rows may be short and cells empty: what the layout pads, and what
    /// it leaves off a line's end.
    #[test]
    fn table_of_uneven_rows_and_wide_characters() {
        let rows = vec![
            vec!["pÄ1".to_string(), "1".to_string(), "x".to_string()],
            vec!["p2".to_string()],
            vec!["p3".to_string(), "".to_string(), "".to_string()],
            vec!["p4444".to_string(), "22".to_string(), "".to_string()],
        ];
        let align = [Align::Left, Align::Right, Align::Left];
        let t = render_table(&["t", "n", "w"], &align, &rows);
        assert_eq!(
            t,
            "t       n  w\n-----  --  -\npÄ1     1  x\np2\np3\np4444  22\n"
        );
        let mut cells = Rows::default();
        for row in &rows {
            for cell in row {
                cells.cell(cell);
            }
            cells.end_row();
        }
        assert_eq!(cells.widths(), [5, 2, 1]);
        assert_eq!(cells.row(1).collect::<Vec<_>>(), ["p2"]);
        assert_eq!(cells.row(3).collect::<Vec<_>>(), ["p4444", "22", ""]);
        assert_eq!(cells.row(4).count(), 0);
    }

    #[test]
    fn csv_quotes_when_needed() {
        let rows = vec![vec!["a,b".to_string(), "1".to_string()]];
        assert_eq!(render_csv(&["name", "v"], &rows), "name,v\n\"a,b\",1\n");
    }

    #[test]
    fn literals_print_as_their_value_would() {
        for text in [
            "420.080",
            "+420.08",
            "-150.000",
            "-.5",
            ".5",
            "1.",
            "007",
            "-0.0",
            "0",
            "-0",
            "0.000120",
            "123456789012345",
            "-99999.9999999999",
            "1000000",
            "0.000000000000001",
        ] {
            let mut buf = String::new();
            assert!(shortest_of_literal(&mut buf, text), "{text}");
            let mut want = String::new();
            shortest(&mut want, text.parse::<f64>().unwrap());
            assert_eq!(buf, want, "{text}");
        }
        for text in [
            "9E9",
            "1234567890123456",
            "0.0000000000000001",
            "-",
            ".",
            "1.2.3",
            "",
        ] {
            assert!(!shortest_of_literal(&mut String::new(), text), "{text}");
        }
    }

    #[test]
    fn angles_print_as_their_rounded_value_would() {
        for v in [
            180.0,
            -180.0,
            0.0,
            -0.0,
            -0.00001,
            0.00005,
            12.34565,
            -45.000049,
            89.99999,
            1e-9,
            -123.45678,
            1e11,
            3e15,
            f64::NAN,
        ] {
            let mut buf = String::new();
            shortest_to_4_places(&mut buf, v);
            let mut want = String::new();
            shortest(&mut want, (v * 1e4).round() / 1e4);
            assert_eq!(buf, want, "{v}");
        }
    }

    #[test]
    fn negative_zero_prints_as_zero() {
        assert_eq!(mm(-0.0001, 3), "0.000");
        assert_eq!(mm(-0.0006, 3), "-0.001");
    }
}
