//! The instrument and test set-up the diagnosis assumes when the data
//! cannot tell: tracker noise, probe orientation noise, the ISO 9283 cube.
//! The numbers and their sources live in `data/instrument.toml`, embedded
//! in the binary and parsed once.

use crate::error::{Error, Result};
use serde::Deserialize;
use std::sync::OnceLock;

const INSTRUMENT_TOML: &str = include_str!("../../data/instrument.toml");

/// The contents of `data/instrument.toml`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Instrument {
    pub position: PositionNoise,
    pub orientation: OrientationNoise,
    pub iso_cube: IsoCubeShape,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionNoise {
    /// Tracker position noise, mm per axis.
    pub noise_mm: f64,
    /// Floor of an estimated noise level, mm per axis.
    pub min_noise_mm: f64,
    /// Largest noise of an instrument, mm per axis.
    pub max_noise_mm: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrientationNoise {
    /// Probe orientation noise at `position.noise_mm`, mrad per axis.
    pub noise_mrad: f64,
}

/// The ISO 9283 cube as fractions of an arm's wrist reach.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IsoCubeShape {
    pub forward: f64,
    pub above_shoulder: f64,
    pub side: f64,
    /// Test points' distance from the corners, fraction of the diagonal.
    pub corner_inset: f64,
}

fn parse(text: &str) -> Result<Instrument, toml::de::Error> {
    toml::from_str(text)
}

/// The embedded instrument data, parsed on first use. It is part of the
/// binary and a unit test parses it, so the error is a build defect; it is
/// still an error rather than a panic because the library never aborts.
pub fn instrument() -> Result<&'static Instrument> {
    static INSTRUMENT: OnceLock<std::result::Result<Instrument, String>> = OnceLock::new();
    INSTRUMENT
        .get_or_init(|| parse(INSTRUMENT_TOML).map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|e| Error::input(format!("data/instrument.toml (embedded): {e}")))
}

/// Position noise of a laser tracker, mm per axis, when the data cannot
/// tell.
pub fn default_noise_mm() -> Result<f64> {
    Ok(instrument()?.position.noise_mm)
}

/// Orientation noise of a 6-DOF tracker probe, mrad per axis, at the
/// default position noise.
pub fn orientation_noise_mrad() -> Result<f64> {
    Ok(instrument()?.orientation.noise_mrad)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instrument_file_parses_with_sensible_numbers() {
        let i = parse(INSTRUMENT_TOML).unwrap();
        assert!(i.position.noise_mm > 0.0 && i.position.noise_mm < 1.0);
        assert!(i.position.min_noise_mm > 0.0 && i.position.min_noise_mm < i.position.noise_mm);
        assert!(i.orientation.noise_mrad > 0.0);
        let c = &i.iso_cube;
        assert!(c.forward > 0.0 && c.side > 0.0 && c.corner_inset > 0.0 && c.corner_inset < 0.5);
    }
}
