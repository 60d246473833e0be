//! `rapidtherm correct`: the main job's command line. Its arguments are
//! read into a [`CorrectPlan`] before any input is opened (every usage
//! error is raised there); the library's job runs the plan
//! (`rapidtherm::correct::job`); this file renders what it returns (the
//! report, the check's list, the diff) and puts the written files in
//! place.

use super::ci_report::{self, ReportFormat};
use super::correct_words::{reason_words, shared_words, summary_text};
use super::events::EventMessages;
use super::messages::{self, note};
use super::output::FileSink;
use super::tasks;
use super::unified_diff::unified_diff;
use super::Format;
use super::{write_stdout, Status};
use rapidtherm::correct::check::{counts, CheckFinding, CheckRule, FindingStatus};
use rapidtherm::correct::job::{self, moves_a_robot, CorrectedTask};
use rapidtherm::correct::plan::{
    Action, ArmChoice, CorrectJob, CorrectPlan, Destination, ModelSource, RuntimePlan, TimeBasis,
};
use rapidtherm::correct::{Kind, Outcome, Reason};
use rapidtherm::error::{Error, Result};
use rapidtherm::model::warm::Moment;
use rapidtherm::model::Model;
use rapidtherm::report::{mm, render_csv, render_table, Align};
use rapidtherm::schedule::WhichVisit;
use rapidtherm::writes::{Checked, Made, Plan, Role};
use std::path::{Path, PathBuf};

/// `--visit`: the command line's names for [`Visit`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum VisitArg {
    First,
    Mean,
    Last,
}

impl From<VisitArg> for WhichVisit {
    fn from(v: VisitArg) -> WhichVisit {
        match v {
            VisitArg::First => WhichVisit::First,
            VisitArg::Mean => WhichVisit::Mean,
            VisitArg::Last => WhichVisit::Last,
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
    /// Moves to a procedure's parameter that its calls do not settle.
    Parameter,
    /// Moves to targets declared in none of the files read.
    Undeclared,
    /// Moves with a tooldata or wobjdata declared PERS without a value
    /// (another task or module sets it).
    SetElsewhere,
    /// Moves by an instruction rapidtherm does not know (an option's).
    Instruction,
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
            AcceptArg::Parameter => Reason::Parameter,
            AcceptArg::Undeclared => Reason::Undeclared,
            AcceptArg::SetElsewhere => Reason::SetElsewhere,
            AcceptArg::Instruction => Reason::Instruction,
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
    // A negative minute is read as a value (and refused as a minute), not
    // taken for a flag.
    #[arg(
        long,
        value_name = "MIN|steady",
        group = "when",
        allow_hyphen_values = true
    )]
    pub at: Option<String>,
    /// Times per target: a CSV `target,time_min` (`rapidtherm schedule`
    /// writes one).
    #[arg(long, value_name = "FILE.csv", group = "when")]
    pub schedule: Option<PathBuf>,
    /// Estimate the times from the program itself, starting at this minute
    /// (walks --entry, follows calls and loops, times every move).
    #[arg(
        long,
        value_name = "MIN",
        group = "when",
        allow_negative_numbers = true
    )]
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
    pub pick: tasks::TaskArgs,
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
    /// Put a task whose backup does not say where its robot stands (a
    /// missing or broken BACKINFO, SYS.cfg or MOC.cfg) at the world origin,
    /// as the arm named or the IRB 140; without it such a task is refused.
    #[arg(long)]
    pub accept_default_placement: bool,
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
    /// Correct on the controller instead, all day: write a RAPID system
    /// module (NAME.sys, beside the output) that carries the arm's heating
    /// state through running and stopped spans and corrects any target
    /// when the program reaches it, and rewrite every move to call it.
    /// The declarations keep their cold numbers; no --at, --schedule or
    /// --start (docs/runtime.md). With --check: the CI gate, exit 1 unless
    /// every move calls the module and the module beside is the one this
    /// version writes for the program and model.
    #[arg(long, group = "when", conflicts_with_all = ["default_time", "split_shared", "expand_expressions", "plot"])]
    pub runtime: bool,
    /// With --runtime: the module's name (a RAPID identifier of at most
    /// 27 characters); its global routines are NAME, NAMEJ, NAMET, NAMEJT
    /// and NAMEReset, every other name of it is LOCAL.
    #[arg(long, value_name = "NAME", default_value = "RtWarm")]
    pub runtime_module: String,
    /// Replace a file this run names itself (the --runtime module, a
    /// picture in the --plot folder) even where it is not one rapidtherm
    /// wrote (docs/limits.md); without it such a file is refused.
    #[arg(long)]
    pub force: bool,
    /// Format of the per-target report (printed when no output is chosen);
    /// with --check also github or junit, for CI (docs/ci.md).
    #[arg(long, value_enum, default_value_t = ReportFormat::Table)]
    pub format: ReportFormat,
}

