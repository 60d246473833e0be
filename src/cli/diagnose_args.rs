//! `diagnose`'s arguments, and the table of fitted parameters both
//! diagnoses print (the OPW one in `diagnose`, the general chain's in
//! `diagnose_chain`): shared below both, so that neither imports the
//! other back.

use super::Format;
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::report::{render_table, Align};
use std::path::PathBuf;

pub(super) fn cold_start(s: &str) -> Result<ColdStart, String> {
    ColdStart::from_name(s).map_err(|e| e.message)
}

#[derive(clap::Args)]
pub struct DiagnoseArgs {
    /// Measurements CSV (`-`: standard input).
    pub data: PathBuf,
    /// The current model (default: the embedded default model that
    /// `rapidtherm model show` prints: the nominal IRB 140, its link
    /// expansion calibrated to the papers' FEA drift; docs/model.md).
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Tracker noise, mm per axis (default: estimated from repeated poses;
    /// without them not measured, and each test uses its model's residual).
    #[arg(long)]
    pub noise: Option<f64>,
    /// Data without temperature columns: assume the session starts cold at
    /// its first row and follows this warm-up (`irb140`); without it no
    /// thermal effect is a candidate.
    #[arg(long, value_name = "PROFILE", value_parser = cold_start)]
    pub assume_cold_start: Option<ColdStart>,
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Write the model with the diagnosed effects added.
    #[arg(long, value_name = "FILE.toml")]
    pub save_model: Option<PathBuf>,
    /// Write SVG plots of the gap before and after into this directory.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Replace a file in the --plot folder even where it is not an SVG
    /// picture (docs/limits.md); without it such a file is refused.
    #[arg(long)]
    pub force: bool,
    /// First fit the rigid transform from the instrument's frame to the robot base.
    #[arg(long)]
    pub register: bool,
    /// The arm, by name (`rapidtherm arms`) or URDF file.
    #[arg(long, value_name = "NAME|FILE.urdf")]
    pub robot: Option<PathBuf>,
    /// Diagnose as a general serial chain (geometric calibration of every
    /// joint origin), even when the arm has the OPW form.
    #[arg(long)]
    pub chain: bool,
    /// The URDF link the instrument measured (a reflector), hung on the
    /// flange by fixed joints; its offset is fitted (default: tool0).
    #[arg(long, value_name = "LINK")]
    pub point: Option<String>,
    /// A second measurements file in the same instrument frame, held out:
    /// the geometry fitted on DATA is judged on it.
    #[arg(long, value_name = "FILE.csv")]
    pub holdout: Option<PathBuf>,
}

pub(crate) fn parameter_table<'a>(
    params: impl Iterator<Item = (&'a str, f64, Option<f64>, &'a str)>,
) -> String {
    let rows: Vec<Vec<String>> = params
        .map(|(name, value, stderr, unit)| {
            vec![
                name.to_string(),
                format!("{value:.4}"),
                stderr
                    .map(|e| format!("{e:.4}"))
                    .unwrap_or_else(|| "not identifiable".into()),
                unit.to_string(),
            ]
        })
        .collect();
    render_table(
        &["parameter", "value", "± stderr", "unit"],
        &[Align::Left, Align::Right, Align::Right, Align::Left],
        &rows,
    )
}
