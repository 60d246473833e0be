//! Robot configuration (RAPID `confdata`): which of the arm's solutions a
//! target means.
//!
//! cf1, cf4, cf6 are the quadrants of axes 1, 4 and 6, `floor(q / 90°)`.
//! cfx, for the six-axis arms with eight arm/wrist solutions (the IRB 140
//! family and every arm of the catalogue, `data/arms/`), is `4a + 2b + c`
//! (RAPID reference manual, confdata; `docs/model.md`):
//!
//! | cfx | wrist centre vs axis 1 (a) | wrist centre vs lower arm (b) | axis 5 (c) |
//! |-----|----------------------------|-------------------------------|------------|
//! | 0   | in front of                | in front of                   | positive   |
//! | 1   | in front of                | in front of                   | negative   |
//! | 2   | in front of                | behind                        | positive   |
//! | 3   | in front of                | behind                        | negative   |
//! | 4   | behind                     | in front of                   | positive   |
//! | 5   | behind                     | in front of                   | negative   |
//! | 6   | behind                     | behind                        | positive   |
//! | 7   | behind                     | behind                        | negative   |
//!
//! "In front of axis 1" is measured from axis 1 itself (not from the axis-2
//! line a1 further out: 70 mm on the IRB 140, 320 mm on the IRB 6700),
//! along the direction the arm faces after axis 1 turned. "In front of the
//! lower arm" is the forward side of the line through axes 2 and 3, the
//! lower arm itself, whatever the elbow offset a2: on the IRB 2600 (a2 =
//! −115 mm) the wrist centre crosses that line at q3 ≈ −81.8°, not at
//! −90° as on the IRB 140. That line is where the arm stretches (the elbow
//! singularity), so each of the IK's two elbow branches has one cfx. On a
//! parallel-arm robot (IRB 2400) it is the same physical lower arm: the
//! controller reading q3 against the horizontal changes the angles, not the
//! geometry. Zero (exactly on the line, or axis 5 at exactly 0) counts as
//! "in front of" / "positive".

use super::Joints;
use serde::Serialize;
use std::f64::consts::FRAC_PI_2;
use std::fmt;

/// RAPID confdata `[cf1, cf4, cf6, cfx]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
pub struct RobConf {
    pub cf1: i32,
    pub cf4: i32,
    pub cf6: i32,
    pub cfx: i32,
}

impl fmt::Display for RobConf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{},{},{},{}]", self.cf1, self.cf4, self.cf6, self.cfx)
    }
}

/// Quadrant of an angle in radians, `floor(q / 90°)`.
#[inline]
pub fn quadrant(q: f64) -> i32 {
    let x = q / FRAC_PI_2;
    // floor without the libm call (no SSE4.1 in the baseline target): the
    // truncation is exact below 2³¹, one less for negative fractions.
    if x.abs() < 2_147_483_648.0 {
        let t = x as i32;
        return if f64::from(t) > x { t - 1 } else { t };
    }
    // Saturating cast: absurd angles give absurd but finite quadrants.
    x.floor() as i32
}

/// The interval `[lo, hi)` (radians) of a quadrant.
pub fn quadrant_range(cf: i32) -> (f64, f64) {
    (cf as f64 * FRAC_PI_2, (cf as f64 + 1.0) * FRAC_PI_2)
}

/// Distance (radians) of an angle from a quadrant's interval; 0 inside.
pub fn quadrant_distance(q: f64, cf: i32) -> f64 {
    let (lo, hi) = quadrant_range(cf);
    if q < lo {
        lo - q
    } else if q >= hi {
        q - hi
    } else {
        0.0
    }
}

/// The three bits of cfx, as the arm geometry decides them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CfxBits {
    /// Wrist centre behind axis 1.
    pub behind_axis1: bool,
    /// Wrist centre behind the lower arm.
    pub behind_lower_arm: bool,
    /// Axis 5 negative.
    pub axis5_negative: bool,
}

impl CfxBits {
    pub fn cfx(self) -> i32 {
        4 * i32::from(self.behind_axis1)
            + 2 * i32::from(self.behind_lower_arm)
            + i32::from(self.axis5_negative)
    }

    pub fn from_cfx(cfx: i32) -> Option<CfxBits> {
        if !(0..=7).contains(&cfx) {
            return None;
        }
        Some(CfxBits {
            behind_axis1: cfx & 4 != 0,
            behind_lower_arm: cfx & 2 != 0,
            axis5_negative: cfx & 1 != 0,
        })
    }
}

impl RobConf {
    pub fn new(cf1: i32, cf4: i32, cf6: i32, cfx: i32) -> RobConf {
        RobConf { cf1, cf4, cf6, cfx }
    }

    /// cf1, cf4, cf6 from joint angles and cfx from its bits.
    pub fn from_parts(q: &Joints, bits: CfxBits) -> RobConf {
        RobConf {
            cf1: quadrant(q[0]),
            cf4: quadrant(q[3]),
            cf6: quadrant(q[5]),
            cfx: bits.cfx(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrants_follow_the_manual() {
        let d = f64::to_radians;
        assert_eq!(quadrant(d(0.0)), 0);
        assert_eq!(quadrant(d(89.9)), 0);
        assert_eq!(quadrant(d(90.0)), 1);
        assert_eq!(quadrant(d(-0.1)), -1);
        assert_eq!(quadrant(d(-90.0)), -1);
        assert_eq!(quadrant(d(-90.1)), -2);
        assert_eq!(quadrant(d(-180.0)), -2);
        assert_eq!(quadrant(d(390.0)), 4);
        assert!((quadrant_distance(d(95.0), 0) - d(5.0)).abs() < 1e-15);
        assert_eq!(quadrant_distance(d(45.0), 0), 0.0);
    }

    #[test]
    fn cfx_bits_round_trip() {
        for cfx in 0..8 {
            assert_eq!(CfxBits::from_cfx(cfx).map(CfxBits::cfx), Some(cfx));
        }
        assert_eq!(CfxBits::from_cfx(8), None);
        assert_eq!(CfxBits::from_cfx(-1), None);
    }
}
