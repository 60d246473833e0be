//! Fitting one named heating model to one axis of points, and the quality
//! figures the paper reports (R, R², mean relative error Ā) plus the ones a
//! user of the curve needs (RMSE, max error in °C, error on held-out data).
//! `auto`, the choice among these models, stands above ([`super::select`],
//! [`super::fit`]).

use super::poly::{fit_poly, PolyCurve};
use super::saturating::{fit_saturating, SatCurve};
use super::uncertainty::forecast_interval;
use crate::error::{Error, ErrorKind, Result};
use std::borrow::Cow;
use std::fmt;
use std::str::FromStr;

/// Which model to fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// Polynomial in time of this degree (the paper's method).
    Poly(usize),
    /// T0 + ΔT·(1 − e^(−t/τ)).
    FirstOrder,
    /// T0 + ΔT1·(1 − e^(−t/τ1)) + ΔT2·(1 − e^(−t/τ2)).
    TwoTau,
    /// First-order or two-tau, whichever forecasts the held-out end of the
    /// recording better ([`super::select`]).
    Auto,
}

/// Highest polynomial degree accepted: far above any useful heating curve
/// (the paper found nothing gained above 4), low enough to stay meaningful.
pub const MAX_POLY_DEGREE: usize = 20;

impl ModelKind {
    /// Number of fitted parameters (T0 counted unless pinned).
    pub fn params(self, pinned_t0: bool) -> usize {
        match self {
            ModelKind::Poly(d) => d + 1,
            // Auto needs at least what its simplest candidate needs.
            ModelKind::FirstOrder | ModelKind::Auto => 3 - usize::from(pinned_t0),
            ModelKind::TwoTau => 5 - usize::from(pinned_t0),
        }
    }

    /// The models `--model all` compares: the paper's three polynomials and
    /// the two saturating models.
    pub fn all() -> Vec<ModelKind> {
        vec![
            ModelKind::Poly(1),
            ModelKind::Poly(2),
            ModelKind::Poly(3),
            ModelKind::FirstOrder,
            ModelKind::TwoTau,
        ]
    }
}

impl fmt::Display for ModelKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModelKind::Poly(d) => write!(f, "poly{d}"),
            ModelKind::FirstOrder => f.write_str("first-order"),
            ModelKind::TwoTau => f.write_str("two-tau"),
            ModelKind::Auto => f.write_str("auto"),
        }
    }
}

impl FromStr for ModelKind {
    type Err = Error;
    fn from_str(s: &str) -> Result<ModelKind> {
        let lower = s.trim().to_ascii_lowercase();
        match lower.as_str() {
            "first-order" | "first_order" | "exp" => return Ok(ModelKind::FirstOrder),
            "two-tau" | "two_tau" | "exp2" => return Ok(ModelKind::TwoTau),
            "auto" => return Ok(ModelKind::Auto),
            "linear" => return Ok(ModelKind::Poly(1)),
            "quadratic" => return Ok(ModelKind::Poly(2)),
            "cubic" => return Ok(ModelKind::Poly(3)),
            _ => {}
        }
        match lower.strip_prefix("poly").map(str::parse::<usize>) {
            Some(Ok(d)) if (1..=MAX_POLY_DEGREE).contains(&d) => Ok(ModelKind::Poly(d)),
            _ => Err(Error::usage(format!(
                "unknown heating model `{s}`: expected poly1 .. poly{MAX_POLY_DEGREE}, first-order, two-tau or auto"
            ))),
        }
    }
}

/// A fitted heating curve of one axis.
#[derive(Debug, Clone, PartialEq)]
pub enum Curve {
    Poly(PolyCurve),
    Saturating(SatCurve),
}

impl Curve {
    /// Value at `t`, extrapolating freely: for metrics and plots only.
    pub fn eval(&self, t: f64) -> f64 {
        match self {
            Curve::Poly(p) => p.eval(t),
            Curve::Saturating(s) => s.eval(t),
        }
    }

    /// Value at `t` for prediction: a polynomial refuses any time outside
    /// its fitted window, a saturating curve any time before the cold start.
    pub fn predict(&self, t: f64) -> Result<f64> {
        if !t.is_finite() {
            return Err(Error::usage(format!("time {t} min is not a finite number")));
        }
        match self {
            Curve::Poly(p) if !p.contains(t) => Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "minute {t} is outside the window {} to {} min the degree-{} polynomial was fitted to",
                    p.t_lo,
                    p.t_hi,
                    p.degree()
                ),
            )
            .with_note(format!(
                "a polynomial in time means nothing outside its window (it would give {:.1} °C here); use a saturating model (first-order or two-tau) to predict beyond it",
                p.eval(t)
            ))),
            Curve::Saturating(_) if t < 0.0 => Err(Error::usage(format!(
                "minute {t} is before the cold start (t = 0)"
            ))),
            _ => Ok(self.eval(t)),
        }
    }
}

