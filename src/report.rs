//! Rendering of tabular results for people (aligned table) and scripts
//! (CSV, JSON). Commands build rows of strings; this module lays them out.
//!
//! A foundation: imports nothing of the library. Which format a run prints
//! is the CLI's choice.

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
    let ncol = header.len();
    let mut width: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (i, cell) in row.iter().enumerate().take(ncol) {
            width[i] = width[i].max(cell.chars().count());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = &str>| -> String {
        let mut out = String::new();
        for (i, cell) in cells.enumerate().take(ncol) {
            if i > 0 {
                out.push_str("  ");
            }
            let pad = width[i] - cell.chars().count();
            let right = align.get(i).copied().unwrap_or(Align::Left) == Align::Right;
            if right {
                out.extend(std::iter::repeat_n(' ', pad));
                out.push_str(cell);
            } else {
                out.push_str(cell);
                if i + 1 < ncol {
                    out.extend(std::iter::repeat_n(' ', pad));
                }
            }
        }
        out.truncate(out.trim_end().len());
        out.push('\n');
        out
    };
    let mut out = line(&mut header.iter().copied());
    let rule: Vec<String> = width.iter().map(|w| "-".repeat(*w)).collect();
    out.push_str(&line(&mut rule.iter().map(String::as_str)));
    for row in rows {
        out.push_str(&line(&mut row.iter().map(String::as_str)));
    }
    out
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

    #[test]
    fn csv_quotes_when_needed() {
        let rows = vec![vec!["a,b".to_string(), "1".to_string()]];
        assert_eq!(render_csv(&["name", "v"], &rows), "name,v\n\"a,b\",1\n");
    }

    #[test]
    fn negative_zero_prints_as_zero() {
        assert_eq!(mm(-0.0001, 3), "0.000");
        assert_eq!(mm(-0.0006, 3), "-0.001");
    }
}
