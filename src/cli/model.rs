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