/// How well a curve matches points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    pub n: usize,
    /// R = √(1 − SSres/SStot) (the paper's eq. 10); `None` when R² < 0 or
    /// the data are constant.
    pub r: Option<f64>,
    /// R² = 1 − SSres/SStot; `None` when the data are constant.
    pub r2: Option<f64>,
    /// Ā = (1/n)·Σ|(y − ŷ)/y|·100 % (the paper's eq. 6); `None` if some y = 0.
    pub mean_rel_pct: Option<f64>,
    /// Root-mean-square error, °C.
    pub rmse: f64,
    /// Largest absolute error, °C.
    pub max_abs: f64,
}

impl Metrics {
    pub fn of(t: &[f64], y: &[f64], f: impl Fn(f64) -> f64) -> Metrics {
        let n = t.len().min(y.len());
        let y = &y[..n];
        let mean = y.iter().sum::<f64>() / n.max(1) as f64;
        let (mut ss_res, mut ss_tot, mut rel, mut max_abs) = (0.0, 0.0, 0.0, 0.0f64);
        let mut rel_ok = true;
        for (&x, &v) in t.iter().zip(y) {
            let e = v - f(x);
            ss_res += e * e;
            ss_tot += (v - mean) * (v - mean);
            max_abs = max_abs.max(e.abs());
            if v == 0.0 {
                rel_ok = false;
            } else {
                rel += (e / v).abs();
            }
        }
        let r2 = (ss_tot > 0.0).then(|| 1.0 - ss_res / ss_tot);
        Metrics {
            n,
            r: r2.filter(|v| *v >= 0.0).map(f64::sqrt),
            r2,
            mean_rel_pct: (rel_ok && n > 0).then(|| rel / n as f64 * 100.0),
            rmse: (ss_res / n.max(1) as f64).sqrt(),
            max_abs,
        }
    }
}

/// Fraction of the rows (from the start) used for the held-out check; the
/// rest is predicted by a curve that has not seen it.
pub const TRAIN_FRACTION: (usize, usize) = (4, 5);

/// Most rows a curve is fitted to. A longer recording (a controller
/// logging every 50 ms: 200,000 rows for a warm-up) is fitted to the means
/// of consecutive groups of rows, as many groups as this, each group's
/// mean time against its mean temperature; the quality figures are still
/// taken on every row. A group spans the recording's length divided by
/// this (2.5 s of a three-hour warm-up), far below a heating time constant
/// (minutes), so the curve is the one the rows give; the fits, their
/// hold-out and the forecast's profile then cost what a recording of this
/// many rows costs, not minutes.
pub const MAX_FIT_ROWS: usize = 4000;

/// The rows a curve is fitted to: `t`, `y` themselves when there are at
/// most [`MAX_FIT_ROWS`], else the means of consecutive groups.
pub(super) fn fitted_rows<'a>(t: &'a [f64], y: &'a [f64]) -> (Cow<'a, [f64]>, Cow<'a, [f64]>) {
    let n = t.len().min(y.len());
    if n <= MAX_FIT_ROWS {
        return (Cow::Borrowed(&t[..n]), Cow::Borrowed(&y[..n]));
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    // Group boundaries spread the remainder over the groups, so that no
    // group is much smaller than the others.
    let edge = |g: usize| g * n / MAX_FIT_ROWS;
    let (gt, gy): (Vec<f64>, Vec<f64>) = (0..MAX_FIT_ROWS)
        .map(|g| {
            let (a, b) = (edge(g), edge(g + 1));
            (mean(&t[a..b]), mean(&y[a..b]))
        })
        .unzip();
    (Cow::Owned(gt), Cow::Owned(gy))
}

/// One candidate of a choice and how it did.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    pub kind: ModelKind,
    /// RMSE (°C) on the held-out rows of the candidate fitted to the rest;
    /// `None` when it could not be judged (too few rows for it).
    pub holdout_rmse: Option<f64>,
    /// Why the candidate is no result (did not converge, degenerate).
    pub refused: Option<String>,
}

