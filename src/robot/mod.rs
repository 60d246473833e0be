//! The robot model: nominal geometry of a six-axis arm with an offset
//! shoulder and a spherical wrist (OPW parameters), forward kinematics with
//! typed frames, and the base thermal-expansion model of
//! `shared/spec/irb140.md` (link lengths scaled by link temperature).
//!
//! Joint angles are radians inside the library, degrees in files and on the
//! command line; lengths are millimetres.
//!
//! - [`Robot`] (`arm`): the robot with its model; `Robot::irb140()`, `fk`,
//!   `ik`, `ik_conf`, `conf_of`. What later code calls.
//! - `urdf`: the embedded IRB 140 URDF and the reader for other arms.
//! - `chain`: forward kinematics of any serial chain, OPW extraction.
//! - `ik`: the closed-form OPW solution, turns, limits, singularities.
//! - `conf`: robconf (confdata) and the cfx table.
//! - `frames`: tooldata / wobjdata, robtarget ↔ flange.

pub mod arm;
pub mod chain;
pub mod conf;
pub mod frames;
pub mod ik;
pub mod urdf;

pub use arm::Robot;
pub use conf::RobConf;
pub use frames::{ToolData, WobjData};
pub use ik::{Solution, Solutions};

use crate::error::{Error, Location, Result};
use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

/// Joint angles of axes 1..6 in radians, ABB sign convention.
pub type Joints = [f64; 6];

/// Motor temperatures of axes 1..6 in °C.
pub type MotorTemps = [f64; 6];

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

/// Nominal ABB IRB 140 (`shared/spec/irb140.md`).
pub const IRB140: Opw = Opw {
    c1: 352.0,
    a1: 70.0,
    c2: 360.0,
    c3: 380.0,
    c4: 65.0,
    a2: 0.0,
    b: 0.0,
};

/// ABB's axis 3 is zero with the upper arm horizontal; OPW's with it in line
/// with the lower arm: θ3 = q3 + 90°.
pub const OPW_OFFSET_Q3: f64 = std::f64::consts::FRAC_PI_2;

impl Opw {
    /// Flange (tool0) pose in the base frame for joint angles `q` (ABB
    /// convention: θ3 = q3 + 90°).
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        self.fk_theta(&[q[0], q[1], q[2] + OPW_OFFSET_Q3, q[3], q[4], q[5]])
    }
}

/// Which motors set the temperature of a link: the link temperature is the
/// mean of the listed motors' temperatures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkThermal {
    /// Linear expansion coefficient, 1/K.
    pub alpha: f64,
    /// Motor axes (1-based) whose mean temperature is the link's.
    pub motors: Vec<usize>,
}

/// The base thermal-expansion model: each link's lengths grow with
/// α·(T_link − T_ref).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThermalExpansion {
    /// Temperature at which the program's targets were taught, °C.
    pub t_ref: f64,
    /// Base link: c1 and a1.
    pub base: LinkThermal,
    /// Lower arm: c2.
    pub lower_arm: LinkThermal,
    /// Upper arm: c3 (and a2).
    pub upper_arm: LinkThermal,
    /// Wrist: c4.
    pub wrist: LinkThermal,
}

/// Aluminium alloy A380 (NADCA typical value), 1/K.
pub const ALPHA_A380: f64 = 21.8e-6;

impl Default for ThermalExpansion {
    /// The table of `irb140.md`: T_ref 7 °C, A380 everywhere.
    fn default() -> Self {
        let link = |motors: &[usize]| LinkThermal {
            alpha: ALPHA_A380,
            motors: motors.to_vec(),
        };
        ThermalExpansion {
            t_ref: 7.0,
            base: link(&[1]),
            lower_arm: link(&[2, 3]),
            upper_arm: link(&[4, 5, 6]),
            wrist: link(&[5, 6]),
        }
    }
}

