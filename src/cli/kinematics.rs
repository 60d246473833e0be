//! `fk` and `ik`: the robot model by hand.
//!
//! Joint limits (the robot's URDF): `fk` computes the pose of any joint
//! values but warns on stderr for each axis outside its limits (the
//! controller would refuse the jointtarget); `ik` lists only solutions
//! within the limits and warns, for each arm branch it leaves out, which
//! axis is outside its limits, so that a missing configuration is never a
//! silent one.

use super::arms::RobotPick;
use super::messages::warning;
use super::Format;
use super::{write_stdout, Status};
use nalgebra::Isometry3;
use rapidtherm::correct::Frame;
use rapidtherm::error::{Error, Result};
use rapidtherm::model::ThermalExpansion;
use rapidtherm::report::{mm, render_csv, render_table, Align};
use rapidtherm::robot::euler::euler_zyx_deg;
use rapidtherm::robot::frames::{pose_from_rapid, pose_to_rapid};
use rapidtherm::robot::{describe_violation, LinkScales, RobConf, Solutions};
use rapidtherm::thermal::MotorTemps;
use serde_json::json;
use std::path::PathBuf;

/// Options shared by `fk` and `ik`.
#[derive(clap::Args)]
pub struct ArmArgs {
    /// Motor temperatures of axes 1..6 (°C): use the warm (expanded) arm.
    #[arg(
        long,
        value_name = "T1,..,T6",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    temps: Option<Vec<f64>>,
    /// Another arm instead of the embedded IRB 140: an ABB arm by name
    /// (`rapidtherm arms`) or any serial six-axis arm's URDF file.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    robot: Option<PathBuf>,
    /// Thermal-expansion model (TOML: t_ref, and alpha/motors per link).
    #[arg(long, value_name = "FILE.toml")]
    thermal: Option<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
}

#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct FkArgs {
    /// Joint angles of axes 1..6, degrees (ABB convention).
    #[arg(value_names = ["J1", "J2", "J3", "J4", "J5", "J6"], num_args = 6, required = true)]
    joints: Vec<f64>,
    #[command(flatten)]
    model: ArmArgs,
}

#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct IkArgs {
    /// Flange (tool0) pose in the base frame: x y z (mm) and quaternion
    /// q1 q2 q3 q4 (w x y z, normalised on input as the controller does).
    #[arg(value_names = ["X", "Y", "Z", "Q1", "Q2", "Q3", "Q4"], num_args = 7, required = true)]
    pose: Vec<f64>,
    /// Only the solution with this robconf.
    #[arg(
        long,
        value_name = "CF1,CF4,CF6,CFX",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    conf: Option<Vec<i32>>,
    #[command(flatten)]
    model: ArmArgs,
}

fn six(values: &[f64], what: &str) -> Result<[f64; 6]> {
    let arr: [f64; 6] = values
        .try_into()
        .map_err(|_| Error::usage(format!("{what}: six values needed, got {}", values.len())))?;
    if let Some(v) = arr.iter().find(|v| !v.is_finite()) {
        return Err(Error::usage(format!("{what}: {v} is not a finite number")));
    }
    Ok(arr)
}

/// The arm `fk` and `ik` compute on, read from [`ArmArgs`].
struct ArmPlan {
    robot: RobotPick,
    /// `--temps`: the warm arm's motor temperatures.
    temps: Option<MotorTemps>,
    /// `--thermal`: the expansion model's file (the default one without).
    thermal: Option<PathBuf>,
    format: Format,
}

impl ArmPlan {
    /// Every usage error of the options, before any file is read.
    fn of(args: ArmArgs) -> Result<ArmPlan> {
        let temps = args
            .temps
            .as_deref()
            .map(|t| six(t, "--temps"))
            .transpose()?;
        Ok(ArmPlan {
            robot: super::arms::robot_pick(args.robot.as_deref())?,
            temps,
            thermal: args.thermal,
            format: args.format,
        })
    }

    /// The warm arm's segment scales at `--temps`, by the `--thermal`
    /// model (the default one without).
    fn scales(&self) -> Result<Option<LinkScales>> {
        let Some(t) = &self.temps else {
            return Ok(None);
        };
        let thermal = match &self.thermal {
            Some(path) => {
                let text =
                    String::from_utf8(rapidtherm::input::read_path(path)?).map_err(|_| {
                        Error::input(format!("{}: a thermal model must be UTF-8", path.display()))
                    })?;
                ThermalExpansion::from_toml(&path.display().to_string(), &text)?
            }
            None => ThermalExpansion::default(),
        };
        Ok(Some(thermal.scales(t)))
    }
}

