//! `simulate`: simulated measurements ("real" data) of an arm with chosen
//! effects and noise. Its arguments are read into a [`SimulateCommand`]
//! (every usage error raised there, the output checked) before any input
//! is read; the run reads the plan alone.

use super::diagnose::{load_model, robot_choice, Messages};
use super::{read_input, write_output, Status};
use rapidtherm::csv_table::CsvTable;
use rapidtherm::diagnose::job;
use rapidtherm::diagnose::plan::RobotChoice;
use rapidtherm::diagnose::simulate::{
    iso_cube_poses, program_poses, random_poses, simulate_arm, SimSpec,
};
use rapidtherm::error::{Error, Result};
use rapidtherm::model::effects::Effect;
use rapidtherm::writes::{Checked, Plan, Role};
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TempsSource {
    /// Write t1_c..t6_c columns.
    Measured,
    /// Leave temperatures to the reader's heating profile.
    Profile,
}

#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Poses: `random:N` (uniform within the joint limits), `joints:FILE.csv`
    /// (columns j1_deg..j6_deg, optional pose), `iso-cube` or `program:FILE`.
    #[arg(long, default_value = "random:12")]
    poses: String,
    /// Minutes since the cold start: START:END:STEP or a comma list.
    #[arg(long, default_value = "0:180:6")]
    times: String,
    /// An effect to add, `NAME[:param=value,...]` (repeatable).
    #[arg(long = "effect", value_name = "NAME[:P=V,...]")]
    effects: Vec<String>,
    /// Tracker noise, mm per axis.
    #[arg(long, default_value_t = 0.01)]
    noise: f64,
    /// Also write the measured orientation (qw, qx, qy, qz).
    #[arg(long)]
    orientation: bool,
    /// Write motor temperatures, or leave them to the heating profile.
    #[arg(long, value_enum, default_value_t = TempsSource::Profile)]
    temps: TempsSource,
    /// Random seed (poses and noise).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The model the "real" robot departs from (default: nominal IRB 140).
    #[arg(long)]
    model: Option<PathBuf>,
    /// An arm with an offset shoulder and a spherical wrist, by name
    /// (`rapidtherm arms`) or URDF file; its lengths replace the model's
    /// geometry.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    robot: Option<PathBuf>,
    /// Output CSV (`-`: standard output).
    #[arg(short = 'o', long = "output", default_value = "-")]
    output: PathBuf,
}

/// `--poses`, read: where the simulated poses come from.
#[derive(Debug, Clone, PartialEq)]
enum Poses {
    /// `random:N`: uniform within the joint limits.
    Random(usize),
    /// `joints:FILE.csv`: columns j1_deg..j6_deg, optional pose.
    Joints(PathBuf),
    /// `iso-cube`: the arm's ISO 9283 cube.
    IsoCube,
    /// `program:FILE`: the poses a RAPID program moves to.
    Program(PathBuf),
}

impl Poses {
    fn parse(spec: &str) -> Result<Poses> {
        if let Some(n) = spec.strip_prefix("random:") {
            let n: usize = n
                .parse()
                .ok()
                .filter(|&n| n > 0 && n <= 100_000)
                .ok_or_else(|| Error::usage(format!("--poses {spec}: N must be 1..100000")))?;
            return Ok(Poses::Random(n));
        }
        if let Some(file) = spec.strip_prefix("joints:") {
            return Ok(Poses::Joints(PathBuf::from(file)));
        }
        if spec == "iso-cube" {
            return Ok(Poses::IsoCube);
        }
        if let Some(file) = spec.strip_prefix("program:") {
            return Ok(Poses::Program(PathBuf::from(file)));
        }
        Err(Error::usage(format!(
            "--poses `{spec}`: expected random:N, joints:FILE.csv, iso-cube or program:FILE"
        )))
    }

    /// The file the poses are read from, if any.
    fn file(&self) -> Option<&Path> {
        match self {
            Poses::Joints(f) | Poses::Program(f) => Some(f),
            Poses::Random(_) | Poses::IsoCube => None,
        }
    }
}

/// Everything `simulate` does, read from its arguments once.
pub struct SimulateCommand {
    poses: Poses,
    times: Vec<f64>,
    /// The `--effect`s, added to the model's own.
    effects: Vec<Effect>,
    noise_mm: f64,
    orientation: bool,
    temps: TempsSource,
    seed: u64,
    model: Option<PathBuf>,
    robot: Option<RobotChoice>,
    output: PathBuf,
    /// The output, checked against the inputs before any is read.
    checked: Checked,
}

/// The plan of `simulate`'s arguments: every usage error is raised here,
/// and the output checked, before any input is read.
pub fn plan(args: SimulateArgs) -> Result<SimulateCommand> {
    if !(args.noise.is_finite() && args.noise >= 0.0) {
        return Err(Error::usage("--noise must be a finite number >= 0"));
    }
    super::output::check_file("-o", &args.output)?;
    rapidtherm::diagnose::simulate::check_noise(args.noise)?;
    let poses = Poses::parse(&args.poses)?;
    let mut writes = Plan::new(false);
    for f in poses
        .file()
        .into_iter()
        .chain(args.model.as_deref())
        .chain(args.robot.as_deref())
    {
        writes.input(f);
    }
    writes.output("-o", &args.output, Role::Named);
    let checked = super::output::check(&writes)?;
    let effects = args
        .effects
        .iter()
        .map(|spec| Effect::parse_spec(spec))
        .collect::<Result<Vec<Effect>>>()?;
    let robot = robot_choice(&args.robot)?;
    let times = parse_times(&args.times)?;
    Ok(SimulateCommand {
        poses,
        times,
        effects,
        noise_mm: args.noise,
        orientation: args.orientation,
        temps: args.temps,
        seed: args.seed,
        model: args.model,
        robot,
        output: args.output,
        checked,
    })
}

