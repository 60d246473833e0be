//! `rapidtherm correct`: the main job.

use super::Format;
use super::{output, read_input, read_program, write_output, write_stdout, Status};
use rapidtherm::correct::{correct, marker, Options, Outcome, Reason, When};
use rapidtherm::error::{Error, Result};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::report::{mm, render_csv, render_table, Align};
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{self, EstimateOptions, Schedule, Visit};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// `--visit`: the command line's names for [`Visit`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum VisitArg {
    First,
    Mean,
    Last,
}

impl From<VisitArg> for Visit {
    fn from(v: VisitArg) -> Visit {
        match v {
            VisitArg::First => Visit::First,
            VisitArg::Mean => Visit::Mean,
            VisitArg::Last => Visit::Last,
        }
    }
}

/// `--accept`: the command line's names for the [`Reason`]s a target may
/// be left alone for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum AcceptArg {
    /// Targets whose value the run decides (assigned, searched,
    /// placeholders).
    Runtime,
    /// Literals written with named constants or expressions.
    Expression,
    /// Declared targets no move reaches.
    Unused,
    /// Targets in a work object moved by a mechanical unit.
    Coordinated,
}

impl From<AcceptArg> for Reason {
    fn from(a: AcceptArg) -> Reason {
        match a {
            AcceptArg::Runtime => Reason::Runtime,
            AcceptArg::Expression => Reason::Expression,
            AcceptArg::Unused => Reason::Unused,
            AcceptArg::Coordinated => Reason::Coordinated,
        }
    }
}

/// When the targets are reached, as the command line says it.
#[derive(clap::Args)]
#[group(id = "when", required = true, multiple = false)]
pub struct WhenArgs {
    /// Every target at this minute since the cold start, or `steady` for
    /// the thermally stable state after warm-up.
    #[arg(long, value_name = "MIN|steady", group = "when")]
    pub at: Option<String>,
    /// Times per target: a CSV `target,time_min` (`rapidtherm schedule`
    /// writes one).
    #[arg(long, value_name = "FILE.csv", group = "when")]
    pub schedule: Option<PathBuf>,
    /// Estimate the times from the program itself, starting at this minute
    /// (walks --entry, follows calls and loops, times every move).
    #[arg(long, value_name = "MIN", group = "when")]
    pub start: Option<f64>,
}

#[derive(clap::Args)]
pub struct CorrectArgs {
    /// RAPID files of one program (several files are one run).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub when: WhenArgs,
    /// With --schedule or --start: the minute for targets the schedule
    /// does not list (without it, a missing target is an error).
    #[arg(long, value_name = "MIN|steady")]
    pub default_time: Option<String>,
    /// With --start: the routine the program starts in.
    #[arg(long, value_name = "NAME", default_value = "main", requires = "start")]
    pub entry: String,
    /// With --start: how many times the entry routine runs back to back.
    #[arg(long, value_name = "N", default_value_t = 1, requires = "start")]
    pub cycles: u32,
    /// A target reached several times is corrected for this visit.
    #[arg(long, value_enum, default_value_t = VisitArg::Mean)]
    pub visit: VisitArg,
    /// Model file (robot, thermal expansion, heating, effects); default:
    /// the embedded IRB 140 and heating profile.
    #[arg(long, value_name = "FILE.toml")]
    pub model: Option<PathBuf>,
    /// The arm the controller moves: an ABB arm by name (`rapidtherm arms`)
    /// or a URDF file; default: the embedded IRB 140.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    pub robot: Option<PathBuf>,
    /// Write the corrected program here (`-`: standard output).
    #[arg(short, long, value_name = "OUT", conflicts_with_all = ["in_place", "check", "diff"])]
    pub output: Option<PathBuf>,
    /// Rewrite the input files themselves (atomically).
    #[arg(long, conflicts_with_all = ["check", "diff"])]
    pub in_place: bool,
    /// With --in-place: keep each original as FILE + SUFFIX.
    #[arg(long, value_name = "SUFFIX", requires = "in_place")]
    pub backup: Option<String>,
    /// Write nothing; list (on standard output, in --format) every target
    /// that would move more than --tolerance or is left cold, and exit 1 if
    /// there is any.
    #[arg(long)]
    pub check: bool,
    /// Print a unified diff of the change (in the file's own bytes, so it
    /// applies with `patch`); write nothing; exit 1 if the program would
    /// change. With --check, the check's list goes to standard error.
    #[arg(long)]
    pub diff: bool,
    /// With --check: targets left alone for these reasons do not fail the
    /// check (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', value_name = "REASON")]
    pub accept: Vec<AcceptArg>,
    /// Write numbers in place of robtarget literals written with named
    /// constants or expressions (`[[nX,0,300],...]`) and correct them;
    /// without it they are left alone and reported.
    #[arg(long)]
    pub expand_expressions: bool,
    /// With --check: largest correction (mm) that counts as no change.
    #[arg(long, value_name = "MM", default_value_t = 0.001)]
    pub tolerance: f64,
    /// Format of the per-target report (printed when no output is chosen).
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
}