/// What the `fk` table's numbers are, under it.
const FK_LEGEND: &str = "frame: the flange (tool0) in the robot base frame; rx_deg, ry_deg, rz_deg are q1..q4 as RobotStudio's Euler ZYX (R = Rz·Ry·Rx)\n";

fn deg(v: f64) -> String {
    mm(v, 4)
}

/// Largest joint angle `fk` takes, degrees: beyond any arm's travel (an
/// independent axis 6 turns a few hundred times at most), so a larger
/// number is a typing or unit mistake, and its robconf (quarter turns)
/// would not fit the controller's integers.
const MAX_JOINT_DEG: f64 = 100_000.0;

/// Everything `fk` does, read from its arguments once.
pub struct FkCommand {
    /// Degrees, ABB convention.
    angles: [f64; 6],
    arm: ArmPlan,
}

/// The plan of `fk`'s arguments: every usage error is raised here,
/// before any file is read.
pub fn plan_fk(args: FkArgs) -> Result<FkCommand> {
    let angles = six(&args.joints, "joint angles")?;
    if let Some(i) = (0..6).find(|&i| angles[i].abs() > MAX_JOINT_DEG) {
        return Err(Error::usage(format!(
            "axis {} at {:e}° is no joint angle (more than {MAX_JOINT_DEG}° from zero)",
            i + 1,
            angles[i]
        )));
    }
    Ok(FkCommand {
        angles,
        arm: ArmPlan::of(args.model)?,
    })
}

pub fn run_fk(cmd: FkCommand) -> Result<Status> {
    let q = cmd.angles.map(f64::to_radians);
    let robot = super::arms::load_robot(&cmd.arm.robot)?;
    let temps = cmd.arm.temps;
    for v in robot.outside_limits(&q) {
        warning!("{}", describe_violation(&v));
    }
    let conf = robot.conf_of(&q);
    let mut rows = vec![("nominal", robot.fk(&q))];
    if let Some(s) = cmd.arm.scales()? {
        rows.push(("warm", robot.fk_scaled(&q, &s)));
    }
    let out = match cmd.arm.format {
        Format::Json => {
            let poses: Vec<_> = rows
                .iter()
                .map(|(model, pose)| {
                    let (t, r) = pose_to_rapid(pose);
                    json!({
                        "model": model,
                        "x_mm": t[0],
                        "y_mm": t[1],
                        "z_mm": t[2],
                        "q": r,
                        "euler_zyx_deg": euler_zyx_deg(&pose.rotation),
                    })
                })
                .collect();
            let v = json!({
                "joints_deg": cmd.angles,
                "temps_c": temps,
                "robconf": [conf.cf1, conf.cf4, conf.cf6, conf.cfx],
                "frame": Frame::BaseFlange.code(),
                "poses": poses,
            });
            rapidtherm::report::json::document("fk", &v)?
        }
        format => {
            let header = [
                "model", "x_mm", "y_mm", "z_mm", "q1", "q2", "q3", "q4", "robconf", "rx_deg",
                "ry_deg", "rz_deg",
            ];
            // Rows in CSV's order (new columns last: scripts read the
            // others by place); the table shows the angles beside q1..q4.
            let cells: Vec<Vec<String>> = rows
                .iter()
                .map(|(model, pose)| {
                    let (t, r) = pose_to_rapid(pose);
                    let mut row = vec![model.to_string()];
                    row.extend(t.iter().map(|v| mm(*v, 4)));
                    row.extend(r.iter().map(|v| mm(*v, 6)));
                    row.push(conf.to_string());
                    row.extend(euler_zyx_deg(&pose.rotation).map(deg));
                    row
                })
                .collect();
            if format == Format::Csv {
                render_csv(&header, &cells)
            } else {
                let order = [0, 1, 2, 3, 4, 5, 6, 7, 9, 10, 11, 8];
                let pick = |row: &[String]| order.map(|i| row[i].clone()).to_vec();
                let table_header = order.map(|i| header[i]);
                let cells: Vec<Vec<String>> = cells.iter().map(|r| pick(r)).collect();
                let mut align = vec![Align::Left];
                align.extend([Align::Right; 10]);
                align.push(Align::Left);
                render_table(&table_header, &align, &cells) + FK_LEGEND
            }
        }
    };
    write_stdout(out.as_bytes())?;
    Ok(Status::Success)
}

