use super::Status;
use rapidtherm::error::{Error, ErrorKind, Result};

#[derive(clap::Args)]
pub struct SimulateArgs {}

#[derive(clap::Args)]
pub struct DiagnoseArgs {}

#[derive(clap::Args)]
pub struct GapArgs {}

fn not_yet(what: &str) -> Result<Status> {
    Err(Error::new(
        ErrorKind::Unsupported,
        format!("`{what}` is not built yet"),
    ))
}

pub fn run_simulate(_args: SimulateArgs) -> Result<Status> {
    not_yet("simulate")
}

pub fn run_diagnose(_args: DiagnoseArgs) -> Result<Status> {
    not_yet("diagnose")
}

pub fn run_gap(_args: GapArgs) -> Result<Status> {
    not_yet("gap")
}