fn moment(text: &str, what: &str) -> Result<Moment> {
    if text.eq_ignore_ascii_case("steady") {
        return Ok(Moment::Steady);
    }
    match text.parse::<f64>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(Moment::Minute(t)),
        _ => Err(Error::usage(format!(
            "{what}: `{text}` is neither a minute since the cold start (≥ 0) nor `steady`"
        ))),
    }
}

pub fn load_model(path: Option<&Path>) -> Result<Model> {
    match path {
        Some(p) => Model::load(p),
        None => Ok(Model::default()),
    }
}

pub fn run_correct(args: CorrectArgs) -> Result<Status> {
    if args.output.is_some() && args.files.len() > 1 {
        return Err(Error::usage(
            "-o writes one file: give one input, or use --in-place for several",
        ));
    }
    if args.in_place && args.files.iter().any(|f| f == Path::new("-")) {
        return Err(Error::usage("--in-place cannot rewrite standard input"));
    }
    if args.tolerance.is_nan() || args.tolerance < 0.0 {
        return Err(Error::usage("--tolerance must be a length ≥ 0 (mm)"));
    }
    let model = load_model(args.model.as_deref())?;
    let robot = super::arms::load_robot(args.robot.as_deref())?;
    let (inputs, program) = read_program(&args.files)?;
    let when = when_of(&args, &program, &robot)?;
    let horizon = match &when {
        When::At(Moment::Minute(t)) => *t,
        When::At(Moment::Steady) => 0.0,
        When::Schedule {
            schedule,
            joints,
            default,
        } => {
            let latest = std::iter::once(schedule)
                .chain(joints)
                .flat_map(|s| s.targets().iter().filter_map(|id| s.times(id)))
                .flatten()
                .copied()
                .fold(0.0, f64::max);
            match default {
                Some(Moment::Minute(t)) => latest.max(*t),
                _ => latest,
            }
        }
    };
    let warm = WarmRobot::new(robot, &model, horizon)?;
    let options = Options {
        when,
        visit: args.visit.into(),
        expand_expressions: args.expand_expressions,
        model_label: model_label(args.model.as_deref(), args.robot.as_deref())?,
    };
    let bar = progress_bar(program.targets().len() + program.jointtargets().len());
    let outcome = correct(&program, &warm, &options, &mut |done, total| {
        if let Some(b) = &bar {
            b.set_length(total as u64);
            b.set_position(done as u64);
        }
    })?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let changed = outcome
        .outputs
        .iter()
        .enumerate()
        .any(|(f, o)| o.as_slice() != program.source(f));
    if let Some(how) = &outcome.already_corrected {
        eprintln!("note: already corrected: {how}; nothing to do");
    }
    let accepted: Vec<Reason> = args.accept.iter().map(|&a| a.into()).collect();
    let findings = check_findings(&outcome, args.tolerance, &accepted);
    if args.diff {
        let mut text = Vec::new();
        for ((name, before), after) in inputs.iter().zip(&outcome.outputs) {
            text.extend(unified_diff(name, before, after));
        }
        write_stdout(&text)?;
        eprint!("{}", summary_text(&outcome));
        if args.check {
            eprint!("{}", check_list(&findings, Format::Table)?);
            eprint!("{}", check_verdict(&findings, args.tolerance));
        }
        return Ok(if changed || (args.check && !findings.is_empty()) {
            Status::Changes
        } else {
            Status::Success
        });
    }
    if args.check {
        eprint!("{}", summary_text(&outcome));
        write_stdout(check_list(&findings, args.format)?.as_bytes())?;
        eprint!("{}", check_verdict(&findings, args.tolerance));
        return Ok(if findings.is_empty() {
            Status::Success
        } else {
            Status::Changes
        });
    }
    if let Some(out) = &args.output {
        write_output(out, &outcome.outputs[0])?;
        eprint!("{}", summary_text(&outcome));
        return Ok(Status::Success);
    }
    if args.in_place {
        let writes: Vec<(&String, &Vec<u8>)> = inputs
            .iter()
            .zip(&outcome.outputs)
            .filter(|((_, before), after)| *after != before)
            .map(|((name, _), after)| (name, after))
            .collect();
        // Every backup is checked before any file is written: a refused
        // backup leaves the whole program as it was.
        if let Some(suffix) = args.backup.as_deref() {
            for (name, _) in &writes {
                output::check_backup_free(&output::backup_path(Path::new(name), suffix))?;
            }
        }
        for (name, after) in writes {
            output::write_atomic(Path::new(name), after, args.backup.as_deref())?;
        }
        eprint!("{}", summary_text(&outcome));
        return Ok(Status::Success);
    }
    write_stdout(report(&outcome, args.format)?.as_bytes())?;
    if args.format == Format::Table {
        eprint!("{}", summary_text(&outcome));
    }
    Ok(Status::Success)
}

