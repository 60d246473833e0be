//! `rapidtherm targets FILE...`: every robtarget of RAPID programs.
use super::Format;
use super::{write_stdout, Status};
use rapidtherm::error::Result;
use rapidtherm::rapid::{self, Target};
use rapidtherm::report::{render_csv, render_table, Align};
use rapidtherm::resolve::{self, Usage};
use rapidtherm::robot::euler::euler_zyx_deg;
use rapidtherm::robot::frames::pose_from_rapid;
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

/// The tool/work-object pairs a target is moved to with, as
/// [`resolve::uses_by_frames`] groups them: in program order of each
/// pair's first use, so the first is the one `correct` corrects it for.
/// Names as written, `tool0`/`wobj0` where the move names none (RAPID's
/// defaults). Empty: no move instruction reaches the target.
fn pairs(t: &Target, uses: Option<&Vec<Usage>>) -> Vec<(String, String)> {
    match uses {
        Some(u) if !u.is_empty() => resolve::uses_by_frames(u)
            .iter()
            .map(|g| (g[0].tool_name().to_string(), g[0].wobj_name().to_string()))
            .collect(),
        // A derived target written in a move (`MoveL Offs(p10, ...)`):
        // its bases carry the uses, the target the move's own names.
        _ if t.instruction.is_some() => vec![(
            t.tool.as_deref().unwrap_or("tool0").to_string(),
            t.wobj.as_deref().unwrap_or("wobj0").to_string(),
        )],
        _ => Vec::new(),
    }
}

/// RobotStudio's RX, RY, RZ of a target's quaternion (degrees); `None`
/// without numbers or for a quaternion that is not a rotation.
fn euler(t: &Target) -> Option<[f64; 3]> {
    let v = t.value.as_ref()?;
    let pose = pose_from_rapid(v.trans_values(), v.rot_values()).ok()?;
    Some(euler_zyx_deg(&pose.rotation))
}

/// An angle for the listing: to 0.0001° (what RobotStudio shows), in the
/// shortest text.
fn angle(v: f64) -> String {
    n((v * 1e4).round() / 1e4)
}

