//! Where a move sent the robot: its end point, tool, work object and the
//! displacement then active.

use super::value::Value;
use nalgebra::Isometry3;

/// Where a move sent the robot.
#[derive(Debug, Clone)]
pub(super) struct Commanded {
    /// The robtarget or jointtarget of the move's end point.
    pub(super) target: Value,
    /// Its tooldata and wobjdata.
    pub(super) tool: Value,
    pub(super) wobj: Value,
    /// The program displacement active at the move.
    pub(super) pdisp: Isometry3<f64>,
    pub(super) eoffs: [f64; 6],
}
