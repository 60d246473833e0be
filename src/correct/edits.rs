//! The text a correction writes: new numbers spliced into the program's
//! original bytes, each formatted like the literal it replaces.

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
