//! Timing one move: RAPID speeddata, and how long a linear or joint move
//! takes at it.

use crate::robot::Joints;
use nalgebra::Isometry3;

/// RAPID `speeddata`: TCP speed (mm/s), reorientation speed (°/s), linear
/// and rotational external-axis speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveSpeed {
    pub v_tcp: f64,
    pub v_ori: f64,
    pub v_leax: f64,
    pub v_reax: f64,
}

/// The predefined speeddata of the RAPID reference manual: `v5` … `v7000`
/// are `[n, 500, 5000, 1000]`; `vmax` is the robot's maximum TCP speed,
/// taken as 5000 mm/s for this family.
pub fn predefined_speed(name: &str) -> Option<MoveSpeed> {
    crate::rapid::builtins::predefined_speed(name).map(|s| MoveSpeed {
        v_tcp: s.v_tcp,
        v_ori: s.v_ori,
        v_leax: s.v_leax,
        v_reax: s.v_reax,
    })
}

/// Seconds for a linear move (MoveL, MoveC approximated by its chord
/// unless the caller passes the arc length): the slower of the TCP path at
/// `v_tcp` and the reorientation at `v_ori`, as the controller does.
/// Acceleration phases are ignored: at the minute scale of a warm-up they
/// shift times by well under a second per move.
pub fn linear_move_seconds(from: &Isometry3<f64>, to: &Isometry3<f64>, speed: &MoveSpeed) -> f64 {
    let dist = (to.translation.vector - from.translation.vector).norm();
    let angle = from.rotation.angle_to(&to.rotation).to_degrees();
    seconds_for(dist, speed.v_tcp).max(seconds_for(angle, speed.v_ori))
}

/// Seconds for a joint move (MoveJ, MoveAbsJ): the axis that needs longest
/// at its maximum speed sets the time, and the TCP may not exceed `v_tcp`
/// along the straight line between the two poses (a lower bound of its
/// true path).
pub fn joint_move_seconds(
    from: &Joints,
    to: &Joints,
    max_speed_deg_s: &[f64; 6],
    tcp_distance_mm: f64,
    speed: &MoveSpeed,
) -> f64 {
    let axes = (0..6)
        .map(|i| seconds_for((to[i] - from[i]).abs().to_degrees(), max_speed_deg_s[i]))
        .fold(0.0, f64::max);
    axes.max(seconds_for(tcp_distance_mm, speed.v_tcp))
}

pub(super) fn seconds_for(amount: f64, rate: f64) -> f64 {
    if rate > 0.0 {
        amount / rate
    } else {
        0.0
    }
}
