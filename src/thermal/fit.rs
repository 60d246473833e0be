//! Fitting a heating model to one axis of a recording: a model named, or
//! `auto`'s choice among them by forecast ([`super::select`]). The models
//! themselves, their curves and quality figures are [`super::kind_fit`]'s.

use super::kind_fit::{fit_named_curve, fit_without_interval, steady_interval_of};
use super::record::{HeatingRecord, AXIS_COLUMNS};
use super::select::select_saturating;
use crate::error::{Error, ErrorKind, Result};

pub use super::kind_fit::{
    AxisFit, Candidate, Curve, Metrics, ModelKind, MAX_FIT_ROWS, MAX_POLY_DEGREE, TRAIN_FRACTION,
};

/// Fit one model to points. `pin_t0` fixes T(0) of saturating models.
pub fn fit_curve(t: &[f64], y: &[f64], kind: ModelKind, pin_t0: Option<f64>) -> Result<Curve> {
    Ok(match kind {
        ModelKind::Auto => select_saturating(0, t, y, pin_t0)?.curve,
        named => fit_named_curve(t, y, named, pin_t0)?,
    })
}

/// Fit, metrics, held-out check and steady interval of one axis of points.
pub fn fit_points(
    axis: usize,
    t: &[f64],
    y: &[f64],
    kind: ModelKind,
    pin_t0: Option<f64>,
) -> Result<AxisFit> {
    if kind == ModelKind::Auto {
        return select_saturating(axis, t, y, pin_t0);
    }
    let mut fit = fit_without_interval(axis, t, y, kind, pin_t0)?;
    fit.steady_interval = steady_interval_of(&fit.curve, t, y, pin_t0);
    Ok(fit)
}

/// Fit one axis (1-based) of a recording. Input errors (too few points, time
/// that does not advance) are located at that axis's column in the record.
pub fn fit_axis(
    record: &HeatingRecord,
    axis: usize,
    kind: ModelKind,
    pin_t0: Option<f64>,
) -> Result<AxisFit> {
    let Some(y) = axis.checked_sub(1).and_then(|a| record.temps.get(a)) else {
        return Err(Error::usage(format!("axis {axis} does not exist (1..6)")));
    };
    fit_points(axis, &record.times, y, kind, pin_t0).map_err(|e| {
        if e.kind == ErrorKind::Input && e.location.is_none() {
            let loc = record.location(record.len().saturating_sub(1), axis - 1);
            Error::input(format!(
                "column `{}`: {}",
                AXIS_COLUMNS[axis - 1],
                e.message
            ))
            .at(loc)
        } else {
            e
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::ErrorKind;

    #[test]
    fn polynomial_refuses_outside_window() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let c = fit_curve(&t, &[1.0, 2.0, 3.0, 4.0], ModelKind::Poly(1), None).unwrap();
        assert!((c.predict(3.0).unwrap() - 4.0).abs() < 1e-12);
        let e = c.predict(3.5).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Unsupported);
    }
}
