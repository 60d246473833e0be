//! The text a correction writes: new numbers spliced into the program's
//! original bytes, each formatted like the literal it replaces.

use super::{marker, Correction, Options};
use crate::error::Result;
use crate::rapid::rewrite::Edit;
use crate::rapid::Program;
use nalgebra::UnitQuaternion;

/// Orientation is rewritten only when it turns by more than this (rad): a
/// quaternion written with six decimals resolves about 2e-6 rad.
pub const ORIENTATION_CHANGE_RAD: f64 = 1e-6;

/// The quaternion of `rot` with the sign of the written one (q and −q are
/// the same rotation; keep what the user wrote).
pub(super) fn quaternion_like(rot: &UnitQuaternion<f64>, written: &[f64; 4]) -> [f64; 4] {
    let q = rot.quaternion();
    let dot = q.w * written[0] + q.i * written[1] + q.j * written[2] + q.k * written[3];
    let s = if dot < 0.0 { -1.0 } else { 1.0 };
    [s * q.w, s * q.i, s * q.j, s * q.k]
}

/// The new bytes of every file of the program, in its file order; a file
/// that changes gets the marker of the run under its module header.
/// `more` are edits beyond the corrections' numbers (a split's copies
/// and renamed arguments), by file.
pub(super) fn write_files(
    program: &Program,
    corrections: &[Correction],
    more: &[(usize, Edit)],
    basis: &str,
    options: &Options,
) -> Result<Vec<Vec<u8>>> {
    (0..program.files.len())
        .map(|f| {
            let mut edits: Vec<Edit> = corrections
                .iter()
                .filter(|c| c.file_index == f)
                .flat_map(|c| c.edits.iter().cloned())
                .chain(
                    more.iter()
                        .filter(|(file, _)| *file == f)
                        .map(|(_, e)| e.clone()),
                )
                .collect();
            if !edits.is_empty() {
                let m = marker::for_run(
                    basis,
                    &options.model_label,
                    options.split_shared,
                    program.source(f),
                );
                edits.extend(marker::insert(program, f, &m));
            }
            program.apply_edits(f, &edits)
        })
        .collect()
}
