//! The robot's geometry: a six-axis serial arm (any URDF chain; closed-form
//! IK where it has an offset shoulder and a spherical wrist, the OPW form,
//! numeric IK elsewhere),
//! robconf, and the tool and work-object frames RAPID targets are written
//! in. A warm arm is the same arm with its segments scaled
//! ([`LinkScales`]); what scales them is the `model`'s business.
//!
//! Owns geometry only. May import the shared `error` and `csv_table`;
//! never `thermal`, `model` or anything above.
//!
//! Joint angles are radians inside the library, degrees in files and on the
//! command line; lengths are millimetres.
//!
//! - [`Robot`] (`arm`): the robot with its model; `Robot::irb140()`, `fk`,
//!   `ik`, `ik_conf`, `conf_of`. What later code calls.
//! - `urdf`: the embedded IRB 140 URDF (`data/irb140/irb140.urdf`) and the
//!   reader for other arms; [`irb140_opw`] is its nominal OPW geometry.
//! - `abb`: ABB's arms by name (`data/arms/*.toml`), `Robot::abb`.
//! - `chain`: forward kinematics of any serial chain, the chain of OPW
//!   lengths, OPW extraction.
//! - `ik`: the closed-form OPW solution, turns, limits, singularities.
//! - `ik_conf`: IK for one robconf, the requested branch computed directly
//!   (the enumeration of `ik` as its fallback and reference).
//! - `ik_chain`: numeric IK (and robconf) for the arms without the OPW
//!   form.
//! - `conf`: robconf (confdata) and the cfx table.
//! - `frames`: tooldata / wobjdata, robtarget ↔ flange.
//! - `euler`: a rotation as RobotStudio's Euler ZYX angles (RX, RY, RZ).

pub mod abb;
pub mod arm;
pub mod chain;
pub mod conf;
pub mod euler;
pub mod frames;
pub mod ik;
mod ik_chain;
mod ik_conf;
mod lanes;
pub mod urdf;
pub mod urdf_scan;

pub use arm::{degrees_text, describe_violation, irb140_opw, Robot};
pub use conf::RobConf;
pub use frames::{ToolData, WobjData};
pub use ik::{Dropped, Solution, Solutions, Violation};

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

/// Joint angles of axes 1..6 in radians, ABB sign convention.
pub type Joints = [f64; 6];

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
