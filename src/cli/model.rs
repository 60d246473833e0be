//! `model show`: the model the simulation uses, as a valid model file.

use super::correct::load_model;
use super::{write_stdout, Status};
use rapidtherm::error::Result;
use std::path::PathBuf;

#[derive(clap::Subcommand)]
pub enum ModelCommand {
    /// Print the default model as a valid model file.
    Show {
        /// Show this model file instead (checked and normalised).
        #[arg(long, value_name = "FILE.toml")]
        model: Option<PathBuf>,
    },
}

pub fn run_model(cmd: ModelCommand) -> Result<Status> {
    match cmd {
        ModelCommand::Show { model } => {
            let m = load_model(model.as_deref())?;
            write_stdout(m.to_toml()?.as_bytes())?;
            Ok(Status::Success)
        }
    }
}

/// How a saved model names the URDF it was fitted on: as given when the
/// model is written to the current folder (where a relative path keeps
/// meaning the same file), else its absolute path.
pub fn urdf_reference(urdf: &str, model_path: &std::path::Path) -> String {
    let here = model_path
        .parent()
        .is_none_or(|d| d.as_os_str().is_empty() || d == std::path::Path::new("."));
    if here || std::path::Path::new(urdf).is_absolute() {
        return urdf.to_string();
    }
    std::fs::canonicalize(urdf)
        .map(|p| p.display().to_string())
        .unwrap_or_else(|_| urdf.to_string())
}