/// The model and arm a run uses, as the marker of a corrected file names
/// them: the embedded ones and catalogue arms by name, files by their
/// fingerprint.
fn model_label(model: Option<&Path>, robot: Option<&Path>) -> Result<String> {
    let fingerprint = |p: &Path| -> Result<String> {
        let (_, bytes) = read_input(p)?;
        Ok(marker::fingerprint(&bytes))
    };
    let model = match model {
        Some(p) => fingerprint(p)?,
        None => "embedded default".to_string(),
    };
    let arm = super::arms::robot_label(robot, &fingerprint)?;
    Ok(format!("{model} model, {arm} arm"))
}

/// One line of `--check`'s list: a target that would move more than the
/// tolerance, or one left cold for a reason not accepted.
#[derive(serde::Serialize)]
struct Finding {
    id: String,
    kind: String,
    file: String,
    line: u32,
    col: u32,
    /// `moves` or `left-alone`.
    status: &'static str,
    correction_mm: Option<f64>,
    reason: Option<Reason>,
    detail: String,
}

fn check_findings(outcome: &Outcome, tolerance: f64, accepted: &[Reason]) -> Vec<Finding> {
    let moves = outcome
        .corrections
        .iter()
        .filter(|c| c.correction_norm_mm > tolerance)
        .map(|c| Finding {
            id: c.id.clone(),
            kind: c.kind.clone(),
            file: c.file.clone(),
            line: c.line,
            col: c.col,
            status: "moves",
            correction_mm: Some(c.correction_norm_mm),
            reason: None,
            detail: String::new(),
        });
    let cold = outcome
        .left_alone
        .iter()
        .filter(|l| l.reason.leaves_target_cold() && !accepted.contains(&l.reason))
        .map(|l| Finding {
            id: l.id.clone(),
            kind: l.kind.clone(),
            file: l.file.clone(),
            line: l.line,
            col: l.col,
            status: "left-alone",
            correction_mm: None,
            reason: Some(l.reason),
            detail: reason_words(l.reason, &l.kind, &l.detail),
        });
    moves.chain(cold).collect()
}

