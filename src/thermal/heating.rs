//! What every heating model answers: the six motor temperatures at a time
//! since the cold start, and the steady state where it has one.

use super::saturating;
use crate::error::Result;

/// Motor temperatures of axes 1..6 in °C.
pub type MotorTemps = [f64; 6];

/// Anything that gives the six motor temperatures at a time (minutes since
/// the cold start). Implementations refuse times they cannot vouch for
/// (a polynomial outside its fitted window) instead of extrapolating.
pub trait HeatingProfile: Send + Sync {
    fn temps_at(&self, t_min: f64) -> Result<MotorTemps>;

    /// The thermally stable state after warm-up (`--at steady`). Only
    /// saturating models have one; the others refuse.
    fn steady(&self) -> Result<MotorTemps> {
        Err(crate::error::Error::new(
            crate::error::ErrorKind::Unsupported,
            "this heating model has no steady state (a polynomial or a recording does not saturate)",
        )
        .with_remedy(crate::error::Remedy::GiveMinute))
    }

    /// The saturating curve of each axis, where the profile is one: the
    /// only kind with a state that can be carried forward through running
    /// and stopped spans ([`super::duty`]). `None` for polynomials and recordings.
    fn curves(&self) -> Option<[saturating::SatCurve; 6]> {
        None
    }
}

/// Table 1 of the FEA paper: maximum motor temperatures, °C.
pub const TABLE1_TMAX: MotorTemps = [18.837, 21.596, 18.849, 21.665, 27.537, 30.705];
