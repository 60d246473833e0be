//! `diff`: the targets of two programs compared, and a CI gate on how far
//! any moved.

use super::ci_report::{self, Compared, ReportFormat};
use super::messages::{self, error, note};
use super::tasks::{self, TaskPick};
use super::Format;
use super::{read_input, write_stdout, Status};
use rapidtherm::compare::{diff, max_limit_deg, max_limit_mm, DataType, Diff, Gate, GateFailure};
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid;
use rapidtherm::rapid::task::Task;
use rapidtherm::report::{mm, render_csv, render_table, Align};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct DiffArgs {
    /// The original program: a RAPID file, a program file (.pgf), a task
    /// folder or a controller backup (tasks are compared by name).
    pub a: PathBuf,
    /// The program to compare with it (e.g. the corrected one).
    pub b: PathBuf,
    /// Format of the comparison; with a gate also github or junit, for CI
    /// (docs/ci.md).
    #[arg(long, value_enum, default_value_t = ReportFormat::Table)]
    pub format: ReportFormat,
    /// A CI gate: exit 1 when a robtarget moved more than this (mm), a
    /// target is in one program only, or the programs have no target in
    /// common; each failing target is named on stderr.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    pub fail_above: Option<f64>,
    /// The gate's angle: exit 1 when a jointtarget's joint or a
    /// robtarget's orientation turned more than this (degrees). Default
    /// with --fail-above: the turn that moves a point 100 mm from its axis
    /// by MM (MM/100 mm rad: 0.15 mm → 0.086°, 0.5 mm → 0.29°), which every
    /// thermal correction passes and a re-taught jointtarget does not.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub fail_above_deg: Option<f64>,
    /// With backups or task folders: compare only this task (repeatable).
    #[arg(long = "task", value_name = "NAME")]
    pub task: Vec<String>,
}

/// A gate threshold as given: from 0 to `most` (data/gate.toml: beyond
/// it every thermal correction and every re-taught target passes alike).
fn threshold(value: Option<f64>, flag: &str, unit: &str, most: f64) -> Result<Option<f64>> {
    match value {
        Some(v) if !(v.is_finite() && v >= 0.0 && v <= most) => Err(Error::usage(format!(
            "{flag} {}: the limit must be a number of {unit} from 0 to {} (beyond it, a re-taught target passes as a thermal correction would)",
            shown(v),
            mm(most, 2).trim_end_matches('0').trim_end_matches('.')
        ))),
        v => Ok(v),
    }
}

