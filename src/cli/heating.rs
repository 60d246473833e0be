use super::Status;
use rapidtherm::error::{Error, ErrorKind, Result};

#[derive(clap::Subcommand)]
pub enum HeatingCommand {
    /// Fit heating models to a recording.
    Fit {},
}

pub fn run(_cmd: HeatingCommand) -> Result<Status> {
    Err(Error::new(
        ErrorKind::Unsupported,
        "`heating` is not built yet",
    ))
}
