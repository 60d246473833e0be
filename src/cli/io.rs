//! Reading the inputs a command names (`-`: standard input) and writing
//! data to standard output.

use rapidtherm::error::{Error, Result};
use std::io::Write;
use std::path::Path;

/// Read a whole input file, or standard input for `-`. Returns the name to
/// use in messages and the bytes.
pub fn read_input(path: &Path) -> Result<(String, Vec<u8>)> {
    if path == Path::new("-") {
        Ok(("<stdin>".to_string(), rapidtherm::input::read_stdin()?))
    } else {
        let bytes = rapidtherm::input::read_path(path)?;
        Ok((path.display().to_string(), bytes))
    }
}

/// Input files as read: the name used in messages and the bytes.
pub use rapidtherm::correct::job::Inputs;

/// Write data to standard output (a closed pipe is not an error worth a
/// panic: the reader has what it wanted).
pub fn write_stdout(bytes: &[u8]) -> Result<()> {
    let mut out = std::io::stdout().lock();
    stdout_written(out.write_all(bytes).and_then(|_| out.flush()))
}

/// What writing to standard output came to, as [`write_stdout`] takes it.
pub fn stdout_written(r: std::io::Result<()>) -> Result<()> {
    match r {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Error::io(Path::new("<stdout>"), &e)),
    }
}
