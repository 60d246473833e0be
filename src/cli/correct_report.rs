//! The per-target report of `rapidtherm correct`: each correction with the
//! tool and work object it is made for, the frame and units of its
//! numbers, then the targets left alone, derived, split or used with
//! other frames.

use super::correct_words::{reason_words, shared_words};
use super::Format;
use rapidtherm::correct::{Frame, Outcome};
use rapidtherm::error::Result;
use rapidtherm::report::{mm, render_csv, render_table, Align};

/// The report's columns. The table's names carry their units; CSV keeps
/// the names scripts read (`dx`, ...) and gains the new columns at the
/// end.
const TABLE_HEADER: [&str; 13] = [
    "target",
    "kind",
    "line",
    "minute",
    "tool",
    "wobj",
    "drift_mm",
    "dx_mm",
    "dy_mm",
    "dz_mm",
    "corr_mm",
    "dangle_deg",
    "rewritten",
];
const CSV_HEADER: [&str; 14] = [
    "target",
    "kind",
    "line",
    "minute",
    "drift_mm",
    "dx",
    "dy",
    "dz",
    "corr_mm",
    "dangle_deg",
    "rewritten",
    "tool",
    "wobj",
    "frame",
];

/// The per-target report: corrected against original.
pub fn report(outcome: &Outcome, format: Format) -> Result<String> {
    let numbers = |c: &rapidtherm::correct::Correction| -> Vec<String> {
        vec![
            mm(c.drift_norm_mm, 4),
            mm(c.correction_mm[0], 4),
            mm(c.correction_mm[1], 4),
            mm(c.correction_mm[2], 4),
            mm(c.correction_norm_mm, 4),
            mm(c.dangle_deg, 6),
            if c.rewritten { "yes" } else { "no" }.to_string(),
        ]
    };
    let minute = |c: &rapidtherm::correct::Correction| {
        c.time_min
            .map_or("steady".to_string(), |t| format!("{t:.2}"))
    };
    Ok(match format {
        Format::Json => rapidtherm::report::json::document("correct", outcome)?,
        Format::Csv => {
            let rows: Vec<Vec<String>> = outcome
                .corrections
                .iter()
                .map(|c| {
                    let mut r = vec![
                        c.id.clone(),
                        c.kind.to_string(),
                        c.line.to_string(),
                        minute(c),
                    ];
                    r.extend(numbers(c));
                    r.push(c.tool.clone().unwrap_or_default());
                    r.push(c.wobj.clone().unwrap_or_default());
                    r.push(c.frame.code().to_string());
                    r
                })
                .collect();
            render_csv(&CSV_HEADER, &rows)
        }
        Format::Table => {
            // A target also moved to with other pairs is marked: its
            // numbers are right for the pair shown, its first use's.
            let shared = |c: &rapidtherm::correct::Correction| {
                outcome
                    .shared
                    .iter()
                    .any(|u| u.id == c.id && u.file == c.file && u.line == c.line)
            };
            let mut marked = false;
            let rows: Vec<Vec<String>> = outcome
                .corrections
                .iter()
                .map(|c| {
                    let mut r = vec![
                        c.id.clone(),
                        c.kind.to_string(),
                        c.line.to_string(),
                        minute(c),
                    ];
                    r.push(c.tool.clone().unwrap_or_else(|| "-".to_string()));
                    let mut wobj = c.wobj.clone().unwrap_or_else(|| "-".to_string());
                    if shared(c) {
                        wobj.push('*');
                        marked = true;
                    }
                    r.push(wobj);
                    r.extend(numbers(c));
                    r
                })
                .collect();
            let mut align = vec![Align::Left, Align::Left, Align::Right, Align::Right];
            align.extend([Align::Left; 2]);
            align.extend([Align::Right; 6]);
            align.push(Align::Left);
            let mut text = render_table(&TABLE_HEADER, &align, &rows);
            text.push_str(&legend(outcome));
            if marked {
                text.push_str("*: also moved to with other tools or work objects; corrected for the pair shown, its first use (the other uses are listed below)\n");
            }
            text.push_str(&lines(outcome));
            text
        }
    })
}

/// The frame of the table's numbers, for the kinds of targets it lists.
fn legend(outcome: &Outcome) -> String {
    let has = |f: Frame| outcome.corrections.iter().any(|c| c.frame == f);
    let mut text = String::new();
    if has(Frame::WobjObject) {
        text.push_str("frame: drift_mm and dx_mm, dy_mm, dz_mm are in the object frame of the row's wobj, the frame the target's x, y, z are written in\n");
    }
    if has(Frame::BaseFlange) {
        text.push_str("frame: for jointtargets (tool -), drift_mm and dx_mm, dy_mm, dz_mm are at the flange in the robot base frame\n");
    }
    text
}

/// The report's lines below the table: targets left as written and why,
/// derived targets, residuals, other uses, splits.
fn lines(outcome: &Outcome) -> String {
    let mut text = String::new();
    for d in &outcome.derived {
        let residual = match d.residual_mm {
            Some(r) => format!("residual drift {} mm", mm(r, 4)),
            None => "its pose is known only at run time".to_string(),
        };
        text.push_str(&format!(
            "derived {} (line {}): {} left as written; its bases move by up to {} mm; {}\n",
            d.id,
            d.line,
            d.expr,
            mm(d.base_correction_mm, 4),
            residual
        ));
    }
    for l in &outcome.left_alone {
        text.push_str(&format!(
            "left alone {} {} (line {}): {}: {}\n",
            l.kind,
            l.id,
            l.line,
            l.reason.code(),
            reason_words(l.reason, l.kind, &l.detail)
        ));
    }
    for r in &outcome.residuals {
        text.push_str(&format!(
            "residual {} (line {}): {} mm, {}° at the flange ({})\n",
            r.id,
            r.line,
            mm(r.position_mm, 4),
            mm(r.angle_deg, 4),
            r.rule
        ));
    }
    for u in &outcome.shared {
        text.push_str(&format!(
            "other use {} (line {}): {}\n",
            u.id,
            u.line,
            shared_words(u)
        ));
    }
    for s in &outcome.splits {
        let moves: Vec<String> = s
            .moves
            .iter()
            .map(|m| format!("{} in {} line {}", m.instruction, m.routine, m.line))
            .collect();
        text.push_str(&format!(
            "split {} (line {}): copy {} declared after it, corrected for tool {}, wobj {}; now named by {}\n",
            s.id,
            s.line,
            s.copy,
            s.tool,
            s.wobj,
            moves.join(", ")
        ));
    }
    text
}
