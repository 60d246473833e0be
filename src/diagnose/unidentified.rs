//! Why a fitted parameter is not identifiable from the data: shared by the
//! chain calibration ([`super::chain_calib`]) and the effect fit
//! ([`super::fit`]), so that both say it in the same typed words.

use serde::Serialize;

/// Why a parameter is not identifiable from the measured positions (held
/// at zero, never printed as a finding).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "kebab-case")]
pub enum Unidentified {
    /// It hardly moves the measured point: changed by its resolution it
    /// moves no pose by as much as the noise (a joint turning about an axis
    /// through the point, a rotation about a line the point lies on).
    /// `lever_mm`: the largest displacement of the point per unit of the
    /// parameter (for an angle in mrad, its lever in metres).
    NoLever { lever_mm: f64 },
    /// Its effect is (nearly) that of kept parameters: `independent` is the
    /// share of its column's norm independent of them.
    SameAs {
        independent: f64,
        same_as: Vec<String>,
    },
    /// Its own part of the data is too small for the noise: its standard
    /// error would be `stderr`, above its resolution `limit` (both in the
    /// parameter's unit).
    Unresolved { stderr: f64, limit: f64 },
    /// The fit took it to `value`, beyond the plausible `limit`: the data
    /// leave it free to wander.
    Implausible { value: f64, limit: f64 },
    /// A time constant the fit ran onto a bound of its range (`value`, 0 or
    /// the longest allowed): the data push it beyond, and do not pin it;
    /// held there, not fitted.
    AtBound { value: f64 },
}