/// A moment as the command line writes it: a minute since the cold
/// start, or `steady`. The one place a time is read from text.
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

/// The model `--model` names (the embedded default without it).
pub fn load_model(path: Option<&Path>) -> Result<Model> {
    job::load_model(&model_source(path))
}

/// `--model`: an embedded model by name (`default`, the calibrated one;
/// `base`, docs/model.md's unscaled base model) when no file of that name
/// exists, else a model file.
pub fn model_source(path: Option<&Path>) -> ModelSource {
    match path {
        None => ModelSource::Default,
        Some(p) if !p.exists() && p.to_str().and_then(Model::named).is_some() => {
            ModelSource::Named(p.display().to_string())
        }
        Some(p) => ModelSource::File(p.to_path_buf()),
    }
}

/// Everything `correct` does, read from its arguments once: the library's
/// plan of the job and what the command line does around it. Once it is
/// made, the arguments are not read again.
pub struct CorrectCommand {
    /// The programs, and the tasks of them to work on.
    files: Vec<PathBuf>,
    pick: tasks::TaskPick,
    job: CorrectJob,
    /// Files the flags name that the run reads (the model, URDF arms):
    /// none of them is written over.
    flag_inputs: Vec<PathBuf>,
    /// Replace a file the run names itself even where rapidtherm did not
    /// write it.
    force: bool,
    format: ReportFormat,
    /// The folder the pictures go to.
    plot: Option<PathBuf>,
}

/// The plan of the arguments: every usage error is raised here, before
/// any input is read. The arguments are spent here: the run reads the
/// plan alone.
pub fn plan(args: CorrectArgs) -> Result<CorrectCommand> {
    if args.in_place && args.files.iter().any(|f| f == Path::new("-")) {
        return Err(Error::usage("--in-place cannot rewrite standard input"));
    }
    // A tolerance beyond any thermal correction would let every check
    // pass: bounded by the rule, before any input is read.
    let rule = CheckRule::new(
        args.tolerance,
        args.accept.iter().map(|&a| a.into()).collect(),
    )?;
    ci_report::refuse_outside_check(args.format, args.check, args.diff)?;
    if args.output.is_some() && args.files.len() > 1 {
        return Err(one_file());
    }
    let default = args
        .default_time
        .as_deref()
        .map(|t| moment(t, "--default-time"))
        .transpose()?;
    // The module times itself by the controller's clock: there is no
    // basis to read (--runtime is one of clap's group of time bases).
    let when = match (&args.when.at, &args.when.schedule, args.when.start) {
        _ if args.runtime => None,
        (Some(at), _, _) => Some(TimeBasis::At(moment(at, "--at")?)),
        (None, Some(file), _) => Some(TimeBasis::Schedule {
            file: file.clone(),
            default,
        }),
        (None, None, Some(start)) => {
            if !(start.is_finite() && start >= 0.0) {
                return Err(Error::usage("--start: a minute since the cold start (≥ 0)"));
            }
            Some(TimeBasis::Start {
                start_min: start,
                entry: args.entry.clone(),
                cycles: args.cycles,
                default,
            })
        }
        (None, None, None) => {
            return Err(Error::usage(
                "say when the targets are reached: --at MIN, --at steady, --schedule FILE or --start MIN",
            ))
        }
    };
    let action = match (&args.output, args.in_place, args.check, args.diff) {
        (_, _, _, true) => Action::Diff {
            check: args.check.then_some(rule),
        },
        (_, _, true, false) => Action::Check(rule),
        (Some(out), _, _, _) if out == Path::new("-") => Action::Write(Destination::Stdout),
        (Some(out), _, _, _) => Action::Write(Destination::File(out.clone())),
        (None, true, _, _) => Action::Write(Destination::InPlace {
            backup: args.backup.clone(),
        }),
        (None, false, _, _) => Action::Report,
    };
    super::plot::check_dir(args.plot.as_deref())?;
    let arms = ArmChoice {
        model: model_source(args.model.as_deref()),
        specs: super::arms::arm_specs(&args.robot)?,
        irb140_thermal: args.irb140_thermal,
        placing: super::arms::placing(args.accept_default_placement),
    };
    let job = match when {
        Some(when) => CorrectJob::Correct(CorrectPlan {
            when,
            visit: args.visit.into(),
            arms,
            expand_expressions: args.expand_expressions,
            split_shared: args.split_shared,
            action,
            keep_rows: args.plot.is_some(),
        }),
        None => {
            super::correct_runtime::check_module(&args.runtime_module, &action)?;
            CorrectJob::Runtime(RuntimePlan {
                module: args.runtime_module,
                arms,
                action,
            })
        }
    };
    let mut flag_inputs: Vec<PathBuf> = args.model.into_iter().collect();
    for r in &args.robot {
        let file = r.split_once('=').map_or(r.as_str(), |(_, f)| f);
        if Path::new(file).is_file() {
            flag_inputs.push(PathBuf::from(file));
        }
    }
    Ok(CorrectCommand {
        files: args.files,
        pick: args.pick.into(),
        job,
        flag_inputs,
        force: args.force,
        format: args.format,
        plot: args.plot,
    })
}