/// The arm branches `ik` leaves out, one warning each: which axis is
/// outside its limits in every turn.
fn warn_dropped(solutions: &Solutions) {
    for d in solutions.dropped() {
        warning!(
            "the solution with cfx {} is not listed: {}",
            d.conf.cfx,
            describe_violation(&d.violation)
        );
    }
}

/// Everything `ik` does, read from its arguments once.
pub struct IkCommand {
    /// The flange in the base frame, its quaternion normalised.
    pose: Isometry3<f64>,
    /// `--conf`: only the solution of this robconf.
    conf: Option<RobConf>,
    arm: ArmPlan,
}

/// The plan of `ik`'s arguments: every usage error is raised here,
/// before any file is read.
pub fn plan_ik(args: IkArgs) -> Result<IkCommand> {
    let [x, y, z, q1, q2, q3, q4] = <[f64; 7]>::try_from(args.pose.as_slice())
        .map_err(|_| Error::usage("pose: x y z q1 q2 q3 q4 needed"))?;
    let pose = pose_from_rapid([x, y, z], [q1, q2, q3, q4])?;
    let conf = match &args.conf {
        Some(c) => {
            let [cf1, cf4, cf6, cfx] = <[i32; 4]>::try_from(c.as_slice())
                .map_err(|_| Error::usage("--conf: four integers cf1,cf4,cf6,cfx needed"))?;
            Some(RobConf::new(cf1, cf4, cf6, cfx))
        }
        None => None,
    };
    Ok(IkCommand {
        pose,
        conf,
        arm: ArmPlan::of(args.model)?,
    })
}

pub fn run_ik(cmd: IkCommand) -> Result<Status> {
    let pose = cmd.pose;
    let robot = super::arms::load_robot(&cmd.arm.robot)?;
    let scales = cmd.arm.scales()?;
    let solutions: Vec<([f64; 6], RobConf)> = match &cmd.conf {
        Some(conf) => {
            let q = match &scales {
                Some(s) => robot.ik_conf_scaled(&pose, conf, s)?,
                None => robot.ik_conf(&pose, conf)?,
            };
            vec![(q, robot.conf_of(&q))]
        }
        None => {
            let all = match &scales {
                Some(s) => robot.ik_scaled(&pose, s)?,
                None => robot.ik(&pose)?,
            };
            warn_dropped(&all);
            all.iter().map(|s| (s.q, s.conf)).collect()
        }
    };
    let out = match cmd.arm.format {
        Format::Json => {
            let list: Vec<_> = solutions
                .iter()
                .map(|(q, c)| {
                    json!({
                        "joints_deg": q.map(|v| v.to_degrees()),
                        "robconf": [c.cf1, c.cf4, c.cf6, c.cfx],
                    })
                })
                .collect();
            let (t, r) = pose_to_rapid(&pose);
            let asked = json!({
                "frame": Frame::BaseFlange.code(),
                "x_mm": t[0],
                "y_mm": t[1],
                "z_mm": t[2],
                "q": r,
                "euler_zyx_deg": euler_zyx_deg(&pose.rotation),
            });
            rapidtherm::report::json::document("ik", &json!({ "pose": asked, "solutions": list }))?
        }
        format => {
            let header = ["j1", "j2", "j3", "j4", "j5", "j6", "robconf"];
            let table_header = [
                "j1_deg", "j2_deg", "j3_deg", "j4_deg", "j5_deg", "j6_deg", "robconf",
            ];
            let cells: Vec<Vec<String>> = solutions
                .iter()
                .map(|(q, c)| {
                    let mut row: Vec<String> = q.iter().map(|v| deg(v.to_degrees())).collect();
                    row.push(c.to_string());
                    row
                })
                .collect();
            if format == Format::Csv {
                render_csv(&header, &cells)
            } else {
                let mut align = vec![Align::Right; 6];
                align.push(Align::Left);
                let [rx, ry, rz] = euler_zyx_deg(&pose.rotation).map(deg);
                render_table(&table_header, &align, &cells)
                    + &format!("pose: the flange (tool0) in the robot base frame, rx_deg {rx}, ry_deg {ry}, rz_deg {rz} (RobotStudio's Euler ZYX of q1..q4)\n")
            }
        }
    };
    write_stdout(out.as_bytes())?;
    Ok(Status::Success)
}
