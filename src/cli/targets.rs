//! `rapidtherm targets FILE...`: every robtarget of RAPID programs.
use super::Format;
use super::{write_stdout, Status};
use rapidtherm::error::Result;
use rapidtherm::rapid::{self, Target};
use rapidtherm::report::{render_csv, render_table, Align};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct TargetsArgs {
    /// RAPID files (.mod, .modx, .prg, .sys); `-` reads standard input.
    /// Several files are read as one run (identifiers unique across them).
    /// A program file (.pgf), a task folder or a controller backup: each
    /// task is one run.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub pick: super::tasks::TaskPick,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// List the jointtargets (MoveAbsJ positions, degrees) instead.
    #[arg(long)]
    pub joints: bool,
}

/// Shortest text that reads back as the same number.
fn n(v: f64) -> String {
    let s = format!("{v}");
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

fn values(t: &Target) -> Vec<String> {
    match &t.value {
        Some(v) => v
            .trans_values()
            .into_iter()
            .chain(v.rot_values())
            .chain(v.robconf_values())
            .map(n)
            .collect(),
        None => vec![String::new(); 11],
    }
}

pub fn run(args: TargetsArgs) -> Result<Status> {
    let tasks = super::tasks::select(&args.files, &args.pick)?;
    let refs: Vec<&rapidtherm::rapid::task::Task> = tasks.iter().collect();
    let labels = super::tasks::labels(&refs);
    let mut texts = Vec::new();
    for task in &tasks {
        let (inputs, prog) = super::tasks::read(task)?;
        texts.push(if args.joints {
            joints(&prog, args.format)
        } else {
            listing(&args, &inputs, &prog)?
        });
    }
    let key = if args.joints {
        "jointtargets"
    } else {
        "targets"
    };
    let out = super::tasks::join(args.format, labels.as_deref(), texts, key, &[])?;
    write_stdout(out.as_bytes())?;
    Ok(Status::Success)
}

/// The listing of one program's robtargets.
fn listing(
    args: &TargetsArgs,
    inputs: &super::Inputs,
    prog: &rapidtherm::rapid::Program,
) -> Result<String> {
    let several = inputs.len() > 1;
    let opt = |s: &Option<std::sync::Arc<str>>| s.as_deref().unwrap_or("").to_string();
    let out = match args.format {
        Format::Table => {
            let header = [
                "target", "kind", "at", "x", "y", "z", "q1", "q2", "q3", "q4", "robconf", "tool",
                "wobj",
            ];
            let mut align = vec![Align::Left, Align::Left, Align::Left];
            align.extend([Align::Right; 7]);
            align.extend([Align::Left; 3]);
            let rows: Vec<Vec<String>> = prog
                .targets()
                .iter()
                .map(|t| {
                    let at = if several {
                        format!(
                            "{}:{}:{}",
                            prog.files[t.origin.file], t.origin.pos.line, t.origin.pos.col
                        )
                    } else {
                        format!("{}:{}", t.origin.pos.line, t.origin.pos.col)
                    };
                    let mut r = vec![t.id.clone(), t.kind.as_str().to_string(), at];
                    let v = values(t);
                    match &t.derived {
                        Some(d) if t.value.is_none() => {
                            r.extend(std::iter::repeat_n(String::new(), 7));
                            r.push(format!("= {}", d.expr));
                        }
                        _ => {
                            r.extend(v[..7].iter().cloned());
                            r.push(format!("[{}]", v[7..11].join(",")));
                        }
                    }
                    r.push(opt(&t.tool));
                    r.push(opt(&t.wobj));
                    r
                })
                .collect();
            render_table(&header, &align, &rows)
        }
        Format::Csv => {
            let header = [
                "target",
                "kind",
                "file",
                "line",
                "col",
                "x",
                "y",
                "z",
                "q1",
                "q2",
                "q3",
                "q4",
                "cf1",
                "cf4",
                "cf6",
                "cfx",
                "tool",
                "wobj",
                "instruction",
                "module",
                "routine",
                "derived_from",
                "expression",
            ];
            let rows: Vec<Vec<String>> = prog
                .targets()
                .iter()
                .map(|t| {
                    let mut r = vec![
                        t.id.clone(),
                        t.kind.as_str().to_string(),
                        prog.files[t.origin.file].clone(),
                        t.origin.pos.line.to_string(),
                        t.origin.pos.col.to_string(),
                    ];
                    r.extend(values(t));
                    r.push(opt(&t.tool));
                    r.push(opt(&t.wobj));
                    r.push(opt(&t.instruction));
                    r.push(t.origin.module.to_string());
                    r.push(opt(&t.origin.routine));
                    let (bases, expr) = t
                        .derived
                        .as_ref()
                        .map(|d| (d.bases.join(" "), d.expr.clone()))
                        .unwrap_or_default();
                    r.push(bases);
                    r.push(expr);
                    r
                })
                .collect();
            render_csv(&header, &rows)
        }
        Format::Json => {
            let items: Vec<serde_json::Value> = prog
                .targets()
                .iter()
                .map(|t| {
                    let v = t.value.as_ref();
                    serde_json::json!({
                        "target": t.id,
                        "kind": t.kind.as_str(),
                        "file": prog.files[t.origin.file],
                        "line": t.origin.pos.line,
                        "col": t.origin.pos.col,
                        "module": &*t.origin.module,
                        "routine": t.origin.routine.as_deref(),
                        "trans": v.map(|v| v.trans_values()),
                        "rot": v.map(|v| v.rot_values()),
                        "robconf": v.map(|v| v.robconf_values()),
                        "extax": v.map(|v| v.extax_values()),
                        "instruction": t.instruction.as_deref(),
                        "tool": t.tool.as_deref(),
                        "wobj": t.wobj.as_deref(),
                        "derived": t.derived.as_ref().map(|d| serde_json::json!({
                            "expression": d.expr,
                            "function": d.function,
                            "bases": d.bases,
                        })),
                    })
                })
                .collect();
            let mut s = serde_json::to_string_pretty(&items).unwrap_or_default();
            s.push('\n');
            s
        }
    };
    Ok(out)
}

fn joints(prog: &rapid::Program, format: Format) -> String {
    let header = [
        "target", "kind", "file", "line", "col", "j1", "j2", "j3", "j4", "j5", "j6", "tool", "wobj",
    ];
    let opt = |s: &Option<std::sync::Arc<str>>| s.as_deref().unwrap_or("").to_string();
    let rows: Vec<Vec<String>> = prog
        .jointtargets()
        .iter()
        .map(|j| {
            let mut r = vec![
                j.id.clone(),
                j.kind.as_str().to_string(),
                prog.files[j.origin.file].clone(),
                j.origin.pos.line.to_string(),
                j.origin.pos.col.to_string(),
            ];
            r.extend(j.robax.iter().map(|x| n(x.value)));
            r.push(opt(&j.tool));
            r.push(opt(&j.wobj));
            r
        })
        .collect();
    match format {
        Format::Table => {
            let mut align = vec![Align::Left; 5];
            align.extend([Align::Right; 6]);
            align.extend([Align::Left; 2]);
            render_table(&header, &align, &rows)
        }
        Format::Csv => render_csv(&header, &rows),
        Format::Json => {
            let items: Vec<serde_json::Value> = prog
                .jointtargets()
                .iter()
                .map(|j| {
                    serde_json::json!({
                        "target": j.id,
                        "kind": j.kind.as_str(),
                        "file": prog.files[j.origin.file],
                        "line": j.origin.pos.line,
                        "col": j.origin.pos.col,
                        "robax": j.robax.iter().map(|x| x.value).collect::<Vec<_>>(),
                        "extax": j.extax.iter().map(|x| x.value).collect::<Vec<_>>(),
                        "instruction": j.instruction.as_deref(),
                        "tool": j.tool.as_deref(),
                        "wobj": j.wobj.as_deref(),
                    })
                })
                .collect();
            let mut s = serde_json::to_string_pretty(&items).unwrap_or_default();
            s.push('\n');
            s
        }
    }
}
