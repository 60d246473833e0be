//! `--robot NAME|FILE.urdf` for every command that takes an arm, and
//! `arms`: the catalogue of ABB arms by name.

use super::messages::info;
use super::{write_stdout, Format, Status};
use rapidtherm::error::{Error, Result};
use rapidtherm::report::{render_csv, render_table, Align};
use rapidtherm::resolve::arm::{names_a_file, ArmSource, ArmSpec, Placing};
use rapidtherm::robot::abb::{self, AbbArm};
use rapidtherm::robot::Robot;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct ArmsArgs {
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

/// What `--robot` names: a URDF file (a file that exists, or a path ending
/// in `.urdf`) or an arm of the catalogue.
enum RobotArg<'a> {
    File(&'a Path),
    Name(&'a str),
}

fn robot_arg(arg: &Path) -> Result<RobotArg<'_>> {
    if names_a_file(arg) {
        return Ok(RobotArg::File(arg));
    }
    arg.to_str().map(RobotArg::Name).ok_or_else(|| {
        Error::usage(format!(
            "--robot {}: not a file, nor an arm name",
            arg.display()
        ))
    })
}

/// The arm `--robot` gives, read from the command line: looked up in the
/// catalogue (a name it lacks is a usage error before any input is read),
/// a URDF file read when the arm is loaded.
#[derive(Debug, Clone)]
pub enum RobotPick {
    /// No `--robot`: the embedded IRB 140.
    Irb140,
    Urdf(PathBuf),
    /// `written`: the name as `--robot` gave it.
    Catalogue {
        arm: &'static AbbArm,
        written: String,
    },
}

/// `--robot` (a URDF file or a catalogue name), or the embedded IRB 140
/// without it.
pub fn robot_pick(arg: Option<&Path>) -> Result<RobotPick> {
    Ok(match arg {
        None => RobotPick::Irb140,
        Some(a) => match robot_arg(a)? {
            RobotArg::File(p) => RobotPick::Urdf(p.to_path_buf()),
            RobotArg::Name(n) => RobotPick::Catalogue {
                arm: find_arm(n)?,
                written: n.to_string(),
            },
        },
    })
}

/// The arm picked, its URDF file read.
pub fn load_robot(pick: &RobotPick) -> Result<Robot> {
    let (robot, from) = match pick {
        RobotPick::Irb140 => (Robot::irb140(), "the embedded IRB 140, default".to_string()),
        RobotPick::Urdf(p) => (
            Robot::from_urdf_file(p)?,
            format!("from the URDF file {}, chosen by --robot", p.display()),
        ),
        RobotPick::Catalogue { arm, written } => (
            arm.robot(),
            format!("from the catalogue, chosen by --robot {written}"),
        ),
    };
    info!("arm {} ({from})", robot.name);
    Ok(robot)
}

/// The catalogue arm `--robot NAME` names; the error says it came from
/// `--robot`.
pub fn find_arm(name: &str) -> Result<&'static AbbArm> {
    abb::find(name).map_err(|e| Error {
        message: format!("--robot {name}: {}", e.message),
        ..e
    })
}

/// Whether `--robot` names a file (its geometry "from the URDF") rather
/// than a catalogue arm.
pub fn is_file(arg: &Path) -> bool {
    matches!(robot_arg(arg), Ok(RobotArg::File(_)))
}

/// `--robot` values as arms: `[TASK=]NAME|FILE.urdf`, the task part
/// where the whole is no file's name; a catalogue name looked up here (a
/// name it lacks is a usage error before any input is read), a URDF file
/// read when its task's arm is resolved.
pub fn arm_specs(values: &[String]) -> Result<Vec<ArmSpec>> {
    values
        .iter()
        .map(|v| {
            let (task, spec) = match v.split_once('=') {
                Some((t, spec)) if !Path::new(v).exists() => (Some(t.to_string()), spec),
                _ => (None, v.as_str()),
            };
            let source = match robot_arg(Path::new(spec))? {
                RobotArg::File(p) => ArmSource::Urdf(p.to_path_buf()),
                RobotArg::Name(n) => ArmSource::Catalogue(find_arm(n)?),
            };
            Ok(ArmSpec {
                task,
                source,
                written: spec.to_string(),
            })
        })
        .collect()
}

fn sources(arm: &AbbArm) -> String {
    let mut labels: Vec<&str> = Vec::new();
    for s in &arm.sources.geometry {
        if !labels.contains(&s.label.as_str()) {
            labels.push(&s.label);
        }
    }
    labels.join(", ")
}

fn number(v: f64) -> String {
    format!("{v}")
}

/// Everything `arms` does, read from its arguments once.
pub struct ArmsCommand {
    format: Format,
}

/// The plan of `arms`' arguments (clap has refused every wrong one).
pub fn plan(args: ArmsArgs) -> Result<ArmsCommand> {
    Ok(ArmsCommand {
        format: args.format,
    })
}

pub fn run_arms(cmd: ArmsCommand) -> Result<Status> {
    let arms = abb::catalogue();
    let header = [
        "name",
        "payload_kg",
        "reach_m",
        "axis3",
        "speeds",
        "geometry_from",
    ];
    let rows: Vec<Vec<String>> = arms
        .iter()
        .map(|a| {
            vec![
                a.name.clone(),
                number(a.payload_kg),
                number(a.reach_m),
                serde_json::to_value(a.axis3)
                    .ok()
                    .and_then(|v| v.as_str().map(str::to_string))
                    .unwrap_or_default(),
                if a.max_speed_deg_s.is_some() {
                    "known"
                } else {
                    "unknown"
                }
                .to_string(),
                sources(a),
            ]
        })
        .collect();
    let text = match cmd.format {
        Format::Table => {
            use Align::{Left, Right};
            render_table(&header, &[Left, Right, Right, Left, Left, Left], &rows)
        }
        Format::Csv => render_csv(&header, &rows),
        Format::Json => rapidtherm::report::json::rows("arms", "arms", arms)?,
    };
    write_stdout(text.as_bytes())?;
    Ok(Status::Success)
}

/// `--accept-default-placement` as the library's choice.
pub fn placing(accept: bool) -> Placing {
    if accept {
        Placing::AcceptDefault
    } else {
        Placing::FromBackup
    }
}