/// The fit of one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisFit {
    /// 1-based axis number.
    pub axis: usize,
    pub kind: ModelKind,
    pub curve: Curve,
    /// Against every point of the recording.
    pub fit: Metrics,
    /// The same model fitted to the first 80 % of the rows, evaluated on the
    /// last 20 % (extrapolating, which is the point). `None` when the first
    /// 80 % is too short for the model.
    pub holdout: Option<Metrics>,
    /// Saturating models: the steady temperatures the recording cannot
    /// tell apart from the fitted one's (`uncertainty::forecast_interval`
    /// at t = ∞),
    /// °C. Wide when the recording is shorter than its time constants.
    pub steady_interval: Option<(f64, f64)>,
    /// With `auto`: every candidate and how it forecast the held-out rows
    /// (`kind` is the one chosen). Empty for a model asked for by name.
    pub chosen_from: Vec<Candidate>,
}

impl AxisFit {
    /// The model as a report names it: `first-order`, or `auto: first-order`
    /// when `auto` chose it.
    pub fn model_name(&self) -> String {
        if self.chosen_from.is_empty() {
            self.kind.to_string()
        } else {
            format!("auto: {}", self.kind)
        }
    }
}

/// [`super::fit::fit_points`] of a named kind but the steady interval, the costly part:
/// `auto` computes that for the candidate it keeps only.
pub(super) fn fit_without_interval(
    axis: usize,
    t: &[f64],
    y: &[f64],
    kind: ModelKind,
    pin_t0: Option<f64>,
) -> Result<AxisFit> {
    let (ft, fy) = fitted_rows(t, y);
    let curve = fit_named_curve(&ft, &fy, kind, pin_t0)?;
    let fit = Metrics::of(t, y, |x| curve.eval(x));
    let n = t.len().min(y.len());
    let split = n * TRAIN_FRACTION.0 / TRAIN_FRACTION.1;
    let holdout = if split < n && split >= kind.params(pin_t0.is_some()) {
        let (ht, hy) = fitted_rows(&t[..split], &y[..split]);
        fit_named_curve(&ht, &hy, kind, pin_t0)
            .ok()
            .map(|c| Metrics::of(&t[split..n], &y[split..n], |x| c.eval(x)))
    } else {
        None
    };
    Ok(AxisFit {
        axis,
        kind,
        curve,
        fit,
        holdout,
        steady_interval: None,
        chosen_from: Vec::new(),
    })
}

/// Fit one named model to points ([`super::fit::fit_curve`] for any kind,
/// `auto` among them). `auto` is a choice among models, made by
/// [`super::select`] above this file, not one model to fit.
pub(super) fn fit_named_curve(
    t: &[f64],
    y: &[f64],
    kind: ModelKind,
    pin_t0: Option<f64>,
) -> Result<Curve> {
    Ok(match kind {
        ModelKind::Poly(d) => Curve::Poly(fit_poly(t, y, d)?),
        ModelKind::FirstOrder => Curve::Saturating(fit_saturating(t, y, 1, pin_t0)?),
        ModelKind::TwoTau => Curve::Saturating(fit_saturating(t, y, 2, pin_t0)?),
        ModelKind::Auto => {
            return Err(Error::usage(
                "`auto` chooses among models; it is not one model to fit",
            ))
        }
    })
}

/// The steady temperatures the points cannot rule out, for a saturating
/// curve (a polynomial has no steady state).
pub(super) fn steady_interval_of(
    curve: &Curve,
    t: &[f64],
    y: &[f64],
    pin_t0: Option<f64>,
) -> Option<(f64, f64)> {
    let (t, y) = fitted_rows(t, y);
    match curve {
        Curve::Saturating(c) => forecast_interval(&t, &y, c, pin_t0, f64::INFINITY),
        Curve::Poly(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn model_names_round_trip() {
        for k in ModelKind::all() {
            assert_eq!(k.to_string().parse::<ModelKind>().unwrap(), k);
        }
        assert_eq!("poly7".parse::<ModelKind>().unwrap(), ModelKind::Poly(7));
        assert!("poly0".parse::<ModelKind>().is_err());
        assert!("spline".parse::<ModelKind>().is_err());
    }

    #[test]
    fn metrics_match_hand_computation() {
        // y = 1, 2, 4; f = 1, 2, 3: SSres 1, SStot 14/3, Ā = 25/3 %.
        let m = Metrics::of(&[0.0, 1.0, 2.0], &[1.0, 2.0, 4.0], |x| x + 1.0);
        assert!((m.r2.unwrap() - (1.0 - 3.0 / 14.0)).abs() < 1e-15);
        assert!((m.mean_rel_pct.unwrap() - 25.0 / 3.0).abs() < 1e-12);
        assert!((m.rmse - (1.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert_eq!(m.max_abs, 1.0);
    }
}