fn one_file() -> Error {
    Error::usage("-o writes one file: give one input, or use --in-place for several")
}

/// Every file the run will write, planned once its tasks are found and
/// checked before any of their files is read (`rapidtherm::writes`): the
/// corrected programs, the `--runtime` modules, the pictures.
fn writes(cmd: &CorrectCommand, found: &[rapidtherm::rapid::task::Task]) -> Result<Checked> {
    let motion: Vec<&rapidtherm::rapid::task::Task> =
        found.iter().filter(|t| moves_a_robot(t)).collect();
    // A file of two tasks is the job's to name first (it is not written
    // twice over).
    job::refuse_files_of_two_tasks(&motion.iter().map(|t| (*t).clone()).collect::<Vec<_>>())?;
    let mut w = Plan::new(cmd.force);
    let schedule = match &cmd.job {
        CorrectJob::Correct(plan) => plan.when.schedule_file(),
        CorrectJob::Runtime(_) => None,
    };
    for f in schedule
        .into_iter()
        .chain(cmd.flag_inputs.iter().map(PathBuf::as_path))
    {
        w.input(f);
    }
    let action = cmd.job.action();
    let in_place = matches!(action, Action::Write(Destination::InPlace { .. }));
    if !in_place {
        for t in &motion {
            for m in &t.modules {
                w.input(m);
            }
        }
    }
    if let Action::Write(dest) = action {
        let (flag, role) = match dest {
            Destination::InPlace { .. } => ("--in-place", Role::InPlace),
            _ => ("-o", Role::Named),
        };
        for f in dest.files(&motion) {
            w.output(flag, &f, role);
        }
        if let CorrectJob::Runtime(runtime) = &cmd.job {
            let flag = format!("--runtime-module {}", runtime.module);
            for m in
                rapidtherm::correct::runtime::write::module_paths(dest, &motion, &runtime.module)
            {
                w.output(&flag, &m, Role::Made(Made::RuntimeModule));
            }
            // The backup's list of the modules a restore loads.
            for b in
                rapidtherm::correct::runtime::write::backinfo_paths(dest, &motion, &runtime.module)
            {
                w.output("--in-place", &b, Role::InPlace);
            }
        }
    }
    if let Some(dir) = &cmd.plot {
        let flag = format!("--plot {}", dir.display());
        for name in super::plot::names(&motion) {
            w.output(&flag, &dir.join(name), Role::Made(Made::Picture));
        }
    }
    super::output::check(&w)
}