/// A number as given, in few characters (`1e308`, not 309 digits).
fn shown(v: f64) -> String {
    if v.abs() >= 1e6 {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// Everything `diff` does, read from its arguments once.
pub struct DiffCommand {
    a: PathBuf,
    b: PathBuf,
    format: ReportFormat,
    gate: Option<Gate>,
    /// The gate's angle is the default one for its distance (no
    /// `--fail-above-deg`).
    default_deg: bool,
    pick: TaskPick,
}

/// The plan of `diff`'s arguments: every usage error is raised here,
/// before any file is read.
pub fn plan(args: DiffArgs) -> Result<DiffCommand> {
    let max_mm = threshold(args.fail_above, "--fail-above", "mm", max_limit_mm())?;
    let max_deg = threshold(
        args.fail_above_deg,
        "--fail-above-deg",
        "degrees",
        max_limit_deg(),
    )?;
    let gate = match (max_mm, max_deg) {
        (None, None) => None,
        _ => Some(Gate::new(max_mm, max_deg)?),
    };
    ci_report::refuse_outside_gate(args.format, gate.is_some())?;
    Ok(DiffCommand {
        a: args.a,
        b: args.b,
        format: args.format,
        gate,
        default_deg: max_deg.is_none(),
        pick: TaskPick { tasks: args.task },
    })
}

pub fn run(cmd: DiffCommand) -> Result<Status> {
    let gate = cmd.gate;
    let pick = cmd.pick;
    let ta = tasks::select(std::slice::from_ref(&cmd.a), &pick)?;
    let tb = tasks::select(std::slice::from_ref(&cmd.b), &pick)?;
    let named = ta.iter().chain(&tb).any(|t| t.name.is_some());
    if !named {
        let (na, ba) = read_input(&cmd.a)?;
        let (nb, bb) = read_input(&cmd.b)?;
        let a = rapid::parse(&na, &ba)?;
        let b = rapid::parse(&nb, &bb)?;
        let d = diff(&a, &b)?;
        let text = match cmd.format.data() {
            Some(format) => render_diff(&d, format)?,
            None => ci_report::gate(
                cmd.format,
                gate.as_ref(),
                &[Compared {
                    task: None,
                    names: (&na, &nb),
                    programs: (&a, &b),
                    diff: &d,
                }],
                &[],
            )?,
        };
        write_stdout(text.as_bytes())?;
        let Some(gate) = gate else {
            return Ok(Status::Success);
        };
        let failures = d.gate(&gate);
        if failures.is_empty() {
            return Ok(Status::Success);
        }
        messages::outcome_lines(&gate_message(&gate, cmd.default_deg, &failures, &na, &nb));
        return Ok(Status::Changes);
    }
    // Tasks pair by name; two single tasks pair whatever their names.
    let pairs: Vec<(&Task, &Task)> = if ta.len() == 1 && tb.len() == 1 {
        vec![(&ta[0], &tb[0])]
    } else {
        ta.iter()
            .filter_map(|a| {
                tb.iter()
                    .find(|b| b.label().eq_ignore_ascii_case(&a.label()))
                    .map(|b| (a, b))
            })
            .collect()
    };
    let unpaired: Vec<String> = ta
        .iter()
        .filter(|a| !pairs.iter().any(|(p, _)| std::ptr::eq(*p, *a)))
        .map(|a| format!("task {} is only in {}", a.label(), cmd.a.display()))
        .chain(
            tb.iter()
                .filter(|b| !pairs.iter().any(|(_, q)| std::ptr::eq(*q, *b)))
                .map(|b| format!("task {} is only in {}", b.label(), cmd.b.display())),
        )
        .collect();
    let mut texts = Vec::new();
    let mut labels = Vec::new();
    let mut message = String::new();
    let mut compared = Vec::new();
    for (a, b) in &pairs {
        let (_, pa) = tasks::read(a)?;
        let (_, pb) = tasks::read(b)?;
        let d = diff(&pa, &pb)?;
        if let Some(format) = cmd.format.data() {
            texts.push(render_diff(&d, format)?);
        }
        labels.push(a.label());
        if let Some(gate) = &gate {
            let failures = d.gate(gate);
            if !failures.is_empty() {
                message.push_str(&format!("task {}: ", a.label()));
                message.push_str(&gate_message(
                    gate,
                    cmd.default_deg,
                    &failures,
                    &cmd.a.display().to_string(),
                    &cmd.b.display().to_string(),
                ));
            }
        }
        if cmd.format.data().is_none() {
            compared.push((pa, pb, d));
        }
    }
    let text = match cmd.format.data() {
        Some(format) => tasks::join(format, Some(&labels), texts, &[])?,
        None => {
            let (na, nb) = (cmd.a.display().to_string(), cmd.b.display().to_string());
            let pairs: Vec<Compared> = labels
                .iter()
                .zip(&compared)
                .map(|(label, (pa, pb, d))| Compared {
                    task: Some(label.clone()),
                    names: (&na, &nb),
                    programs: (pa, pb),
                    diff: d,
                })
                .collect();
            ci_report::gate(cmd.format, gate.as_ref(), &pairs, &unpaired)?
        }
    };
    write_stdout(text.as_bytes())?;
    for u in &unpaired {
        if gate.is_some() {
            error!("{u}");
        } else {
            note!("{u}");
        }
    }
    messages::outcome_lines(&message);
    Ok(
        if gate.is_some() && (!message.is_empty() || !unpaired.is_empty()) {
            Status::Changes
        } else {
            Status::Success
        },
    )
}

/// Why the gate failed, target by target.
fn gate_message(
    gate: &Gate,
    default_deg: bool,
    failures: &[GateFailure],
    a: &str,
    b: &str,
) -> String {
    let mut limits = Vec::new();
    if gate.max_mm.is_finite() {
        limits.push(format!("{} mm", gate.max_mm));
    }
    if default_deg {
        limits.push(format!(
            "{}° (default for {} mm)",
            mm(gate.max_deg, 4),
            gate.max_mm
        ));
    } else if gate.max_deg.is_finite() {
        limits.push(format!("{}°", gate.max_deg));
    }
    let mut lines = Vec::new();
    let mut nothing = false;
    for f in failures {
        match f {
            GateFailure::Moved(t) if t.kind == DataType::Jointtarget => lines.push(format!(
                "  {}: jointtarget, a joint turned {}°{}",
                t.id,
                mm(t.dangle, 6),
                also(t)
            )),
            GateFailure::Moved(t) => lines.push(format!(
                "  {}: {} moved {} mm, turned {}°{}",
                t.id,
                t.kind,
                mm(t.dist, 4),
                mm(t.dangle, 6),
                also(t)
            )),
            GateFailure::OnlyInFirst(id) => lines.push(format!("  {id}: only in {a}")),
            GateFailure::OnlyInSecond(id) => lines.push(format!("  {id}: only in {b}")),
            GateFailure::NothingCompared => nothing = true,
        }
    }
    let mut text = String::new();
    if !lines.is_empty() {
        text.push_str(&format!(
            "{} target(s) fail the gate of {}:\n",
            lines.len(),
            limits.join(" and ")
        ));
        for l in lines {
            text.push_str(&l);
            text.push('\n');
        }
    }
    if nothing {
        text.push_str(&format!(
            "{a} and {b} have no target in common: nothing was compared, the gate fails\n"
        ));
    }
    text
}

/// What changed of a target besides its pose, after a comma (nothing
/// where nothing did): a robconf or an external axis fails any gate.
fn also(t: &rapidtherm::compare::TargetDelta) -> String {
    t.also_changed().iter().map(|w| format!(", {w}")).collect()
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
        Format::Json => rapidtherm::report::json::document("diff", d)?,
        Format::Csv => render_csv(&header, &rows),
        Format::Table => {
            let mut align = vec![Align::Left, Align::Left];
            align.extend([Align::Right; 5]);
            let mut table_header = header;
            table_header[2..5].copy_from_slice(&["dx_mm", "dy_mm", "dz_mm"]);
            let mut text = render_table(&table_header, &align, &rows);
            if !rows.is_empty() {
                text.push_str("frame: dx_mm, dy_mm, dz_mm are in the frame each target is written in (the object frame of the work object it is used with); for jointtargets dangle_deg is the largest joint change\n");
            }
            for t in d.targets.iter().filter(|t| !t.also_changed().is_empty()) {
                text.push_str(&format!("{}: {}\n", t.id, t.also_changed().join(", ")));
            }
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
