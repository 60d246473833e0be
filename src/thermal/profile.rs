//! Heating profiles built from fitted curves, and the embedded default
//! profile of the IRB 140 at 60 % speed.

use super::fit::{fit_axis, AxisFit, Curve, ModelKind};
use super::record::HeatingRecord;
use super::saturating::{SatCurve, SatTerm};
use super::HeatingProfile;
use crate::error::{Error, Result};
use crate::thermal::MotorTemps;

/// One fitted curve per axis. A polynomial axis refuses times outside its
/// window (never a silent extrapolation).
#[derive(Debug, Clone, PartialEq)]
pub struct FittedProfile {
    pub axes: [Curve; 6],
}

impl FittedProfile {
    /// Fit `kind` to every axis of a recording (T(0) pinned for saturating
    /// models when `pin_t0` is given).
    pub fn fit(
        record: &HeatingRecord,
        kind: ModelKind,
        pin_t0: Option<f64>,
    ) -> Result<FittedProfile> {
        let fits: Vec<AxisFit> = (1..=6)
            .map(|axis| fit_axis(record, axis, kind, pin_t0))
            .collect::<Result<_>>()?;
        let curves: Vec<Curve> = fits.into_iter().map(|f| f.curve).collect();
        let axes: [Curve; 6] = curves
            .try_into()
            .map_err(|_| Error::input("a heating record has six axes"))?;
        Ok(FittedProfile { axes })
    }
}

impl HeatingProfile for FittedProfile {
    fn temps_at(&self, t_min: f64) -> Result<MotorTemps> {
        let mut out = [0.0; 6];
        for (o, c) in out.iter_mut().zip(&self.axes) {
            *o = c.predict(t_min)?;
        }
        Ok(out)
    }

    fn steady(&self) -> Result<MotorTemps> {
        let mut out = [0.0; 6];
        for (o, c) in out.iter_mut().zip(&self.axes) {
            *o = match c {
                Curve::Saturating(s) => s.steady(),
                Curve::Poly(_) => {
                    return Err(Error::new(
                        crate::error::ErrorKind::Unsupported,
                        "a polynomial heating curve has no steady state: fit a saturating model (first-order, two-tau) or give a time with --at MIN",
                    ))
                }
            };
        }
        Ok(out)
    }
}

/// Saturating curves on all six axes: defined and bounded for every t ≥ 0.
#[derive(Debug, Clone, PartialEq)]
pub struct SaturatingProfile {
    pub axes: [SatCurve; 6],
}

impl HeatingProfile for SaturatingProfile {
    fn temps_at(&self, t_min: f64) -> Result<MotorTemps> {
        if !t_min.is_finite() || t_min < 0.0 {
            return Err(Error::usage(format!(
                "minute {t_min} is not a time since the cold start (t ≥ 0)"
            )));
        }
        Ok(std::array::from_fn(|i| self.axes[i].eval(t_min)))
    }

    fn steady(&self) -> Result<MotorTemps> {
        Ok(std::array::from_fn(|i| self.axes[i].steady()))
    }
}

/// Temperature of every motor at the cold start of the reference recording
/// (a cold laboratory), and the T_ref of the base thermal model: the default
/// profile starts here exactly.
pub const COLD_START_C: f64 = 7.0;

/// The model kind of the embedded default profile (chosen by held-out error
/// on the reference sample; see the README and `tests/thermal_default.rs`).
pub const DEFAULT_KIND: ModelKind = ModelKind::TwoTau;

/// (ΔT1, τ1, ΔT2, τ2) per axis, °C and minutes: the two-time-constant model
/// fitted to `samples/heating_irb140_60pct.csv` with T(0) pinned at 7.0 °C
/// (`rapidtherm heating fit samples/heating_irb140_60pct.csv --model two-tau
/// --pin-t0 7 --format json`), full precision as printed there.
pub const DEFAULT_PARAMS: [[f64; 4]; 6] = [
    [
        0.6268076010648681,
        7.5437646729631815,
        11.256018695448029,
        37.78926238979746,
    ],
    [
        4.05576694492353,
        14.079930902697969,
        12.03462788326077,
        80.4829413085255,
    ],
    [
        2.885975598991207,
        14.049158982161172,
        10.204132850347094,
        79.85977583594334,
    ],
    [
        4.794876349606954,
        14.08587280584746,
        11.068642940897131,
        75.54269119115092,
    ],
    [
        6.551277808856958,
        12.938995947687841,
        15.371125106994937,
        69.82350195437833,
    ],
    [
        7.968574470189919,
        11.978324555714916,
        17.00811052474162,
        64.82131192750644,
    ],
];

/// The profile used when the user gives no recording: IRB 140 at 60 % of
/// maximum speed, from a cold start at 7.0 °C.
pub fn default_profile() -> SaturatingProfile {
    SaturatingProfile {
        axes: std::array::from_fn(|i| {
            let [d1, t1, d2, t2] = DEFAULT_PARAMS[i];
            SatCurve {
                t0: COLD_START_C,
                terms: vec![
                    SatTerm { delta: d1, tau: t1 },
                    SatTerm { delta: d2, tau: t2 },
                ],
            }
        }),
    }
}
