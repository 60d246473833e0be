use super::Status;
use rapidtherm::error::{Error, ErrorKind, Result};

#[derive(clap::Args)]
pub struct TargetsArgs {}

pub fn run(_args: TargetsArgs) -> Result<Status> {
    Err(Error::new(
        ErrorKind::Unsupported,
        "`targets` is not built yet",
    ))
}
