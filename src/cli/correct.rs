//! `rapidtherm correct`: the main job.

use super::check_rule::CheckRule;
use super::ci_report::{self, ReportFormat};
use super::messages::{self, info, note};
use super::tasks;
use super::Format;
use super::{output, read_input, write_output, write_stdout, Status};
use rapidtherm::correct::{correct, marker, Options, Outcome, Reason, When};
use rapidtherm::error::{Error, Errors, Result};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::rapid::task::Task;
use rapidtherm::report::{mm, render_csv, render_table, Align};
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{self, EstimateOptions, Schedule, Visit};
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
    /// Moves to a target with another tool or work object than the one it
    /// is corrected for (its first use's).
    SharedFrames,
}

impl From<AcceptArg> for Reason {
    fn from(a: AcceptArg) -> Reason {
        match a {
            AcceptArg::Runtime => Reason::Runtime,
            AcceptArg::Expression => Reason::Expression,
            AcceptArg::Unused => Reason::Unused,
            AcceptArg::Coordinated => Reason::Coordinated,
            AcceptArg::SharedFrames => Reason::SharedFrames,
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
    /// RAPID files of one program (several files are one run), a program
    /// file (.pgf), a task folder (PROGMOD/SYSMOD, a backup's RAPID/TASKn)
    /// or a whole controller backup: each task is read as one program.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub pick: tasks::TaskPick,
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
    /// The arm the controller moves: a URDF file or an embedded arm's name;
    /// `TASK=ARM` for one task of a backup. Default: the robot type of the
    /// backup's MOC.cfg, else the embedded IRB 140.
    #[arg(long, value_name = "[TASK=]NAME|FILE.urdf")]
    pub robot: Vec<String>,
    /// Use the IRB 140's thermal defaults (heating and expansion) on an arm
    /// whose own are unknown; the arm's lengths still scale the drift.
    #[arg(long)]
    pub irb140_thermal: bool,
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
    /// With --check: targets left alone for these reasons (and, for
    /// shared-frames, moves with another tool or work object) do not fail
    /// the check (comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', value_name = "REASON")]
    pub accept: Vec<AcceptArg>,
    /// Write numbers in place of robtarget literals written with named
    /// constants or expressions (`[[nX,0,300],...]`) and correct them;
    /// without it they are left alone and reported.
    #[arg(long)]
    pub expand_expressions: bool,
    /// A declared target moved to with several tools or work objects gets
    /// a copy per extra tool/work-object pair, declared on the line after
    /// it and named TARGET_TOOL (TARGET_WOBJ, or TARGET_2, ...), each
    /// corrected for its own pair; the moves with that pair name the copy.
    /// This changes more than numbers: new declarations and renamed move
    /// arguments. Only where a copy's numbers would differ from the
    /// original's (so --at 0 splits nothing). Without it
    /// (and where a copy cannot be made: array elements, record fields,
    /// global PERS, targets also reached through Offs/RelTool or a
    /// variable, or passed to a procedure) such a target is corrected for
    /// its first use and the other uses are reported with their residual.
    #[arg(long)]
    pub split_shared: bool,
    /// With --check: largest correction (mm) that counts as no change; a
    /// use with another tool or work object landing farther off fails too.
    #[arg(long, value_name = "MM", default_value_t = 0.001)]
    pub tolerance: f64,
    /// Also draw the correction as SVG pictures in this folder (created if
    /// missing): top.svg, side.svg, drift.svg (see docs/plot.md).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Format of the per-target report (printed when no output is chosen);
    /// with --check also github or junit, for CI (docs/ci.md).
    #[arg(long, value_enum, default_value_t = ReportFormat::Table)]
    pub format: ReportFormat,
}

pub(super) fn moment(text: &str, what: &str) -> Result<Moment> {
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

/// `--model`: a model file, or an embedded model by name (`default`, the
/// calibrated one; `base`, docs/model.md's unscaled base model) when no file of
/// that name exists.
pub fn load_model(path: Option<&Path>) -> Result<Model> {
    match path {
        Some(p) => match embedded_model(p) {
            Some(m) => Ok(m),
            None => Model::load(p),
        },
        None => Ok(Model::default()),
    }
}

fn embedded_model(path: &Path) -> Option<Model> {
    if path.exists() {
        return None;
    }
    path.to_str().and_then(Model::named)
}

pub fn run_correct(args: CorrectArgs) -> Result<Status> {
    if args.in_place && args.files.iter().any(|f| f == Path::new("-")) {
        return Err(Error::usage("--in-place cannot rewrite standard input"));
    }
    if args.tolerance.is_nan() || args.tolerance < 0.0 {
        return Err(Error::usage("--tolerance must be a length ≥ 0 (mm)"));
    }
    ci_report::refuse_outside_check(args.format, args.check, args.diff)?;
    super::plot::check_dir(args.plot.as_deref())?;
    let model = load_model(args.model.as_deref())?;
    let found = tasks::select(&args.files, &args.pick)?;
    let (motion, still): (Vec<Task>, Vec<Task>) =
        found.into_iter().partition(|t| t.motion != Some(false));
    if args.output.is_some() && (motion.len() != 1 || motion[0].modules.len() != 1) {
        return Err(Error::usage(
            "-o writes one file: give one input, or use --in-place for several",
        ));
    }
    if args.when.schedule.is_some() && motion.len() > 1 {
        return Err(Error::usage(
            "a schedule file times the targets of one task: pick it with --task (or use --start, which times each task)",
        ));
    }
    if let Some(status) = super::stream::correct(&args, &model, &motion, &still)? {
        return Ok(status);
    }
    // Every task is tried before anything is written or printed, so that a
    // run reports all its errors and a refused task leaves every file as
    // it was.
    let mut runs = Vec::new();
    let mut errors = Errors::default();
    for task in motion {
        match correct_task(&args, &model, task) {
            Ok(run) => runs.push(run),
            Err(e) => errors.push(e),
        }
    }
    if let Some(e) = errors.into_error(|n| {
        Error::input(format!(
            "{n} tasks cannot be corrected; nothing was written"
        ))
    }) {
        return Err(e);
    }
    note_still(&still);
    let drawn: Vec<_> = runs
        .iter()
        .map(|r| (&r.task, &r.inputs, &r.outcome))
        .collect();
    let pictures = super::plot::draw(args.plot.as_deref(), &drawn)?;
    let status = emit(&args, &runs)?;
    super::plot::write(args.plot.as_deref(), &pictures)?;
    Ok(status)
}

/// Tasks that move no robot are named and left alone.
pub(super) fn note_still(still: &[Task]) {
    for t in still {
        note!(
            "task {} is not a motion task (SYSPAR/SYS.cfg): left alone",
            t.label()
        );
    }
}

/// One task corrected: what was read, with which arm, and the outcome.
struct Run {
    task: Task,
    arm: String,
    inputs: super::Inputs,
    program: rapid::Program,
    outcome: Outcome,
}

/// The arm of a task, refused when the thermal defaults would be guessed.
pub(super) fn checked_arm(args: &CorrectArgs, task: &Task, model: &Model) -> Result<tasks::Arm> {
    let arm = tasks::arm_for_model(task, &args.robot, model)?;
    if args.model.is_none() && !arm.is_irb140 && !args.irb140_thermal {
        let whose = match &task.name {
            Some(n) => format!("task {n}: "),
            None => String::new(),
        };
        return Err(Error::usage(format!(
            "{whose}{} is not an IRB 140, and how it warms up and expands is unknown: the embedded thermal defaults were measured on an IRB 140",
            arm.robot.name
        ))
        .with_note("give a model file of this arm with --model FILE.toml (its heating measured, or a heating recording in it), or use the IRB 140's defaults on this arm's lengths with --irb140-thermal"));
    }
    Ok(arm)
}

/// The warm robot a task's run needs until `when`'s last minute, and the
/// run's options: (arm name, warm robot, options).
pub(super) fn warm_run(
    args: &CorrectArgs,
    model: &Model,
    task: &Task,
    arm: tasks::Arm,
    when: When,
) -> Result<(String, WarmRobot, Options)> {
    warm_run_until(args, model, task, arm, when, 0.0)
}

/// [`warm_run`] where targets `when` does not hold are reached too, the
/// last at minute `later` (a streamed estimate's cut literals).
pub(super) fn warm_run_until(
    args: &CorrectArgs,
    model: &Model,
    task: &Task,
    arm: tasks::Arm,
    when: When,
    later: f64,
) -> Result<(String, WarmRobot, Options)> {
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
            let latest = latest.max(later);
            match default {
                Some(Moment::Minute(t)) => latest.max(*t),
                _ => latest,
            }
        }
    };
    let arm_name = arm.robot.name.clone();
    let warm = WarmRobot::new(arm.robot, model, horizon)?;
    if warm.instrument_left_out() {
        note!(
            "task {}: the model's tracker-frame is the frame of the instrument it was diagnosed with, not the robot's: left out of the correction",
            task.label()
        );
    }
    let model_label = model_label(args.model.as_deref(), &arm.label)?;
    let borrowed = args.model.is_none() && !arm.is_irb140;
    let on_lengths = if borrowed {
        " on this arm's lengths"
    } else {
        ""
    };
    info!(
        "task {}: thermal model: {model_label}{on_lengths}",
        task.label()
    );
    let options = Options {
        when,
        visit: args.visit.into(),
        expand_expressions: args.expand_expressions,
        model_label,
        base_frame: tasks::base_frame(task)?,
        split_shared: args.split_shared,
    };
    Ok((arm_name, warm, options))
}

fn correct_task(args: &CorrectArgs, model: &Model, task: Task) -> Result<Run> {
    let arm = checked_arm(args, &task, model)?;
    let (inputs, program) = tasks::read(&task)?;
    let when = when_of(args, &program, &arm.robot, tasks::base_frame(&task)?)?;
    let (arm_name, warm, options) = warm_run(args, model, &task, arm, when)?;
    let bar = progress_bar(program.targets().len() + program.jointtargets().len());
    let started = std::time::Instant::now();
    let outcome = correct(&program, &warm, &options, &mut |done, total| {
        if let Some(b) = &bar {
            // The time left is estimated from the pace of the targets
            // alone: what ran before the first (reading, the schedule)
            // would make it many times too long.
            if done == 0 {
                b.reset_eta();
            }
            b.set_length(total as u64);
            b.set_position(done as u64);
        }
    })?;
    messages::took(&format!("task {}: correcting", task.label()), started);
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    Ok(Run {
        task,
        arm: arm_name,
        inputs,
        program,
        outcome,
    })
}

/// Print and write what the runs found, as the options ask.
fn emit(args: &CorrectArgs, runs: &[Run]) -> Result<Status> {
    // A task of a backup is named; files given one by one are one
    // unnamed task, reported as before.
    let named = runs.len() > 1 || runs.iter().any(|r| r.task.name.is_some());
    let heading = |r: &Run| -> String {
        if named {
            format!("task {} ({}):\n", r.task.label(), r.arm)
        } else {
            String::new()
        }
    };
    for r in runs {
        if let Some(how) = &r.outcome.already_corrected {
            note!(
                "{}already corrected: {how}; nothing to do",
                in_task(named, r)
            );
        }
    }
    let changed = runs.iter().any(|r| {
        r.outcome
            .outputs
            .iter()
            .enumerate()
            .any(|(f, o)| o.as_slice() != r.program.source(f))
    });
    let accepted: Vec<Reason> = args.accept.iter().map(|&a| a.into()).collect();
    let rule = CheckRule {
        tolerance: args.tolerance,
        accepted: &accepted,
    };
    let findings: Vec<Vec<Finding>> = runs
        .iter()
        .map(|r| check_findings(&r.outcome, &rule))
        .collect();
    let any_finding = findings.iter().any(|f| !f.is_empty());
    let summaries = || -> String {
        runs.iter()
            .map(|r| heading(r) + &summary_text(&r.outcome))
            .collect()
    };
    if args.diff {
        let mut text = Vec::new();
        for r in runs {
            for ((name, before), after) in r.inputs.iter().zip(&r.outcome.outputs) {
                text.extend(unified_diff(name, before, after));
            }
        }
        write_stdout(&text)?;
        messages::lines(&summaries());
        if args.check {
            messages::outcome_lines(&per_task(
                runs,
                &findings,
                Format::Table,
                named,
                "findings",
                check_list,
            )?);
            messages::lines(&check_verdict(&findings.concat(), args.tolerance));
        }
        return Ok(if changed || (args.check && any_finding) {
            Status::Changes
        } else {
            Status::Success
        });
    }
    if args.check {
        messages::lines(&summaries());
        let list = match args.format.data() {
            Some(format) => per_task(runs, &findings, format, named, "findings", check_list)?,
            None => {
                let checked: Vec<ci_report::Checked> = runs
                    .iter()
                    .map(|r| ci_report::Checked {
                        task: named.then(|| r.task.label()),
                        files: r.inputs.iter().map(|(n, _)| n.as_str()).collect(),
                        outcome: &r.outcome,
                    })
                    .collect();
                ci_report::check(args.format, &checked, &rule)?
            }
        };
        write_stdout(list.as_bytes())?;
        messages::lines(&check_verdict(&findings.concat(), args.tolerance));
        return Ok(if any_finding {
            Status::Changes
        } else {
            Status::Success
        });
    }
    if let Some(out) = &args.output {
        write_output(out, &runs[0].outcome.outputs[0])?;
        messages::lines(&summaries());
        return Ok(Status::Success);
    }
    if args.in_place {
        let mut writes: Vec<(&String, &Vec<u8>)> = Vec::new();
        for r in runs {
            for ((name, before), after) in r.inputs.iter().zip(&r.outcome.outputs) {
                if after == before {
                    continue;
                }
                // One file read in two tasks (a shared module named twice)
                // must not be corrected twice over.
                if writes.iter().any(|(n, a)| *n == name && *a != after) {
                    return Err(Error::input(format!(
                        "{name} is read in two tasks that would correct it differently; correct one task at a time with --task"
                    )));
                }
                writes.push((name, after));
            }
        }
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
        messages::lines(&summaries());
        return Ok(Status::Success);
    }
    // Refused before the run: github and junit report a check only.
    let format = args.format.data().unwrap_or_default();
    let outcomes: Vec<&Outcome> = runs.iter().map(|r| &r.outcome).collect();
    write_stdout(
        per_task(runs, &outcomes, format, named, "report", |o, f| {
            super::correct_report::report(o, f)
        })?
        .as_bytes(),
    )?;
    if format == Format::Table {
        messages::lines(&summaries());
    }
    Ok(Status::Success)
}

fn in_task(named: bool, r: &Run) -> String {
    if named {
        format!("task {}: ", r.task.label())
    } else {
        String::new()
    }
}

/// One rendering per task, joined (see [`tasks::join`]).
fn per_task<T>(
    runs: &[Run],
    items: &[T],
    format: Format,
    named: bool,
    key: &str,
    render: impl Fn(&T, Format) -> Result<String>,
) -> Result<String> {
    let texts = items
        .iter()
        .map(|i| render(i, format))
        .collect::<Result<Vec<String>>>()?;
    let labels: Vec<String> = runs.iter().map(|r| r.task.label()).collect();
    let labels_shown: Vec<String> = runs
        .iter()
        .map(|r| format!("{} ({})", r.task.label(), r.arm))
        .collect();
    let extra: Vec<Vec<(&str, String)>> =
        runs.iter().map(|r| vec![("arm", r.arm.clone())]).collect();
    let shown = match format {
        Format::Table => &labels_shown,
        _ => &labels,
    };
    tasks::join(
        format,
        named.then_some(shown.as_slice()),
        texts,
        key,
        &extra,
    )
}

/// The model and arm a run uses, as the marker of a corrected file names
/// them: the embedded ones by name, files by their fingerprint.
fn model_label(model: Option<&Path>, arm: &str) -> Result<String> {
    let model = match model {
        Some(p) if embedded_model(p).is_some() => {
            format!("embedded {}", p.display().to_string().to_ascii_lowercase())
        }
        Some(p) => {
            let (_, bytes) = read_input(p)?;
            marker::fingerprint(&bytes)
        }
        None => "embedded default".to_string(),
    };
    Ok(format!("{model} model, {arm} arm"))
}

/// One line of `--check`'s list: a target that would move more than the
/// tolerance, or one left cold for a reason not accepted.
#[derive(Clone, serde::Serialize)]
struct Finding {
    id: String,
    kind: String,
    file: String,
    line: u32,
    col: u32,
    /// `moves`, `left-alone`, or `other-use` (a use with another tool or
    /// work object than the target is corrected for).
    status: &'static str,
    correction_mm: Option<f64>,
    /// For `other-use`: how far off the TCP lands there (`None` in JSON
    /// where only the run time knows).
    #[serde(skip_serializing_if = "Option::is_none")]
    residual_mm: Option<Option<f64>>,
    reason: Option<Reason>,
    detail: String,
}

fn check_findings(outcome: &Outcome, rule: &CheckRule) -> Vec<Finding> {
    let moves = outcome
        .corrections
        .iter()
        .filter(|c| rule.moves(c))
        .map(|c| Finding {
            id: c.id.clone(),
            kind: c.kind.clone(),
            file: c.file.clone(),
            line: c.line,
            col: c.col,
            status: "moves",
            correction_mm: Some(c.correction_norm_mm),
            residual_mm: None,
            reason: None,
            detail: String::new(),
        });
    let cold = outcome
        .left_alone
        .iter()
        .filter(|l| rule.left_cold(l))
        .map(|l| Finding {
            id: l.id.clone(),
            kind: l.kind.clone(),
            file: l.file.clone(),
            line: l.line,
            col: l.col,
            status: "left-alone",
            correction_mm: None,
            residual_mm: None,
            reason: Some(l.reason),
            detail: reason_words(l.reason, &l.kind, &l.detail),
        });
    let other_uses = outcome
        .shared
        .iter()
        .filter(|u| rule.lands_off(u))
        .map(|u| Finding {
            id: u.id.clone(),
            kind: u.kind.clone(),
            file: u.file.clone(),
            line: u.line,
            col: u.col,
            status: "other-use",
            correction_mm: None,
            residual_mm: Some(u.residual_mm),
            reason: Some(Reason::SharedFrames),
            detail: shared_words(u),
        });
    moves.chain(cold).chain(other_uses).collect()
}

fn check_list(findings: &Vec<Finding>, format: Format) -> Result<String> {
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
    let other_uses = findings.iter().filter(|f| f.status == "other-use").count();
    let cold = findings.len() - moves - other_uses;
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
    if other_uses > 0 {
        text.push_str(&format!(
            "check: {other_uses} use(s) with another tool or work object than their target is corrected for land more than {tolerance} mm off (--split-shared, or --accept shared-frames)\n"
        ));
    }
    text
}

/// A use with other frames in words: where, with what, how far off, and
/// what the target is corrected for.
pub(super) fn shared_words(u: &rapidtherm::correct::SharedUse) -> String {
    let instruction = |f: &rapidtherm::correct::FramesUse| match &f.through {
        Some(expr) => format!("{} {expr}", f.instruction),
        None => f.instruction.clone(),
    };
    let (o, c) = (&u.other, &u.corrected_for);
    let off = match (u.residual_mm, u.residual_deg) {
        (Some(mm_off), Some(deg)) if deg >= 0.00005 => {
            format!("it lands {} mm, {}° off", mm(mm_off, 4), mm(deg, 4))
        }
        (Some(mm_off), _) => format!("it lands {} mm off", mm(mm_off, 4)),
        (None, _) => format!(
            "where it lands is known only at run time ({})",
            u.unknown.as_deref().unwrap_or("")
        ),
    };
    let mut text = format!(
        "at {} in {} line {} (tool {}, wobj {}) {off}; corrected for tool {}, wobj {} ({} in {} line {}, its first use)",
        instruction(o), o.routine, o.line, o.tool, o.wobj, c.tool, c.wobj, instruction(c), c.routine, c.line
    );
    if let Some(why) = &u.not_split {
        text.push_str(&format!("; not split: {why}"));
    }
    text
}

/// A reason's words, with what the user can do where the CLI has a flag
/// for it.
pub(super) fn reason_words(reason: Reason, kind: &str, detail: &str) -> String {
    match reason {
        Reason::Expression if kind != "jointtarget" => format!("{detail} (--expand-expressions)"),
        _ => detail.to_string(),
    }
}

/// When the targets are reached, from --at, --schedule or --start; the
/// estimate's notes are said.
fn when_of(
    args: &CorrectArgs,
    program: &rapid::Program,
    robot: &Robot,
    base_frame: Option<nalgebra::Isometry3<f64>>,
) -> Result<When> {
    let (when, notes) = when_and_notes(args, program, robot, base_frame)?;
    for note in &notes {
        note!("{note}");
    }
    Ok(when)
}

/// When the targets are reached, from --at, --schedule or --start, and
/// the notes of the estimate (none for the others), not yet said.
pub(super) fn when_and_notes(
    args: &CorrectArgs,
    program: &rapid::Program,
    robot: &Robot,
    base_frame: Option<nalgebra::Isometry3<f64>>,
) -> Result<(When, Vec<String>)> {
    let default = default_moment(args)?;
    Ok(match (&args.when.at, &args.when.schedule, args.when.start) {
        (Some(at), _, _) => (When::At(moment(at, "--at")?), Vec::new()),
        (None, Some(path), _) => {
            let (name, bytes) = read_input(path)?;
            let when = When::Schedule {
                schedule: Schedule::read(&name, &bytes)?,
                joints: None,
                default,
            };
            (when, Vec::new())
        }
        (None, None, Some(start)) => {
            if !(start.is_finite() && start >= 0.0) {
                return Err(Error::usage("--start: a minute since the cold start (≥ 0)"));
            }
            let estimate =
                schedule::estimate(program, robot, &estimate_options(args, start, base_frame))?;
            let when = When::Schedule {
                schedule: estimate.schedule,
                joints: Some(estimate.joint_schedule),
                default,
            };
            (when, estimate.notes)
        }
        (None, None, None) => {
            return Err(Error::usage(
                "say when the targets are reached: --at MIN, --at steady, --schedule FILE or --start MIN",
            ))
        }
    })
}

/// `--default-time`, read.
pub(super) fn default_moment(args: &CorrectArgs) -> Result<Option<Moment>> {
    args.default_time
        .as_deref()
        .map(|t| moment(t, "--default-time"))
        .transpose()
}

/// The walk of `--start start`.
pub(super) fn estimate_options(
    args: &CorrectArgs,
    start: f64,
    base_frame: Option<nalgebra::Isometry3<f64>>,
) -> EstimateOptions {
    EstimateOptions {
        entry: args.entry.clone(),
        start_min: start,
        cycles: args.cycles,
        base_frame,
    }
}

fn progress_bar(total: usize) -> Option<indicatif::ProgressBar> {
    // Only worth showing for long runs, and only to a person.
    if total < 50_000 || !messages::progress_shown() {
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

pub(super) fn summary_text(outcome: &Outcome) -> String {
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
    if s.shared > 0 {
        text.push_str(&format!(
            "; {} use(s) with another tool or work object",
            s.shared
        ));
    }
    if s.split > 0 {
        text.push_str(&format!("; {} split", s.split));
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
    for u in &outcome.shared {
        // Below what a written number resolves it is a note, not a warning.
        let level = match u.residual_mm {
            Some(r) if r < 0.001 => "note",
            _ => "warning",
        };
        text.push_str(&format!(
            "{level}: other use of {} ({}:{}:{}) [{}]: {}\n",
            u.id,
            u.file,
            u.line,
            u.col,
            Reason::SharedFrames.code(),
            shared_words(u)
        ));
    }
    for s in &outcome.splits {
        text.push_str(&format!(
            "note: split {} ({}:{}): copy {} for tool {}, wobj {}\n",
            s.id, s.file, s.line, s.copy, s.tool, s.wobj
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
