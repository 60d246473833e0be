//! Whether a number can be a temperature of a robot's motor or its room
//! (`data/thermal/plausible.toml`): every temperature the tool reads or is
//! given passes here, so that a file in kelvin, a typo or a value below
//! absolute zero is refused where it stands instead of becoming a
//! correction.

use crate::error::{Error, Location, Result};
use serde::Deserialize;
use std::sync::OnceLock;

/// The bounds (`data/thermal/plausible.toml`).
pub const PLAUSIBLE_TOML: &str = include_str!("../../data/thermal/plausible.toml");

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plausible {
    pub lowest_c: f64,
    pub highest_c: f64,
    pub kelvin_low: f64,
    pub kelvin_high: f64,
    pub room_lowest_c: f64,
    pub room_highest_c: f64,
}

/// The embedded bounds, parsed once.
pub fn plausible() -> Plausible {
    static BOUNDS: OnceLock<Plausible> = OnceLock::new();
    *BOUNDS.get_or_init(|| {
        toml::from_str(PLAUSIBLE_TOML).expect("the embedded data/thermal/plausible.toml is valid")
    })
}

/// Absolute zero, °C.
pub const ABSOLUTE_ZERO_C: f64 = -273.15;

/// A number as a message shows it: `1e300`, not three hundred digits.
fn shown(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Why `value` (°C) cannot be a robot's temperature, or `None` when it can.
pub fn implausible(value: f64) -> Option<String> {
    let p = plausible();
    let value_c = value;
    let value = shown(value);
    if !value_c.is_finite() {
        return Some(format!("{value} is not a finite temperature"));
    }
    if value_c < ABSOLUTE_ZERO_C {
        return Some(format!("{value} °C is below absolute zero"));
    }
    if value_c < p.lowest_c || value_c > p.highest_c {
        let mut why = format!(
            "{value} °C is not a plausible robot temperature (rapidtherm takes {} to {} °C)",
            p.lowest_c, p.highest_c
        );
        if (p.kelvin_low..=p.kelvin_high).contains(&value_c) {
            why.push_str(&format!(
                "; is it in kelvin? {value} K is {:.2} °C",
                value_c + ABSOLUTE_ZERO_C
            ));
        }
        return Some(why);
    }
    None
}

/// Why `value` (°C) cannot be the temperature of a room a robot works in
/// (an `ambient_c` column, the motors at the cold start), or `None` when it
/// can. A room above the bound in °F is named: a 20 °C room is 68 °F.
pub fn implausible_room(value: f64) -> Option<String> {
    if let Some(why) = implausible(value) {
        return Some(why);
    }
    let p = plausible();
    if (p.room_lowest_c..=p.room_highest_c).contains(&value) {
        return None;
    }
    let mut why = format!(
        "{} °C is no room a robot works in (rapidtherm takes {} to {} °C)",
        shown(value),
        p.room_lowest_c,
        p.room_highest_c
    );
    let celsius = (value - 32.0) * 5.0 / 9.0;
    if value > p.room_highest_c && (p.room_lowest_c..=p.room_highest_c).contains(&celsius) {
        why.push_str(&format!(
            "; is it in °F? {} °F is {celsius:.1} °C",
            shown(value)
        ));
    }
    Some(why)
}

/// `value` as a room's temperature, or an input error at `location`.
pub fn check_room(value: f64, location: impl FnOnce() -> Location) -> Result<f64> {
    match implausible_room(value) {
        None => Ok(value),
        Some(why) => Err(Error::input(why).at(location())),
    }
}

/// `value` as a temperature, or an input error at `location`.
pub fn check(value: f64, location: impl FnOnce() -> Location) -> Result<f64> {
    match implausible(value) {
        None => Ok(value),
        Some(why) => Err(Error::input(why).at(location())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kelvin_and_absolute_zero_are_named() {
        assert!(implausible(7.0).is_none());
        assert!(implausible(-40.0).is_none());
        assert!(implausible(289.0)
            .unwrap()
            .contains("kelvin? 289 K is 15.85 °C"));
        assert!(implausible(-300.0).unwrap().contains("absolute zero"));
        assert!(implausible(1e300).unwrap().starts_with("1e300 °C"));
        assert!(implausible(f64::NAN).is_some());
        assert!(!implausible(1000.0).unwrap().contains("kelvin"));
    }

    #[test]
    fn a_room_in_fahrenheit_is_named() {
        // 68 °F = (68 - 32) * 5/9 = 20 °C.
        assert!(implausible_room(20.0).is_none());
        let why = implausible_room(68.0).unwrap();
        assert!(why.contains("°F? 68 °F is 20.0 °C"), "{why}");
        assert!(implausible_room(-30.0).is_some());
        assert!(implausible_room(289.0).unwrap().contains("kelvin"));
    }
}
