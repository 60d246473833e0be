//! Heating profiles built from fitted curves, and the embedded default
//! profile of the IRB 140 at 60 % speed (`data/irb140/heating.toml`).

use super::fit::{fit_axis, AxisFit, Curve, ModelKind};
use super::kind_fit::fitted_rows;
use super::record::HeatingRecord;
use super::saturating::{SatCurve, SatTerm};
use super::uncertainty::forecast_interval;
use super::HeatingProfile;
use crate::error::{Error, Location, Result};
use crate::thermal::MotorTemps;
use serde::Deserialize;
use std::sync::OnceLock;

/// One fitted curve per axis. A polynomial axis refuses times outside its
/// window (never a silent extrapolation). Keeps the points it was fitted
/// to, to say how uncertain a forecast beyond them is.
#[derive(Debug, Clone, PartialEq)]
pub struct FittedProfile {
    pub axes: [Curve; 6],
    times: Vec<f64>,
    temps: [Vec<f64>; 6],
    pin_t0: Option<f64>,
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
        Ok(FittedProfile {
            axes,
            times: record.times.clone(),
            temps: record.temps.clone(),
            pin_t0,
        })
    }

    /// Minutes the curves were fitted over (first and last row).
    pub fn window(&self) -> (f64, f64) {
        let lo = self.times.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = self.times.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    }

    /// Per axis, the temperatures at `t_min` of every saturating curve the
    /// recording cannot tell apart from the fitted one
    /// ([`forecast_interval`]); `None` for a polynomial axis (it refuses
    /// to forecast at all). Beyond a recording shorter than its time
    /// constants this is the forecast's honest uncertainty.
    pub fn uncertainty_at(&self, t_min: f64) -> [Option<(f64, f64)>; 6] {
        std::array::from_fn(|a| match &self.axes[a] {
            Curve::Saturating(c) => {
                let (t, y) = fitted_rows(&self.times, &self.temps[a]);
                forecast_interval(&t, &y, c, self.pin_t0, t_min)
            }
            Curve::Poly(_) => None,
        })
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
                        "a polynomial heating curve has no steady state",
                    )
                    .with_remedy(crate::error::Remedy::FitSaturatingOrGiveMinute))
                }
            };
        }
        Ok(out)
    }

    fn curves(&self) -> Option<[SatCurve; 6]> {
        let mut out: [Option<SatCurve>; 6] = Default::default();
        for (o, c) in out.iter_mut().zip(&self.axes) {
            *o = match c {
                Curve::Saturating(s) => Some(s.clone()),
                Curve::Poly(_) => return None,
            };
        }
        let [a, b, c, d, e, f] = out;
        Some([a?, b?, c?, d?, e?, f?])
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

    fn curves(&self) -> Option<[SatCurve; 6]> {
        Some(self.axes.clone())
    }
}

/// The embedded default heating profile (`data/irb140/heating.toml`): the
/// IRB 140 at 60 % of maximum speed from a cold start.
pub const DEFAULT_HEATING_TOML: &str = include_str!("../../data/irb140/heating.toml");

/// The default heating profile's numbers, as `data/irb140/heating.toml`
/// gives them.
#[derive(Debug, Clone, PartialEq)]
pub struct DefaultHeating {
    /// The model kind (two-tau: chosen by held-out error on the reference
    /// sample; see `tests/thermal/sample.rs`).
    pub kind: ModelKind,
    /// Temperature of every motor at the cold start of the reference
    /// recording (a cold laboratory), °C: the T_ref of the default model,
    /// where the profile starts exactly.
    pub t0_c: f64,
    /// (ΔT1 °C, τ1 min, ΔT2 °C, τ2 min) per axis: the two-time-constant
    /// model fitted to `samples/heating_irb140_60pct.csv` with T(0) pinned
    /// (the command is in the data file's header).
    pub params: [[f64; 4]; 6],
}

/// `data/irb140/heating.toml` as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HeatingFile {
    kind: String,
    t0_c: f64,
    axes: Vec<TwoTauAxis>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TwoTauAxis {
    dt1_c: f64,
    tau1_min: f64,
    dt2_c: f64,
    tau2_min: f64,
}