fn check_list(findings: &[Finding], format: Format) -> Result<String> {
    let header = ["target", "kind", "at", "status", "corr_mm", "reason"];
    let rows: Vec<Vec<String>> = findings
        .iter()
        .map(|f| {
            vec![
                f.id.clone(),
                f.kind.clone(),
                format!("{}:{}:{}", f.file, f.line, f.col),
                f.status.to_string(),
                f.correction_mm.map_or(String::new(), |c| mm(c, 4)),
                f.reason
                    .map_or(String::new(), |r| format!("{}: {}", r.code(), f.detail)),
            ]
        })
        .collect();
    Ok(match format {
        Format::Json => {
            serde_json::to_string_pretty(findings).map_err(|e| Error::input(e.to_string()))? + "\n"
        }
        Format::Csv => render_csv(&header, &rows),
        Format::Table if rows.is_empty() => String::new(),
        Format::Table => {
            let mut align = vec![Align::Left; 4];
            align.push(Align::Right);
            align.push(Align::Left);
            render_table(&header, &align, &rows)
        }
    })
}

fn check_verdict(findings: &[Finding], tolerance: f64) -> String {
    let moves = findings.iter().filter(|f| f.status == "moves").count();
    let cold = findings.len() - moves;
    if findings.is_empty() {
        return format!("check: no target moves more than {tolerance} mm and none is left cold\n");
    }
    let mut text = String::new();
    if moves > 0 {
        text.push_str(&format!(
            "check: {moves} target(s) would move more than {tolerance} mm\n"
        ));
    }
    if cold > 0 {
        text.push_str(&format!(
            "check: {cold} target(s) left cold (accept a reason with --accept REASON)\n"
        ));
    }
    text
}

/// A reason's words, with what the user can do where the CLI has a flag
/// for it.
fn reason_words(reason: Reason, kind: &str, detail: &str) -> String {
    match reason {
        Reason::Expression if kind != "jointtarget" => format!("{detail} (--expand-expressions)"),
        _ => detail.to_string(),
    }
}

/// When the targets are reached, from --at, --schedule or --start.
fn when_of(args: &CorrectArgs, program: &rapid::Program, robot: &Robot) -> Result<When> {
    let default = args
        .default_time
        .as_deref()
        .map(|t| moment(t, "--default-time"))
        .transpose()?;
    Ok(match (&args.when.at, &args.when.schedule, args.when.start) {
        (Some(at), _, _) => When::At(moment(at, "--at")?),
        (None, Some(path), _) => {
            let (name, bytes) = read_input(path)?;
            When::Schedule {
                schedule: Schedule::read(&name, &bytes)?,
                joints: None,
                default,
            }
        }
        (None, None, Some(start)) => {
            if !(start.is_finite() && start >= 0.0) {
                return Err(Error::usage("--start: a minute since the cold start (≥ 0)"));
            }
            let estimate = schedule::estimate(
                program,
                robot,
                &EstimateOptions {
                    entry: args.entry.clone(),
                    start_min: start,
                    cycles: args.cycles,
                },
            )?;
            for note in &estimate.notes {
                eprintln!("note: {note}");
            }
            When::Schedule {
                schedule: estimate.schedule,
                joints: Some(estimate.joint_schedule),
                default,
            }
        }
        (None, None, None) => {
            return Err(Error::usage(
                "say when the targets are reached: --at MIN, --at steady, --schedule FILE or --start MIN",
            ))
        }
    })
}

