//! `rapidtherm correct`: the main job.

use super::Format;
use super::{read_input, read_program, write_output, write_stdout, Status};
use rapidtherm::correct::{correct, Options, Outcome, When};
use rapidtherm::error::{decode_lossless, Error, Result};
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
    /// The arm (URDF) the controller moves; default: the embedded IRB 140.
    #[arg(long, value_name = "FILE.urdf")]
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
    /// Write nothing; exit 1 if any target would move more than --tolerance.
    #[arg(long)]
    pub check: bool,
    /// Print a unified diff of the change; write nothing; exit 1 if the
    /// program would change.
    #[arg(long)]
    pub diff: bool,
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

pub fn load_robot(path: Option<&Path>) -> Result<Robot> {
    match path {
        Some(p) => Robot::from_urdf_file(p),
        None => Ok(Robot::irb140()),
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
    let robot = load_robot(args.robot.as_deref())?;
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
    if args.check {
        eprint!("{}", summary_text(&outcome));
        let over = outcome
            .corrections
            .iter()
            .filter(|c| c.correction_norm_mm > args.tolerance)
            .count();
        if over > 0 {
            eprintln!(
                "check: {over} target(s) would move more than {} mm",
                args.tolerance
            );
            return Ok(Status::Changes);
        }
        eprintln!("check: no target moves more than {} mm", args.tolerance);
        return Ok(Status::Success);
    }
    if args.diff {
        let mut text = String::new();
        for ((name, before), after) in inputs.iter().zip(&outcome.outputs) {
            text.push_str(&unified_diff(name, before, after));
        }
        write_stdout(text.as_bytes())?;
        eprint!("{}", summary_text(&outcome));
        return Ok(if changed {
            Status::Changes
        } else {
            Status::Success
        });
    }
    if let Some(out) = &args.output {
        write_output(out, &outcome.outputs[0])?;
        eprint!("{}", summary_text(&outcome));
        return Ok(Status::Success);
    }
    if args.in_place {
        for ((name, before), after) in inputs.iter().zip(&outcome.outputs) {
            if after != before {
                crate::cli::output::write_atomic(Path::new(name), after, args.backup.as_deref())?;
            }
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
            for s in &outcome.skipped {
                text.push_str(&format!(
                    "skipped {} (line {}): {}\n",
                    s.id, s.line, s.reason
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
    if s.skipped > 0 {
        text.push_str(&format!("; {} skipped", s.skipped));
    }
    text.push('\n');
    for sk in &outcome.skipped {
        text.push_str(&format!(
            "warning: skipped {} ({}:{}): {}\n",
            sk.id, sk.file, sk.line, sk.reason
        ));
    }
    for note in &outcome.notes {
        text.push_str(&format!("note: {note}\n"));
    }
    text
}

/// A unified diff of two versions of a file (bytes shown as text: UTF-8
/// where valid, else Latin-1).
fn unified_diff(name: &str, before: &[u8], after: &[u8]) -> String {
    if before == after {
        return String::new();
    }
    let a = decode_lossless(before);
    let b = decode_lossless(after);
    similar::TextDiff::from_lines(&a, &b)
        .unified_diff()
        .context_radius(1)
        .header(&format!("a/{name}"), &format!("b/{name}"))
        .to_string()
}
