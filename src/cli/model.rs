//! `model show`: the model the simulation uses, as a valid model file.

use super::correct::model_source;
use super::{write_stdout, Status};
use rapidtherm::correct::job;
use rapidtherm::correct::plan::ModelSource;
use rapidtherm::error::Result;
use std::path::PathBuf;

#[derive(clap::Subcommand)]
pub enum ModelArgs {
    /// Print the default model as a valid model file.
    Show {
        /// Show this model file instead (checked and normalised).
        #[arg(long, value_name = "FILE.toml")]
        model: Option<PathBuf>,
    },
}

/// Everything `model` does, read from its arguments once.
pub enum ModelCommand {
    /// `show`: the model, as a model file.
    Show(ModelSource),
}

/// The plan of `model`'s arguments (clap has refused every wrong one).
pub fn plan(args: ModelArgs) -> Result<ModelCommand> {
    Ok(match args {
        ModelArgs::Show { model } => ModelCommand::Show(model_source(model.as_deref())),
    })
}

pub fn run(cmd: ModelCommand) -> Result<Status> {
    match cmd {
        ModelCommand::Show(source) => {
            let m = job::load_model(&source)?;
            write_stdout(m.to_toml()?.as_bytes())?;
            Ok(Status::Success)
        }
    }
}
