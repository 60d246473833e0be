//! Motor temperatures over time: heating models fitted to recordings and the
//! embedded default profile of the IRB 140 at 60 % speed.

use crate::error::Result;
use crate::robot::MotorTemps;

/// Anything that gives the six motor temperatures at a time (minutes since
/// the cold start). Implementations refuse times they cannot vouch for
/// (a polynomial outside its fitted window) instead of extrapolating.
pub trait HeatingProfile: Send + Sync {
    fn temps_at(&self, t_min: f64) -> Result<MotorTemps>;
}

/// Table 1 of the FEA paper: maximum motor temperatures, °C.
pub const TABLE1_TMAX: MotorTemps = [18.837, 21.596, 18.849, 21.665, 27.537, 30.705];

/// First-order heating per axis: T(t) = T0 + ΔT·(1 − e^(−t/τ)).
#[derive(Debug, Clone, PartialEq)]
pub struct FirstOrderProfile {
    pub t0: MotorTemps,
    pub delta: MotorTemps,
    pub tau_min: MotorTemps,
}

impl HeatingProfile for FirstOrderProfile {
    fn temps_at(&self, t_min: f64) -> Result<MotorTemps> {
        let t = t_min.max(0.0);
        Ok(std::array::from_fn(|i| {
            self.t0[i] + self.delta[i] * (1.0 - (-t / self.tau_min[i]).exp())
        }))
    }
}

/// The profile used when the user gives no recording.
// Provisional: a first-order curve from 7 °C that reaches 99 % of the
// table-1 maxima at 180 min; replaced by the fit to the reference sample.
pub fn default_profile() -> FirstOrderProfile {
    let t0 = [7.0; 6];
    FirstOrderProfile {
        t0,
        delta: std::array::from_fn(|i| TABLE1_TMAX[i] - t0[i]),
        tau_min: [180.0 / 4.6; 6],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_profile_starts_at_reference_and_saturates() {
        let p = default_profile();
        assert_eq!(p.temps_at(0.0).unwrap(), [7.0; 6]);
        let late = p.temps_at(10_000.0).unwrap();
        for i in 0..6 {
            assert!((late[i] - TABLE1_TMAX[i]).abs() < 1e-9);
        }
    }
}
