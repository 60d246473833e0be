use super::Status;
use rapidtherm::error::{Error, ErrorKind, Result};

#[derive(clap::Args)]
pub struct CorrectArgs {}

#[derive(clap::Args)]
pub struct DiffArgs {}

#[derive(clap::Subcommand)]
pub enum ModelCommand {
    /// Print the default model as a valid model file.
    Show,
}

fn not_yet(what: &str) -> Result<Status> {
    Err(Error::new(
        ErrorKind::Unsupported,
        format!("`{what}` is not built yet"),
    ))
}

pub fn run_correct(_args: CorrectArgs) -> Result<Status> {
    not_yet("correct")
}

pub fn run_diff(_args: DiffArgs) -> Result<Status> {
    not_yet("diff")
}

pub fn run_model(_cmd: ModelCommand) -> Result<Status> {
    not_yet("model")
}
