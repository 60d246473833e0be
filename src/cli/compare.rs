//! `diff`: the targets of two programs compared, and a CI gate on how far
//! any moved.

use super::Format;
use super::{read_input, write_stdout, Status};
use rapidtherm::compare::{diff, Diff};
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid;
use rapidtherm::report::{mm, render_csv, render_table, Align};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct DiffArgs {
    /// The original program.
    pub a: PathBuf,
    /// The program to compare with it (e.g. the corrected one).
    pub b: PathBuf,
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Exit 1 when any target moved more than this (mm): a CI gate.
    #[arg(long, value_name = "MM")]
    pub fail_above: Option<f64>,
}

pub fn run_diff(args: DiffArgs) -> Result<Status> {
    let (na, ba) = read_input(&args.a)?;
    let (nb, bb) = read_input(&args.b)?;
    let a = rapid::parse(&na, &ba)?;
    let b = rapid::parse(&nb, &bb)?;
    let d = diff(&a, &b)?;
    write_stdout(render_diff(&d, args.format)?.as_bytes())?;
    if let Some(limit) = args.fail_above {
        let over = d.targets.iter().filter(|t| t.dist > limit).count();
        if over > 0 {
            eprintln!("{over} target(s) moved more than {limit} mm");
            return Ok(Status::Changes);
        }
    }
    Ok(Status::Success)
}

fn render_diff(d: &Diff, format: Format) -> Result<String> {
    let header = ["target", "kind", "dx", "dy", "dz", "dist_mm", "dangle_deg"];
    let rows: Vec<Vec<String>> = d
        .targets
        .iter()
        .map(|t| {
            vec![
                t.id.clone(),
                t.kind.to_string(),
                mm(t.dx, 4),
                mm(t.dy, 4),
                mm(t.dz, 4),
                mm(t.dist, 4),
                mm(t.dangle, 6),
            ]
        })
        .collect();
    Ok(match format {
        Format::Json => {
            serde_json::to_string_pretty(d).map_err(|e| Error::input(e.to_string()))? + "\n"
        }
        Format::Csv => render_csv(&header, &rows),
        Format::Table => {
            let mut align = vec![Align::Left, Align::Left];
            align.extend([Align::Right; 5]);
            let mut text = render_table(&header, &align, &rows);
            for id in &d.only_in_a {
                text.push_str(&format!("only in the first: {id}\n"));
            }
            for id in &d.only_in_b {
                text.push_str(&format!("only in the second: {id}\n"));
            }
            let s = &d.summary;
            text.push_str(&format!(
                "{} compared, {} changed: max {} mm, RMS {} mm, max {}°\n",
                s.compared,
                s.changed,
                mm(s.max_mm, 4),
                mm(s.rms_mm, 4),
                mm(s.max_deg, 6)
            ));
            text
        }
    })
}
