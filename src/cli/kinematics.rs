use super::Status;
use rapidtherm::error::{Error, ErrorKind, Result};

#[derive(clap::Args)]
pub struct FkArgs {}

#[derive(clap::Args)]
pub struct IkArgs {}

pub fn run_fk(_args: FkArgs) -> Result<Status> {
    Err(Error::new(ErrorKind::Unsupported, "`fk` is not built yet"))
}

pub fn run_ik(_args: IkArgs) -> Result<Status> {
    Err(Error::new(ErrorKind::Unsupported, "`ik` is not built yet"))
}
