//! The measurements that would tell two near-equal candidates apart, as a
//! typed result, and the one place each is put in words: the report's
//! ambiguity sentences and the JSON `separate_by` are rendered from it.

use crate::model::EffectKind;
use serde::{Serialize, Serializer};

/// What to measure to tell two effects apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Separation {
    /// A static and a thermal effect: the cold start against warm.
    ColdAndWarm,
    /// A lag against another thermal effect: the first hour and after the
    /// robot stops.
    EarlyAndAfterStop,
    /// Arm bending against a joint's drift: folded and stretched.
    FoldedAndStretched,
    /// A mount drift: poses at widely different reach and height.
    ReachAndHeight,
    /// Geometry against the instrument's frame: wide ranges of axes 2, 3.
    AxesTwoAndThree,
    /// Gravity sag: the upper arm horizontal and vertical.
    UpperArmLevel,
    /// Anything else: more poses, cold and warm.
    MorePoses,
    /// Sag against the arm's own geometry where the poses are too few for
    /// a full kinematic calibration: more poses than it takes up, and what
    /// sag would have made of the static gap held out.
    CalibrationPoses { poses: usize, sag_cv_mm: f64 },
}

impl Separation {
    /// The measurements that would tell `a` from `b`.
    pub fn of(a: EffectKind, b: EffectKind) -> Separation {
        use EffectKind::*;
        let pair = |x: EffectKind, y: EffectKind| (a == x && b == y) || (a == y && b == x);
        if a.is_thermal() != b.is_thermal() {
            Separation::ColdAndWarm
        } else if a == ThermalLag || b == ThermalLag {
            Separation::EarlyAndAfterStop
        } else if pair(ArmBending, JointOffsetDrift) {
            Separation::FoldedAndStretched
        } else if a == MountDrift || b == MountDrift {
            Separation::ReachAndHeight
        } else if pair(GeometryOffset, TrackerFrame) {
            Separation::AxesTwoAndThree
        } else if a == GravitySag || b == GravitySag {
            Separation::UpperArmLevel
        } else {
            Separation::MorePoses
        }
    }

    pub fn words(&self) -> String {
        match self {
            Separation::ColdAndWarm => "measure the same poses at the cold start (t = 0) and again warm: static effects are there from the start, thermal ones are not".into(),
            Separation::EarlyAndAfterStop => "measure densely in the first hour of the warm-up and after the robot stops: a lag trails the motor temperatures, a scaled expansion follows them".into(),
            Separation::FoldedAndStretched => "measure, at one temperature, poses with the arm folded and stretched: a bent arm turns the flange about the middle of the link, a drifting joint about the joint".into(),
            Separation::ReachAndHeight => "measure poses at widely different reach and height at the same temperature: a moving base shifts them all alike".into(),
            Separation::AxesTwoAndThree => "measure poses over a wide range of axes 2 and 3 (arm folded and stretched, high and low): frame errors move all points rigidly, length and zero errors do not".into(),
            Separation::UpperArmLevel => "measure poses with the upper arm horizontal and vertical at the same temperature: sag is largest with the arm stretched out horizontally".into(),
            Separation::MorePoses => "measure more poses spread over the joint ranges, at the cold start and warm".into(),
            Separation::CalibrationPoses { poses, sag_cv_mm } => format!(
                "measure more poses spread over the joint ranges (more numbers than a full kinematic calibration takes up: {poses} here), with the upper arm horizontal and vertical: from these, gravity-sag would take the static gap to {sag_cv_mm:.3} mm held-out, but the arm's own geometry may explain it as well"
            ),
        }
    }
}

impl Serialize for Separation {
    /// As its words: the JSON `separate_by` is the sentence the report
    /// gives.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.words())
    }
}
