//! The targets of `cargo bench --bench correct`, a CAM program's: a
//! spindle 150 mm long pointing straight down over a 80 × 300 mm field,
//! cf1 and cf6 by the side of axis 1. Axis 4 lands a rounding error either
//! side of 0, in or just outside the written cf4 = 0.

use nalgebra::{Isometry3, Quaternion, UnitQuaternion, Vector3};
use rapidtherm::robot::frames::flange_of_target;
use rapidtherm::robot::{RobConf, ToolFrame, WobjFrames};

/// 2,000 flange poses of those targets, each with its written robconf.
pub fn flanges() -> Vec<(Isometry3<f64>, RobConf)> {
    let tool = ToolFrame {
        tframe: Isometry3::translation(0.0, 0.0, 150.0),
        ..ToolFrame::tool0()
    };
    let wobj = WobjFrames::wobj0();
    (0..2000)
        .map(|i| {
            let (u, v) = (f64::from(i % 50) / 50.0, f64::from(i / 50) / 40.0);
            let y = -150.0 + 300.0 * v;
            let target = Isometry3::from_parts(
                Vector3::new(420.0 + 80.0 * u, y, 250.0 + 20.0 * (u * 7.0).sin()).into(),
                UnitQuaternion::from_quaternion(Quaternion::new(0.0, 0.0, 1.0, 0.0)),
            );
            let cf = if y >= 0.0 { 0 } else { -1 };
            let flange = flange_of_target(&target, &tool, &wobj).expect("a plain tool");
            (flange, RobConf::new(cf, 0, cf, 0))
        })
        .collect()
}