pub fn run(cmd: SimulateCommand) -> Result<Status> {
    let model = load_model(&cmd.model)?;
    let mut effects = model.effects()?;
    effects.extend(cmd.effects.iter().cloned());
    let setup = job::setup(
        cmd.robot.as_ref(),
        &model,
        cmd.model.is_some(),
        &mut Messages,
    )?;
    let spec = SimSpec {
        base: setup.arm.base(&model),
        poses: read_poses(&cmd.poses, cmd.seed, &setup)?,
        times: cmd.times.clone(),
        effects,
        noise_mm: cmd.noise_mm,
        orientation: cmd.orientation,
        measured_temps: cmd.temps == TempsSource::Measured,
        seed: cmd.seed,
    };
    let profile = model.profile()?;
    let meas = simulate_arm(&spec, &setup.arm.map, profile.as_ref())?;
    write_output(&cmd.checked, &cmd.output, meas.to_csv().as_bytes())?;
    Ok(Status::Success)
}

fn read_poses(poses: &Poses, seed: u64, setup: &job::Setup) -> Result<Vec<(String, [f64; 6])>> {
    let limits = &setup.arm.limits_deg;
    match poses {
        Poses::Random(n) => Ok(random_poses(*n, limits, seed)),
        Poses::Joints(file) => read_joints(file, limits),
        Poses::IsoCube => iso_cube_poses(&setup.robot, &setup.arm.iso_cube()?),
        Poses::Program(file) => {
            let (name, bytes) = read_input(file)?;
            let program = rapidtherm::rapid::parse(&name, &bytes)?;
            program_poses(&program, &setup.robot)
        }
    }
}

/// `joints:FILE.csv`: a pose per row, each axis within its limits.
fn read_joints(file: &Path, limits: &[(f64, f64); 6]) -> Result<Vec<(String, [f64; 6])>> {
    let (name, bytes) = read_input(file)?;
    let table = CsvTable::parse(&name, &bytes)?;
    let cols: Vec<usize> = (1..=6)
        .map(|i| table.require(&format!("j{i}_deg")))
        .collect::<Result<_>>()?;
    let label = table.column("pose");
    let mut out = Vec::new();
    for (k, row) in table.rows.iter().enumerate() {
        let mut q = [0.0; 6];
        for i in 0..6 {
            let v = table.number(row, cols[i])?;
            let (lo, hi) = limits[i];
            if v < lo || v > hi {
                return Err(
                    Error::input(format!("axis {} at {v}° is outside {lo}..{hi}°", i + 1))
                        .at(table.field_location(row, cols[i])),
                );
            }
            q[i] = v.to_radians();
        }
        let name = match label {
            Some(c) => table.text(row, c)?.to_string(),
            None => format!("P{}", k + 1),
        };
        out.push((name, q));
    }
    if out.is_empty() {
        return Err(Error::input(format!("{name}: no poses")));
    }
    Ok(out)
}

/// Parse `--times`: `START:END:STEP` (inclusive) or a comma list of
/// minutes.
fn parse_times(text: &str) -> Result<Vec<f64>> {
    let bad = || {
        Error::usage(format!(
            "--times `{text}`: expected START:END:STEP or a comma list of minutes"
        ))
    };
    let num = |s: &str| -> Result<f64> {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(bad)
    };
    let parts: Vec<&str> = text.split(':').collect();
    let times: Vec<f64> = match parts.as_slice() {
        [a, b, c] => {
            let (start, end, step) = (num(a)?, num(b)?, num(c)?);
            if step <= 0.0 || end < start {
                return Err(bad());
            }
            let n = ((end - start) / step + 1e-9).floor() as usize;
            if n > 1_000_000 {
                return Err(Error::usage("--times: too many times"));
            }
            (0..=n).map(|i| start + i as f64 * step).collect()
        }
        [list] => list.split(',').map(num).collect::<Result<_>>()?,
        _ => return Err(bad()),
    };
    if times.is_empty() || times.iter().any(|&t| t < 0.0) || times.windows(2).any(|w| w[1] < w[0]) {
        return Err(Error::usage(format!(
            "--times `{text}`: minutes must be >= 0 and increasing"
        )));
    }
    Ok(times)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_parse() {
        assert_eq!(parse_times("0:12:6").unwrap(), vec![0.0, 6.0, 12.0]);
        assert_eq!(parse_times("0,5,7.5").unwrap(), vec![0.0, 5.0, 7.5]);
        assert!(parse_times("0:10:-1").is_err());
        assert!(parse_times("5,1").is_err());
    }

    #[test]
    fn poses_parse() {
        assert_eq!(Poses::parse("random:3").unwrap(), Poses::Random(3));
        assert_eq!(
            Poses::parse("joints:a.csv").unwrap(),
            Poses::Joints(PathBuf::from("a.csv"))
        );
        assert_eq!(Poses::parse("iso-cube").unwrap(), Poses::IsoCube);
        assert!(Poses::parse("random:0").is_err());
        assert!(Poses::parse("cube").is_err());
    }
}