/// The listing of one program's robtargets.
fn listing(
    args: &TargetsArgs,
    inputs: &super::Inputs,
    prog: &rapidtherm::rapid::Program,
) -> Result<String> {
    let several = inputs.len() > 1;
    // Declared derived targets (`CONST robtarget p20 := Offs(p10, ...)`)
    // with the moves that name them: `usages` gives those to no target.
    let mut uses = resolve::usages(prog);
    uses.extend(resolve::declared_derived_usages(prog));
    let opt = |s: &Option<std::sync::Arc<str>>| s.as_deref().unwrap_or("").to_string();
    let eulers = |t: &Target| -> Vec<String> {
        match euler(t) {
            Some(e) => e.iter().map(|v| angle(*v)).collect(),
            None => vec![String::new(); 3],
        }
    };
    let out = match args.format {
        Format::Table => {
            let header = [
                "target", "kind", "at", "x_mm", "y_mm", "z_mm", "q1", "q2", "q3", "q4", "rx_deg",
                "ry_deg", "rz_deg", "robconf", "tool", "wobj",
            ];
            let mut align = vec![Align::Left, Align::Left, Align::Left];
            align.extend([Align::Right; 10]);
            align.extend([Align::Left; 3]);
            let (mut several_pairs, mut unused) = (false, false);
            let rows: Vec<Vec<String>> = prog
                .targets()
                .iter()
                .enumerate()
                .map(|(i, t)| {
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
                            r.extend(std::iter::repeat_n(String::new(), 10));
                            r.push(format!("= {}", d.expr));
                        }
                        _ => {
                            r.extend(v[..7].iter().cloned());
                            r.extend(eulers(t));
                            r.push(format!("[{}]", v[7..11].join(",")));
                        }
                    }
                    let p = pairs(t, uses.get(&i));
                    several_pairs |= p.len() > 1;
                    unused |= p.is_empty();
                    if p.is_empty() {
                        r.extend(["-".to_string(), "-".to_string()]);
                    } else {
                        let (tools, wobjs): (Vec<String>, Vec<String>) = p.into_iter().unzip();
                        r.push(tools.join(","));
                        r.push(wobjs.join(","));
                    }
                    r
                })
                .collect();
            let mut text = render_table(&header, &align, &rows);
            if !rows.is_empty() {
                text.push_str(LEGEND);
            }
            if several_pairs {
                text.push_str(LEGEND_PAIRS);
            }
            if unused {
                text.push_str(LEGEND_UNUSED);
            }
            text
        }
        Format::Csv => {
            // Scripts read these columns by name or place: new ones are
            // added at the end, none renamed.
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
                "rx_deg",
                "ry_deg",
                "rz_deg",
                "frames",
                "moves",
            ];
            let rows: Vec<Vec<String>> = prog
                .targets()
                .iter()
                .enumerate()
                .map(|(i, t)| {
                    let mut r = vec![
                        t.id.clone(),
                        t.kind.as_str().to_string(),
                        prog.files[t.origin.file].clone(),
                        t.origin.pos.line.to_string(),
                        t.origin.pos.col.to_string(),
                    ];
                    r.extend(values(t));
                    let p = pairs(t, uses.get(&i));
                    let first = p.first().cloned().unwrap_or_default();
                    r.push(first.0);
                    r.push(first.1);
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
                    r.extend(eulers(t));
                    let all: Vec<String> = p.iter().map(|(t, w)| format!("{t}/{w}")).collect();
                    r.push(all.join(" "));
                    r.push(moves(t, uses.get(&i)).to_string());
                    r
                })
                .collect();
            render_csv(&header, &rows)
        }
        Format::Json => {
            let items: Vec<serde_json::Value> = prog
                .targets()
                .iter()
                .enumerate()
                .map(|(i, t)| {
                    let v = t.value.as_ref();
                    let p = pairs(t, uses.get(&i));
                    let first = p.first();
                    let use_json = |tool: &str, wobj: &str, instruction: &str, routine, line| {
                        serde_json::json!({
                            "tool": tool,
                            "wobj": wobj,
                            "instruction": instruction,
                            "routine": routine,
                            "line": line,
                        })
                    };
                    let mut listed: Vec<serde_json::Value> = uses
                        .get(&i)
                        .into_iter()
                        .flatten()
                        .map(|u| {
                            use_json(
                                u.tool_name(),
                                u.wobj_name(),
                                &u.instruction,
                                Some(u.routine.as_str()),
                                u.line,
                            )
                        })
                        .collect();
                    // A derived target written in a move: that move.
                    if let (true, Some(instruction), Some((tool, wobj))) =
                        (listed.is_empty(), t.instruction.as_deref(), first)
                    {
                        listed.push(use_json(
                            tool,
                            wobj,
                            instruction,
                            t.origin.routine.as_deref(),
                            t.origin.pos.line,
                        ));
                    }
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
                        "euler_zyx_deg": euler(t).map(|e| e.map(|a| (a * 1e9).round() / 1e9)),
                        "robconf": v.map(|v| v.robconf_values()),
                        "extax": v.map(|v| v.extax_values()),
                        "instruction": t.instruction.as_deref(),
                        "tool": first.map(|f| &f.0),
                        "wobj": first.map(|f| &f.1),
                        "frames": p.iter().map(|(t, w)| serde_json::json!({"tool": t, "wobj": w})).collect::<Vec<_>>(),
                        "uses": listed,
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

/// How many move instructions reach a target (a derived target written
/// in a move: its own).
fn moves(t: &Target, uses: Option<&Vec<Usage>>) -> usize {
    match uses {
        Some(u) if !u.is_empty() => u.len(),
        _ => usize::from(t.instruction.is_some()),
    }
}

/// What the table's columns mean, under it.
const LEGEND: &str = "frame: x_mm, y_mm, z_mm and q1..q4 are the TCP in the object frame of the row's wobj; rx_deg, ry_deg, rz_deg are q1..q4 as RobotStudio's Euler ZYX (R = Rz·Ry·Rx)\n";
const LEGEND_PAIRS: &str = "several tools or work objects: the pairs in the order the program first uses them, tool and wobj lists matching place by place; `rapidtherm correct` corrects the target for the first\n";
const LEGEND_UNUSED: &str = "-: no move instruction reaches the target\n";

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
            let mut table_header = header;
            table_header[5..11]
                .copy_from_slice(&["j1_deg", "j2_deg", "j3_deg", "j4_deg", "j5_deg", "j6_deg"]);
            render_table(&table_header, &align, &rows)
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