/// Parse a default-heating file (`file` names it in messages).
fn parse_default_heating(file: &str, text: &str) -> Result<DefaultHeating> {
    let f: HeatingFile = toml::from_str(text).map_err(|e| {
        let err = Error::input(format!("heating profile: {}", e.message()));
        match e.span() {
            Some(span) => err.at(Location::from_offset(file, text.as_bytes(), span.start)),
            None => err.with_note(format!("in {file}")),
        }
    })?;
    let bad = |msg: String| Error::input(format!("{file}: heating profile: {msg}"));
    let kind: ModelKind = f.kind.parse()?;
    if kind != ModelKind::TwoTau {
        return Err(bad(format!("kind must be two-tau (got {kind})")));
    }
    if !f.t0_c.is_finite() {
        return Err(bad("t0_c must be a finite temperature".into()));
    }
    let n = f.axes.len();
    let axes: [TwoTauAxis; 6] = f
        .axes
        .try_into()
        .map_err(|_| bad(format!("six [[axes]] are needed (got {n})")))?;
    let mut params = [[0.0; 4]; 6];
    for (i, (a, out)) in axes.iter().zip(&mut params).enumerate() {
        *out = [a.dt1_c, a.tau1_min, a.dt2_c, a.tau2_min];
        if !out.iter().all(|v| v.is_finite()) || a.tau1_min <= 0.0 || a.tau2_min <= 0.0 {
            return Err(bad(format!(
                "axis {}: finite values and positive time constants are needed",
                i + 1
            )));
        }
    }
    Ok(DefaultHeating {
        kind,
        t0_c: f.t0_c,
        params,
    })
}

/// The embedded default heating profile's numbers, parsed once per process.
/// A unit test parses the embedded file, so the `expect` cannot fire on a
/// tested build.
pub fn default_heating() -> &'static DefaultHeating {
    static HEATING: OnceLock<DefaultHeating> = OnceLock::new();
    HEATING.get_or_init(|| {
        parse_default_heating("data/irb140/heating.toml", DEFAULT_HEATING_TOML)
            .expect("the embedded data/irb140/heating.toml is a valid two-tau profile")
    })
}

/// The profile used when the user gives no recording: IRB 140 at 60 % of
/// maximum speed, from a cold start at T_ref (`data/irb140/heating.toml`).
pub fn default_profile() -> SaturatingProfile {
    let h = default_heating();
    SaturatingProfile {
        axes: std::array::from_fn(|i| {
            let [d1, t1, d2, t2] = h.params[i];
            SatCurve {
                t0: h.t0_c,
                terms: vec![
                    SatTerm { delta: d1, tau: t1 },
                    SatTerm { delta: d2, tau: t2 },
                ],
            }
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_heating_parses() {
        let h = parse_default_heating("heating.toml", DEFAULT_HEATING_TOML).unwrap();
        assert_eq!(&h, default_heating());
        assert_eq!(h.kind, ModelKind::TwoTau);
        // The cold start of the reference recording (docs/model.md), the
        // default model's T_ref.
        assert_eq!(h.t0_c, 7.0);
        assert_eq!(h.params[0][0], 0.6268076010648681);
        assert_eq!(h.params[5][3], 64.82131192750644);
    }

    #[test]
    fn bad_heating_files_are_errors() {
        let text = DEFAULT_HEATING_TOML;
        for bad in [
            text.replace("kind = \"two-tau\"", "kind = \"poly3\""),
            text.replace("t0_c = 7.0", "t0_c = nan"),
            text.replace("tau2_min = 64.82131192750644", "tau2_min = -1.0"),
            text.replace("tau2_min = 64.82131192750644", "tau3_min = 1.0"),
            text.replace("[[axes]]  # axis 6", "[extra]"),
            "kind = \"two-tau\"\nt0_c = 7.0\naxes = []\n".to_string(),
        ] {
            assert_ne!(bad, text);
            assert!(parse_default_heating("h.toml", &bad).is_err(), "{bad}");
        }
    }
}