impl LinkThermal {
    /// Mean temperature of this link's motors.
    pub fn temperature(&self, motors: &MotorTemps) -> f64 {
        if self.motors.is_empty() {
            return f64::NAN;
        }
        // An axis number outside 1..6 (refused by `from_toml`) gives NaN,
        // never a panic.
        self.motors
            .iter()
            .map(|&m| {
                m.checked_sub(1)
                    .and_then(|i| motors.get(i))
                    .copied()
                    .unwrap_or(f64::NAN)
            })
            .sum::<f64>()
            / self.motors.len() as f64
    }

    /// Length scale factor 1 + α·(T_link − T_ref).
    pub fn scale(&self, motors: &MotorTemps, t_ref: f64) -> f64 {
        1.0 + self.alpha * (self.temperature(motors) - t_ref)
    }
}

impl ThermalExpansion {
    /// Link temperatures (base, lower arm, upper arm, wrist) in °C.
    pub fn link_temps(&self, motors: &MotorTemps) -> [f64; 4] {
        [
            self.base.temperature(motors),
            self.lower_arm.temperature(motors),
            self.upper_arm.temperature(motors),
            self.wrist.temperature(motors),
        ]
    }

    /// Length scale factors of base, lower arm, upper arm and wrist.
    pub fn scales(&self, motors: &MotorTemps) -> [f64; 4] {
        [
            self.base.scale(motors, self.t_ref),
            self.lower_arm.scale(motors, self.t_ref),
            self.upper_arm.scale(motors, self.t_ref),
            self.wrist.scale(motors, self.t_ref),
        ]
    }

    /// A thermal model from TOML text (`file` names it in messages):
    ///
    /// ```toml
    /// t_ref = 7.0
    /// [base]
    /// alpha = 21.8e-6
    /// motors = [1]
    /// [lower_arm]
    /// ...
    /// ```
    /// with tables `base`, `lower_arm`, `upper_arm`, `wrist`.
    pub fn from_toml(file: &str, text: &str) -> Result<ThermalExpansion> {
        let th: ThermalExpansion = toml::from_str(text).map_err(|e| {
            let err = Error::input(format!("thermal model: {}", e.message()));
            match e.span() {
                Some(span) => err.at(Location::from_offset(file, text.as_bytes(), span.start)),
                None => err.with_note(format!("in {file}")),
            }
        })?;
        let bad = |msg: String| Error::input(format!("{file}: thermal model: {msg}"));
        if !th.t_ref.is_finite() {
            return Err(bad("t_ref must be a finite temperature".into()));
        }
        for (name, link) in [
            ("base", &th.base),
            ("lower_arm", &th.lower_arm),
            ("upper_arm", &th.upper_arm),
            ("wrist", &th.wrist),
        ] {
            if !link.alpha.is_finite() {
                return Err(bad(format!("{name}.alpha must be a finite number")));
            }
            if link.motors.is_empty() || link.motors.iter().any(|m| !(1..=6).contains(m)) {
                return Err(bad(format!(
                    "{name}.motors must list axis numbers 1..6 (got {:?})",
                    link.motors
                )));
            }
        }
        Ok(th)
    }

    /// The geometry of the warm arm.
    pub fn expand(&self, nominal: &Opw, motors: &MotorTemps) -> Opw {
        let [sb, sl, su, sw] = self.scales(motors);
        Opw {
            c1: nominal.c1 * sb,
            a1: nominal.a1 * sb,
            c2: nominal.c2 * sl,
            c3: nominal.c3 * su,
            c4: nominal.c4 * sw,
            a2: nominal.a2 * su,
            b: nominal.b * sb,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn expansion_at_reference_temperature_is_nominal() {
        let th = ThermalExpansion::default();
        assert_eq!(th.expand(&IRB140, &[7.0; 6]), IRB140);
        let warm = th.expand(&IRB140, &[17.0; 6]);
        assert_relative_eq!(warm.c2, 360.0 * (1.0 + 21.8e-6 * 10.0), epsilon = 1e-12);
    }
}
