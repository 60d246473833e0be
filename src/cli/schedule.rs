//! `rapidtherm schedule FILE...`: when each target of a program is
//! reached, estimated by walking its entry routine (CSV on stdout, the
//! choices made on stderr).
use super::messages::{self, note, status};
use super::tasks::TaskPick;
use super::{write_output, Status};
use rapidtherm::error::{Error, Result};
use rapidtherm::resolve::arm::{
    arm_for, base_frame, check_placement, check_task_specs, ArmSpec, Placing,
};
use rapidtherm::schedule::{estimate, Estimate, EstimateOptions};
use rapidtherm::writes::{Plan, Role};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ScheduleArgs {
    /// RAPID files (.mod, .modx, .prg, .sys) read as one run; `-` reads
    /// standard input. A program file (.pgf), a task folder or a backup
    /// with one motion task (or --task picking one).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub pick: super::tasks::TaskArgs,
    /// The arm (its axis speeds time the moves): a URDF file or an
    /// embedded arm's name. Default: the backup's robot type, else the
    /// embedded IRB 140.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    pub robot: Option<String>,
    /// Put a task whose backup does not say where its robot stands at the
    /// world origin, as the arm named or the IRB 140 (else it is refused).
    #[arg(long)]
    pub accept_default_placement: bool,
    /// Minutes since the cold start at which the program starts.
    #[arg(long, value_name = "MIN", default_value_t = 0.0)]
    pub start: f64,
    /// Entry routine (case-insensitive).
    #[arg(long, value_name = "NAME", default_value = "main")]
    pub entry: String,
    /// How many times the entry routine runs back to back.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub cycles: u32,
    /// Where to write the schedule (CSV); `-` is standard output.
    #[arg(short = 'o', long = "output", value_name = "OUT", default_value = "-")]
    pub output: PathBuf,
}

/// Everything `schedule` does, read from its arguments once.
pub struct ScheduleCommand {
    files: Vec<PathBuf>,
    pick: TaskPick,
    /// `--robot`, a catalogue name looked up already.
    specs: Vec<ArmSpec>,
    placing: Placing,
    start_min: f64,
    entry: String,
    cycles: u32,
    output: PathBuf,
}

/// The plan of `schedule`'s arguments: every usage error is raised here,
/// before any input is read.
pub fn plan(args: ScheduleArgs) -> Result<ScheduleCommand> {
    if args.cycles == 0 {
        return Err(Error::usage("--cycles must be at least 1"));
    }
    super::output::check_file("-o", &args.output)?;
    Ok(ScheduleCommand {
        specs: super::arms::arm_specs(args.robot.as_slice())?,
        files: args.files,
        pick: args.pick.into(),
        placing: super::arms::placing(args.accept_default_placement),
        start_min: args.start,
        entry: args.entry,
        cycles: args.cycles,
        output: args.output,
    })
}

pub fn run(cmd: ScheduleCommand) -> Result<Status> {
    let task = super::tasks::one_motion_task(&cmd.files, &cmd.pick, "schedule")?;
    // The output checked against the task's files before they are read.
    let mut writes = Plan::new(false);
    for f in cmd.files.iter().chain(&task.modules) {
        writes.input(f);
    }
    writes.output("-o", &cmd.output, Role::Named);
    let checked = super::output::check(&writes)?;
    // The program's errors are said before the arm's and the base's.
    let program = super::tasks::read(&task)?.1;
    check_task_specs(&cmd.specs, std::slice::from_ref(&task))?;
    let arm = arm_for(&task, &cmd.specs)?;
    check_placement(&task, &arm, cmd.placing)?;
    super::events::say_arm(&task.label(), &arm, task.not_a_backup.as_deref());
    let opts = EstimateOptions {
        entry: cmd.entry.clone(),
        start_min: cmd.start_min,
        cycles: cmd.cycles,
        base_frame: base_frame(&task)?,
    };
    let started = std::time::Instant::now();
    let est = estimate(&program, &arm.robot, &opts)?;
    messages::took("walking the program", started);
    write_output(&checked, &cmd.output, est.to_csv().as_bytes())?;
    Ok(said(&est, &opts))
}

/// The estimate's notes and summary: its targets and visits, and the
/// minutes they span.
fn said(est: &Estimate, opts: &EstimateOptions) -> Status {
    let targets = est.schedule.targets().len() + est.joint_schedule.targets().len();
    let visits = est.schedule.visit_count() + est.joint_schedule.visit_count();
    for n in &est.notes {
        note!("{n}");
    }
    status!(
        "{targets} target(s), {visits} visit(s), {:.2} min from minute {} to {:.2}",
        est.duration_min,
        opts.start_min,
        opts.start_min + est.duration_min
    );
    Status::Success
}