fn progress_bar(total: usize) -> Option<indicatif::ProgressBar> {
    // Only worth showing for long runs, and only to a person.
    if total < 50_000 || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(total as u64);
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "correcting {bar:40} {pos}/{len} targets ({eta} left)",
    ) {
        bar.set_style(style);
    }
    Some(bar)
}

/// The per-target report: corrected against original.
fn report(outcome: &Outcome, format: Format) -> Result<String> {
    let header = [
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
    ];
    let rows: Vec<Vec<String>> = outcome
        .corrections
        .iter()
        .map(|c| {
            vec![
                c.id.clone(),
                c.kind.clone(),
                c.line.to_string(),
                c.time_min
                    .map_or("steady".to_string(), |t| format!("{t:.2}")),
                mm(c.drift_norm_mm, 4),
                mm(c.correction_mm[0], 4),
                mm(c.correction_mm[1], 4),
                mm(c.correction_mm[2], 4),
                mm(c.correction_norm_mm, 4),
                mm(c.dangle_deg, 6),
                if c.rewritten { "yes" } else { "no" }.to_string(),
            ]
        })
        .collect();
    Ok(match format {
        Format::Json => {
            serde_json::to_string_pretty(outcome).map_err(|e| Error::input(e.to_string()))? + "\n"
        }
        Format::Csv => render_csv(&header, &rows),
        Format::Table => {
            let mut align = vec![Align::Left, Align::Left];
            align.extend([Align::Right; 8]);
            align.push(Align::Left);
            let mut text = render_table(&header, &align, &rows);
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
                    reason_words(l.reason, &l.kind, &l.detail)
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
            text
        }
    })
}

fn summary_text(outcome: &Outcome) -> String {
    let s = &outcome.summary;
    let mut text = format!(
        "{} target(s) corrected ({} rewritten): max {} mm, RMS {} mm; largest drift {} mm",
        s.corrected,
        s.rewritten,
        mm(s.max_mm, 4),
        mm(s.rms_mm, 4),
        mm(s.max_drift_mm, 4)
    );
    if s.derived > 0 {
        text.push_str(&format!("; {} derived left as written", s.derived));
    }
    if s.left_alone > 0 {
        text.push_str(&format!("; {} left alone", s.left_alone));
    }
    text.push('\n');
    for l in &outcome.left_alone {
        let level = if l.reason.leaves_target_cold() {
            "warning"
        } else {
            "note"
        };
        text.push_str(&format!(
            "{level}: left alone {} ({}:{}:{}) [{}]: {}\n",
            l.id,
            l.file,
            l.line,
            l.col,
            l.reason.code(),
            reason_words(l.reason, &l.kind, &l.detail)
        ));
    }
    for note in &outcome.notes {
        text.push_str(&format!("note: {note}\n"));
    }
    text
}

/// A unified diff of two versions of a file, in the file's own bytes: a
/// Latin-1 file's diff is Latin-1, so that `patch` applies it to the
/// original.
fn unified_diff(name: &str, before: &[u8], after: &[u8]) -> Vec<u8> {
    if before == after {
        return Vec::new();
    }
    let utf8 = std::str::from_utf8(before).is_ok() && std::str::from_utf8(after).is_ok();
    // Latin-1: each byte one char, and back.
    let text = |b: &[u8]| -> String {
        if utf8 {
            String::from_utf8_lossy(b).into_owned()
        } else {
            b.iter().map(|&c| char::from(c)).collect()
        }
    };
    let (a, b) = (text(before), text(after));
    let body = similar::TextDiff::from_lines(&a, &b)
        .unified_diff()
        .context_radius(1)
        .to_string();
    let mut out = format!("--- a/{name}\n+++ b/{name}\n").into_bytes();
    if utf8 {
        out.extend(body.into_bytes());
    } else {
        out.extend(
            body.chars()
                .map(|c| u8::try_from(u32::from(c)).unwrap_or(b'?')),
        );
    }
    out
}
