//! The OPW parameterisation of an arm with an offset shoulder and a
//! spherical wrist (the IRB 140's form), its lengths scaled segment by
//! segment for a warm arm.

use super::Joints;
use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

/// Scale factors of the arm's four segments: base (c1, a1, b), lower arm
/// (c2), upper arm (c3, a2) and wrist (c4). 1 is the nominal length.
pub type LinkScales = [f64; 4];

/// The five lengths that expand (and the two offsets that the IRB 140 has
/// at zero) in the OPW parameterisation, in mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Opw {
    pub c1: f64,
    pub a1: f64,
    pub c2: f64,
    pub c3: f64,
    pub c4: f64,
    pub a2: f64,
    pub b: f64,
}

/// ABB's axis 3 is zero with the upper arm horizontal; OPW's with it in line
/// with the lower arm: θ3 = q3 + 90°.
pub const OPW_OFFSET_Q3: f64 = std::f64::consts::FRAC_PI_2;

impl Opw {
    /// Flange (tool0) pose in the base frame for joint angles `q` (ABB
    /// convention: θ3 = q3 + 90°).
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        self.fk_theta(&[q[0], q[1], q[2] + OPW_OFFSET_Q3, q[3], q[4], q[5]])
    }

    /// The same arm with each segment's lengths scaled.
    pub fn scaled(&self, s: &LinkScales) -> Opw {
        let [sb, sl, su, sw] = *s;
        Opw {
            c1: self.c1 * sb,
            a1: self.a1 * sb,
            c2: self.c2 * sl,
            c3: self.c3 * su,
            c4: self.c4 * sw,
            a2: self.a2 * su,
            b: self.b * sb,
        }
    }
}