pub fn run(cmd: CorrectCommand) -> Result<Status> {
    let found = tasks::select(&cmd.files, &cmd.pick)?;
    let checked = writes(&cmd, &found)?;
    let plan = match &cmd.job {
        CorrectJob::Runtime(runtime) => {
            return super::correct_runtime::run(runtime, found, &checked)
        }
        CorrectJob::Correct(plan) => plan,
    };
    // What the plan asks of the tasks found: known once they are.
    let motion: Vec<&rapidtherm::rapid::task::Task> =
        found.iter().filter(|t| moves_a_robot(t)).collect();
    let one_output = matches!(
        plan.action,
        Action::Write(Destination::File(_) | Destination::Stdout)
    );
    if one_output && (motion.len() != 1 || motion[0].modules.len() != 1) {
        return Err(one_file());
    }
    if plan.when.schedule_file().is_some() && motion.len() > 1 {
        return Err(Error::usage(
            "a schedule file times the targets of one task: pick it with --task (or use --start, which times each task)",
        ));
    }
    let mut sink = FileSink::new(plan.action.backup(), &checked);
    let runs = job::run(plan, found, &mut EventMessages::default(), &mut sink)?;
    let drawn: Vec<_> = runs
        .iter()
        .map(|r| (&r.task, &r.inputs, &r.outcome))
        .collect();
    let pictures = super::plot::draw(cmd.plot.as_deref(), &drawn)?;
    sink.commit()?;
    let status = emit(plan, cmd.format, &runs)?;
    super::plot::write(&checked, cmd.plot.as_deref(), &pictures)?;
    Ok(status)
}

