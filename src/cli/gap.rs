//! `gap`: the RMS and max gap of a model on measured data, and a gate on
//! it. Its arguments are read into a [`GapCommand`] (every usage error
//! raised there) before any input is read; the run reads the plan alone.

use super::diagnose::{load_model, refused, registration_words, robot_choice, Messages};
use super::messages::outcome;
use super::Format;
use super::{write_stdout, Status};
use rapidtherm::diagnose::job;
use rapidtherm::diagnose::plan::RobotChoice;
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{self, GapStats, Prepared};
use rapidtherm::error::{Error, Result};
use rapidtherm::report::render_csv;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct GapArgs {
    /// Measurements CSV (`-`: standard input).
    data: PathBuf,
    #[arg(long)]
    model: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// First fit the rigid transform from the instrument's frame to the robot base.
    #[arg(long)]
    register: bool,
    /// The arm, by name (`rapidtherm arms`) or URDF file.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    robot: Option<PathBuf>,
    /// Exit with status 1 when the RMS gap exceeds this many mm (a gate for scripts).
    #[arg(long, value_name = "MM")]
    fail_above: Option<f64>,
    /// Data without temperature columns: assume the session starts cold at its first row and follows this warm-up (`irb140`); without it every row is held at the reference temperature, as the diagnosis holds them
    #[arg(long, value_name = "PROFILE", value_parser = super::diagnose_args::cold_start)]
    assume_cold_start: Option<ColdStart>,
}

/// Everything `gap` does, read from its arguments once.
pub struct GapCommand {
    data: PathBuf,
    model: Option<PathBuf>,
    format: Format,
    register: bool,
    robot: Option<RobotChoice>,
    /// `--robot` as given, for the words of a refusal.
    robot_arg: Option<PathBuf>,
    /// The gate: the largest RMS gap (mm) that passes.
    fail_above: Option<f64>,
    assume_cold_start: Option<ColdStart>,
}

/// The plan of `gap`'s arguments: every usage error is raised here,
/// before any file is read.
pub fn plan(args: GapArgs) -> Result<GapCommand> {
    if let Some(limit) = args.fail_above {
        if !(limit.is_finite() && limit >= 0.0) {
            return Err(Error::usage("--fail-above must be a number of mm >= 0"));
        }
    }
    Ok(GapCommand {
        robot: robot_choice(&args.robot)?,
        data: args.data,
        model: args.model,
        format: args.format,
        register: args.register,
        robot_arg: args.robot,
        fail_above: args.fail_above,
        assume_cold_start: args.assume_cold_start,
    })
}

pub fn run(cmd: GapCommand) -> Result<Status> {
    let model = load_model(&cmd.model)?;
    let setup = job::setup(
        cmd.robot.as_ref(),
        &model,
        cmd.model.is_some(),
        &mut Messages,
    )?;
    let prepared = job::gap_of(
        &cmd.data,
        &model,
        &setup,
        cmd.register,
        cmd.assume_cold_start,
        &mut Messages,
    )
    .map_err(|r| refused(r, cmd.robot_arg.as_deref()))?;
    let g = diagnose::gap(&prepared);
    write_stdout(render(cmd.format, &g, &prepared).as_bytes())?;
    match cmd.fail_above {
        // A gap that is not a number never passes the gate: nothing was
        // shown to be within it.
        Some(limit) if g.rms_mm.is_nan() => {
            outcome!("gap is not a number: it is not within {limit} mm");
            Ok(Status::Changes)
        }
        Some(limit) if g.rms_mm > limit => {
            outcome!("gap {:.4} mm RMS is above {limit} mm", g.rms_mm);
            Ok(Status::Changes)
        }
        _ => Ok(Status::Success),
    }
}

/// The gap in `format`.
fn render(format: Format, g: &GapStats, prepared: &Prepared) -> String {
    match format {
        Format::Json => {
            let mut v = serde_json::json!({"rms_mm": g.rms_mm, "max_mm": g.max_mm, "n": g.n});
            if let Some((rms, max)) = diagnose::orientation_gap(prepared) {
                v["rot_rms_mrad"] = rms.into();
                v["rot_max_mrad"] = max.into();
            }
            if let Some(r) = &prepared.registration {
                v["registration"] = serde_json::to_value(r).unwrap_or_default();
            }
            rapidtherm::report::json::document("gap", &v).unwrap_or_default()
        }
        Format::Csv => render_csv(
            &["rms_mm", "max_mm", "n"],
            &[vec![
                format!("{:.5}", g.rms_mm),
                format!("{:.5}", g.max_mm),
                g.n.to_string(),
            ]],
        ),
        Format::Table => {
            let mut s = String::new();
            if let Some(r) = &prepared.registration {
                s.push_str(&registration_words(r));
            }
            s.push_str(&format!(
                "gap: {:.4} mm RMS, {:.4} mm max over {} rows\n",
                g.rms_mm, g.max_mm, g.n
            ));
            if let Some((rms, max)) = diagnose::orientation_gap(prepared) {
                s.push_str(&format!(
                    "orientation gap: {rms:.4} mrad RMS, {max:.4} mrad max\n"
                ));
            }
            s
        }
    }
}
