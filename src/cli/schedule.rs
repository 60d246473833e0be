//! `rapidtherm schedule FILE...`: when each target of a program is
//! reached, estimated by walking its entry routine (CSV on stdout, the
//! choices made on stderr).
use super::messages::{self, note, status};
use super::{write_output, Status};
use rapidtherm::correct::job;
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid::{self, task::Task};
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{self, estimate, CutEstimate, Estimate, EstimateOptions};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ScheduleArgs {
    /// RAPID files (.mod, .modx, .prg, .sys) read as one run; `-` reads
    /// standard input. A program file (.pgf), a task folder or a backup
    /// with one motion task (or --task picking one).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub pick: super::tasks::TaskPick,
    /// The arm (its axis speeds time the moves): a URDF file or an
    /// embedded arm's name. Default: the backup's robot type, else the
    /// embedded IRB 140.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    pub robot: Option<String>,
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

pub fn run_schedule(args: ScheduleArgs) -> Result<Status> {
    if args.cycles == 0 {
        return Err(Error::usage("--cycles must be at least 1"));
    }
    let task = super::tasks::one_motion_task(&args.files, &args.pick, "schedule")?;
    // A file given by name is cut once: walked with its cut moves in runs,
    // else read whole from its skeleton. The arm's and the base's errors
    // are said after the program's, as ever.
    let specs = super::arms::arm_specs(args.robot.as_slice())?;
    let cut = cut_file(&task);
    let arm = rapidtherm::resolve::arm::arm_for(&task, &specs);
    if let Ok(arm) = &arm {
        super::events::say_arm(&task.label(), arm);
    }
    let base = rapidtherm::resolve::arm::base_frame(&task);
    let opts = |base_frame| EstimateOptions {
        entry: args.entry.clone(),
        start_min: args.start,
        cycles: args.cycles,
        base_frame,
    };
    if let (Some(cut), Ok(arm), Ok(base)) = (&cut, &arm, &base) {
        let opts = opts(*base);
        if let Some(walked) = walked_in_runs(cut, &arm.robot, &opts) {
            announce(&task);
            let (csv, targets, visits) = walked.to_csv();
            write_output(&args.output, csv.as_bytes())?;
            return Ok(said(&walked.estimate, (targets, visits), &opts));
        }
    }
    let (program, fast) = match cut.as_ref().and_then(read_from_skeleton) {
        Some(p) => {
            announce(&task);
            (p, true)
        }
        None => (super::tasks::read(&task)?.1, false),
    };
    drop(cut);
    let robot = arm?.robot;
    let opts = opts(base?);
    let est = match estimate(&program, &robot, &opts) {
        Ok(est) => est,
        // An error names places and lines of the file: the grammar's
        // reading has them as the file writes them.
        Err(_) if fast => {
            drop(program);
            estimate(&super::read_program(&task.modules)?.1, &robot, &opts)?
        }
        Err(e) => return Err(e),
    };
    write_output(&args.output, est.to_csv().as_bytes())?;
    let counts = (
        est.schedule.targets().len() + est.joint_schedule.targets().len(),
        est.schedule.visit_count() + est.joint_schedule.visit_count(),
    );
    Ok(said(&est, counts, &opts))
}

/// What reading the task says (its notes, its files).
fn announce(task: &Task) {
    job::announce(task, &mut super::events::Said::default());
}

/// The estimate's notes and summary (`counts`: its targets and visits).
fn said(est: &Estimate, (targets, visits): (usize, usize), opts: &EstimateOptions) -> Status {
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

/// A task of one file given by name, memory-mapped and cut by the fast
/// recogniser (its cut literals' numbers kept for a walk).
struct Cut {
    name: String,
    map: memmap2::Mmap,
    skeleton: rapid::fastmove::Skeleton,
}

/// `None` where the task is not one plain file or nothing was cut.
fn cut_file(task: &Task) -> Option<Cut> {
    let [path] = task.modules.as_slice() else {
        return None;
    };
    if task.name.is_some() || !job::is_plain_file(path) {
        return None;
    }
    let map = job::map_file(path).ok()?;
    let started = std::time::Instant::now();
    let skeleton = rapid::fastmove::skeleton_with_poses(&map);
    messages::took("cutting the moves out", started);
    (!skeleton.cuts.is_empty()).then(|| Cut {
        name: path.display().to_string(),
        map,
        skeleton,
    })
}

/// The estimate of a cut file, walked on its skeleton with the cut moves
/// in runs (as `correct --start` walks it): `None` where the walk
/// declines (the program's reading from its skeleton, or the grammar's,
/// then says it).
fn walked_in_runs(cut: &Cut, robot: &Robot, opts: &EstimateOptions) -> Option<CutEstimate> {
    let started = std::time::Instant::now();
    let program = rapid::parse_skeleton_runs(&cut.name, &cut.skeleton, &cut.map).ok()?;
    if !program.warnings.is_empty() {
        return None;
    }
    // Nothing after the walk asks whether the arm reaches each target:
    // the walk does.
    let file = (&cut.skeleton, &cut.map[..]);
    let walked = schedule::estimate_cuts(&program, file, robot, opts, true).ok()??;
    messages::took("walking the program's skeleton", started);
    Some(walked)
}

/// The program of a cut file, read from its skeleton (the moves the fast
/// recogniser reads put back by the assembly: `rapid::parse_skeleton`):
/// the program the grammar makes of it, a CAM program's at a tenth of the
/// cost. `None` where it has something to say (the grammar's reading
/// then says it).
fn read_from_skeleton(cut: &Cut) -> Option<rapid::Program> {
    let started = std::time::Instant::now();
    let program = rapid::parse_skeleton(&cut.name, &cut.skeleton, &cut.map).ok()?;
    messages::took("reading the program from its skeleton", started);
    program.warnings.is_empty().then_some(program)
}