/// Print what the runs found, as the plan asks, in `format`.
fn emit(plan: &CorrectPlan, format: ReportFormat, runs: &[CorrectedTask]) -> Result<Status> {
    // A task of a backup is named; files given one by one are one
    // unnamed task, reported as before.
    let named = runs.len() > 1 || runs.iter().any(|r| r.task.name.is_some());
    let heading = |r: &CorrectedTask| -> String {
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
    let rule = match &plan.action {
        Action::Check(rule) | Action::Diff { check: Some(rule) } => Some(rule),
        _ => None,
    };
    let summaries = || -> String {
        runs.iter()
            .map(|r| heading(r) + &summary_text(&r.outcome, rule.is_some()))
            .collect()
    };
    let found: Vec<Vec<CheckFinding>> = runs
        .iter()
        .map(|r| {
            rule.map(|rule| rule.findings(&r.outcome))
                .unwrap_or_default()
        })
        .collect();
    let findings: Vec<Vec<Row>> = found
        .iter()
        .map(|f| f.iter().map(Row::of).collect())
        .collect();
    let any_finding = findings.iter().any(|f| !f.is_empty());
    let verdict = |rule: &CheckRule| check_verdict(&found.concat(), rule.tolerance);
    match &plan.action {
        Action::Diff { check } => {
            let mut text = Vec::new();
            for r in runs {
                for ((name, before), after) in r.inputs.iter().zip(&r.outcome.outputs) {
                    text.extend(unified_diff(name, before.bytes(), after));
                }
            }
            write_stdout(&text)?;
            messages::lines(&summaries());
            if let Some(rule) = check {
                messages::outcome_lines(&per_task(
                    runs,
                    &findings,
                    Format::Table,
                    named,
                    check_list,
                )?);
                messages::lines(&verdict(rule));
            }
            let changed = runs.iter().any(CorrectedTask::changed);
            Ok(if changed || (check.is_some() && any_finding) {
                Status::Changes
            } else {
                Status::Success
            })
        }
        Action::Check(rule) => {
            messages::lines(&summaries());
            let list = match format.data() {
                Some(format) => per_task(runs, &findings, format, named, check_list)?,
                None => {
                    let checked: Vec<ci_report::CheckedTask> = runs
                        .iter()
                        .map(|r| ci_report::CheckedTask {
                            task: named.then(|| r.task.label()),
                            files: r.inputs.iter().map(|(n, _)| n.as_str()).collect(),
                            outcome: &r.outcome,
                        })
                        .collect();
                    ci_report::check(format, &checked, rule)?
                }
            };
            write_stdout(list.as_bytes())?;
            messages::lines(&verdict(rule));
            Ok(if any_finding {
                Status::Changes
            } else {
                Status::Success
            })
        }
        Action::Write(_) => {
            messages::lines(&summaries());
            Ok(Status::Success)
        }
        Action::Report => {
            // Refused before the run: github and junit report a check only.
            let format = format.data().unwrap_or_default();
            let outcomes: Vec<&Outcome> = runs.iter().map(|r| &r.outcome).collect();
            write_stdout(
                per_task(runs, &outcomes, format, named, |o, f| {
                    super::correct_report::report(o, f)
                })?
                .as_bytes(),
            )?;
            if format == Format::Table {
                messages::lines(&summaries());
            }
            Ok(Status::Success)
        }
    }
}

fn in_task(named: bool, r: &CorrectedTask) -> String {
    if named {
        format!("task {}: ", r.task.label())
    } else {
        String::new()
    }
}

/// One rendering per task, joined (see [`tasks::join`]).
fn per_task<T>(
    runs: &[CorrectedTask],
    items: &[T],
    format: Format,
    named: bool,
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
    tasks::join(format, named.then_some(shown.as_slice()), texts, &extra)
}

/// One line of `--check`'s list, as its table, CSV and JSON show it.
#[derive(Clone, serde::Serialize)]
struct Row {
    id: String,
    kind: Kind,
    file: String,
    line: u32,
    col: u32,
    status: FindingStatus,
    /// The length of the correction (a vector in `correct`'s JSON).
    #[serde(rename = "correction_norm_mm")]
    correction_mm: Option<f64>,
    /// For `other-use`: how far off the TCP lands there (`None` in JSON
    /// where only the run time knows).
    #[serde(skip_serializing_if = "Option::is_none")]
    residual_mm: Option<Option<f64>>,
    reason: Option<Reason>,
    detail: String,
}

impl Row {
    fn of(f: &CheckFinding) -> Row {
        match *f {
            CheckFinding::Moves(c) => Row {
                id: c.id.clone(),
                kind: c.kind,
                file: c.file.clone(),
                line: c.line,
                col: c.col,
                status: f.status(),
                correction_mm: Some(c.correction_norm_mm),
                residual_mm: None,
                reason: None,
                detail: String::new(),
            },
            CheckFinding::LeftAlone(l) => Row {
                id: l.id.clone(),
                kind: l.kind,
                file: l.file.clone(),
                line: l.line,
                col: l.col,
                status: f.status(),
                correction_mm: None,
                residual_mm: None,
                reason: Some(l.reason),
                detail: reason_words(l.reason, l.kind, &l.detail),
            },
            CheckFinding::OtherUse(u) => Row {
                id: u.id.clone(),
                kind: u.kind,
                file: u.file.clone(),
                line: u.line,
                col: u.col,
                status: f.status(),
                correction_mm: None,
                residual_mm: Some(u.residual_mm),
                reason: Some(Reason::SharedFrames),
                detail: shared_words(u),
            },
        }
    }
}

fn check_list(findings: &Vec<Row>, format: Format) -> Result<String> {
    let header = ["target", "kind", "at", "status", "corr_mm", "reason"];
    let rows: Vec<Vec<String>> = findings
        .iter()
        .map(|f| {
            vec![
                f.id.clone(),
                f.kind.to_string(),
                format!("{}:{}:{}", f.file, f.line, f.col),
                f.status.code().to_string(),
                f.correction_mm.map_or(String::new(), |c| mm(c, 4)),
                f.reason
                    .map_or(String::new(), |r| format!("{}: {}", r.code(), f.detail)),
            ]
        })
        .collect();
    Ok(match format {
        Format::Json => rapidtherm::report::json::rows("correct-check", "findings", findings)?,
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

fn check_verdict(findings: &[CheckFinding], tolerance: f64) -> String {
    let (moves, cold, other_uses) = counts(findings);
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
