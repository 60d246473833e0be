//! The base thermal-expansion model of `docs/model.md`: each link's
//! lengths grow with α·(T_link − T_ref), the link temperature being the
//! mean of the motors that heat it.

use crate::error::{Error, Location, Result};
use crate::robot::{LinkScales, Opw};
use crate::thermal::MotorTemps;
use serde::{Deserialize, Serialize};

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
    /// K0: one factor on every link's expansion, L(T) = L·(1 + K0·α·ΔT).
    /// The castings run cooler than the motor surfaces whose temperatures
    /// drive the model; the embedded default calibrates K0 to the FEA
    /// (`docs/model.md`, "Calibrated default"). 1 (the base model
    /// of docs/model.md, unscaled) when a file does not say.
    #[serde(default = "unscaled")]
    pub k0: f64,
    /// Base link: c1 and a1.
    pub base: LinkThermal,
    /// Lower arm: c2.
    pub lower_arm: LinkThermal,
    /// Upper arm: c3 (and a2).
    pub upper_arm: LinkThermal,
    /// Wrist: c4.
    pub wrist: LinkThermal,
}

fn unscaled() -> f64 {
    1.0
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

    /// Length scale factor 1 + k0·α·(T_link − T_ref).
    pub fn scale(&self, motors: &MotorTemps, t_ref: f64, k0: f64) -> f64 {
        1.0 + k0 * self.alpha * (self.temperature(motors) - t_ref)
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
    pub fn scales(&self, motors: &MotorTemps) -> LinkScales {
        [
            self.base.scale(motors, self.t_ref, self.k0),
            self.lower_arm.scale(motors, self.t_ref, self.k0),
            self.upper_arm.scale(motors, self.t_ref, self.k0),
            self.wrist.scale(motors, self.t_ref, self.k0),
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
        if !(th.k0.is_finite() && th.k0 >= 0.0) {
            return Err(bad("k0 must be a finite factor ≥ 0".into()));
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
        nominal.scaled(&self.scales(motors))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::irb140_opw;
    use approx::assert_relative_eq;

    #[test]
    fn expansion_at_reference_temperature_is_nominal() {
        let th = ThermalExpansion::default();
        let nominal = irb140_opw();
        assert_eq!(th.expand(&nominal, &[7.0; 6]), nominal);
        let warm = th.expand(&nominal, &[17.0; 6]);
        assert_relative_eq!(
            warm.c2,
            360.0 * (1.0 + 0.33699 * 21.8e-6 * 10.0),
            epsilon = 1e-12
        );
    }
}
