//! How far a heating forecast beyond its recording can be trusted.
//!
//! A fitted curve is one of many the recording cannot tell apart. Beyond a
//! recording shorter than its slower heat paths, a single exponential fits
//! to within the noise and still forecasts several kelvin off, and the
//! spread of its own time constant does not show it: the curve family is
//! wrong, not its parameters. So the uncertainty is taken over the richer
//! family: two time constants, the slower up to the slowest heat path a
//! robot has (`data/thermal/forecast.toml`), each pair's amplitudes solved
//! by least squares; every pair whose residuals stay within about two
//! standard errors of the best counts, with its amplitudes' own standard
//! errors around its forecast.

use super::saturating::{SatCurve, TAU_MIN};
use nalgebra::{DMatrix, DVector};
use serde::Deserialize;
use std::sync::OnceLock;

/// `data/thermal/forecast.toml`.
pub const FORECAST_TOML: &str = include_str!("../../data/thermal/forecast.toml");

/// The bounds of the forecast's uncertainty (`data/thermal/forecast.toml`).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForecastBounds {
    /// The slowest heat path of a robot, minutes.
    pub slowest_time_constant_min: f64,
    /// Half-width around each curve's forecast, in standard errors.
    pub standard_errors: f64,
}

/// The embedded bounds, parsed once.
pub fn forecast_bounds() -> ForecastBounds {
    static BOUNDS: OnceLock<ForecastBounds> = OnceLock::new();
    *BOUNDS.get_or_init(|| {
        toml::from_str(FORECAST_TOML).expect("the embedded data/thermal/forecast.toml is valid")
    })
}

/// Grid points per time constant of a pair (log-spaced).
const GRID: usize = 40;

/// Grid points of a single time constant (log-spaced, 2.3 % apart).
const SINGLE_GRID: usize = 400;

/// χ² with two degrees of freedom at 95 %, rounded: the rise in the sum of
/// squared residuals (in noise variances) a pair of time constants may
/// cost and still count as one the recording cannot rule out.
const PROFILE_CHI2: f64 = 6.0;

/// The range of temperatures at minute `at` that the recording `t`, `y`
/// cannot rule out, together with the fitted `curve`'s own forecast: that
/// of every one- and two-time-constant curve (terms rising the way the recording does)
/// whose residuals stay within `PROFILE_CHI2` noise variances of the
/// best such curve's, each widened by its amplitudes' standard errors. Inside the recording it is as narrow as the noise; far beyond a
/// short one it is wide. `None` when the recording has too few points to
/// estimate the noise.
pub fn forecast_interval(
    t: &[f64],
    y: &[f64],
    curve: &SatCurve,
    pin_t0: Option<f64>,
    at: f64,
) -> Option<(f64, f64)> {
    let n = t.len().min(y.len());
    let (t, y) = (&t[..n], &y[..n]);
    let span = t.iter().copied().fold(0.0, f64::max);
    let params = 4 + usize::from(pin_t0.is_none());
    let dof = n.checked_sub(params).filter(|&d| d > 0)? as f64;
    let bounds = forecast_bounds();
    let slowest = bounds.slowest_time_constant_min.max(span);
    let mut sets: Vec<Vec<f64>> = vec![curve.terms.iter().map(|k| k.tau).collect()];
    let (lo, hi) = (TAU_MIN.max(span / 1000.0).ln(), slowest.ln());
    let grid = |i: usize| (lo + (hi - lo) * i as f64 / (GRID - 1) as f64).exp();
    // One time constant, finely: a well-told one moves the forecast by
    // tenths of a kelvin within a few per cent.
    for i in 0..SINGLE_GRID {
        sets.push(vec![
            (lo + (hi - lo) * i as f64 / (SINGLE_GRID - 1) as f64).exp()
        ]);
    }
    for i in 0..GRID {
        for j in i + 1..GRID {
            let (fast, slow) = (grid(i), grid(j));
            if slow / fast >= 1.2 {
                sets.push(vec![fast, slow]);
            }
        }
    }
    // A warm-up's heat paths all heat (a cool-down's all cool): a pair
    // whose terms pull in opposite directions fits noise, not physics.
    let rising = curve.steady() >= curve.t0;
    let solved: Vec<Solved> = sets
        .iter()
        .filter_map(|taus| solve(t, y, taus, pin_t0, at))
        .filter(|s| s.deltas.iter().all(|d| (*d >= 0.0) == rising || *d == 0.0))
        .collect();
    let best = solved.iter().map(|s| s.rss).fold(f64::INFINITY, f64::min);
    if !best.is_finite() {
        return None;
    }
    // Two time constants profiled: Δχ² ≤ 6 (95 % for two parameters),
    // with the noise variance the best pair leaves.
    let sigma2 = best / dof;
    let limit = best + PROFILE_CHI2 * sigma2;
    // The fitted curve's own forecast always belongs: the interval says
    // how far from it the truth may lie. (A first-order curve through a
    // recording that shows two heat paths gets an interval reaching from
    // its own forecast to theirs.)
    let value = curve.eval(at);
    let mut interval = (value, value);
    for s in solved.iter().filter(|s| s.rss <= limit) {
        let half = bounds.standard_errors * (sigma2 * s.leverage).sqrt();
        interval = (
            interval.0.min(s.value - half),
            interval.1.max(s.value + half),
        );
    }
    (interval.0.is_finite() && interval.1.is_finite()).then_some(interval)
}

/// One set of time constants, its amplitudes solved.
struct Solved {
    rss: f64,
    /// The ΔT of each time constant.
    deltas: Vec<f64>,
    /// The curve's value at the forecast time.
    value: f64,
    /// gᵀ(AᵀA)⁻¹g: the forecast's variance per unit noise variance.
    leverage: f64,
}

/// Least squares of T0 (unless pinned) and one ΔT per time constant.
fn solve(t: &[f64], y: &[f64], taus: &[f64], pin_t0: Option<f64>, at: f64) -> Option<Solved> {
    let o = usize::from(pin_t0.is_none());
    let p = o + taus.len();
    let base = pin_t0.unwrap_or(0.0);
    // 1 − e^(−t/τ) as −expm1: exact near 0, and 1 at t = ∞.
    let rise = |x: f64, tau: f64| -(-x / tau).exp_m1();
    let a = DMatrix::from_fn(t.len(), p, |r, c| {
        if c < o {
            1.0
        } else {
            rise(t[r], taus[c - o])
        }
    });
    let b = DVector::from_iterator(y.len(), y.iter().map(|v| v - base));
    let g = DVector::from_fn(p, |c, _| if c < o { 1.0 } else { rise(at, taus[c - o]) });
    let qr = a.clone().qr();
    let r = qr.r();
    // A rank-deficient pair (time constants the data cannot separate at
    // all) has no amplitudes to speak of.
    let scale = r.diagonal().amax();
    if scale.is_nan() || scale <= 0.0 || r.diagonal().iter().any(|d| d.abs() < 1e-10 * scale) {
        return None;
    }
    let qtb = qr.q().transpose() * &b;
    let x = r.solve_upper_triangular(&qtb)?;
    let z = r.tr_solve_upper_triangular(&g)?;
    let resid = &a * &x - &b;
    let value = base + g.dot(&x);
    let solved = Solved {
        rss: resid.norm_squared(),
        deltas: x.iter().skip(o).copied().collect(),
        value,
        leverage: z.norm_squared(),
    };
    (solved.rss.is_finite() && solved.value.is_finite() && solved.leverage.is_finite())
        .then_some(solved)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thermal::saturating::SatTerm;

    #[test]
    fn the_embedded_bounds_parse() {
        let b = forecast_bounds();
        assert!(b.slowest_time_constant_min >= 240.0);
        assert!(b.standard_errors > 0.0);
    }

    #[test]
    fn inside_a_clean_recording_the_interval_is_the_value() {
        // Noise-free first-order data: the fitted curve is exact, every
        // other pair that fits as well agrees inside the window.
        let c = SatCurve {
            t0: 20.0,
            terms: vec![SatTerm {
                delta: 10.0,
                tau: 30.0,
            }],
        };
        let t: Vec<f64> = (0..=300).map(|i| i as f64).collect();
        let y: Vec<f64> = t.iter().map(|&x| c.eval(x)).collect();
        let (lo, hi) = forecast_interval(&t, &y, &c, None, 150.0).unwrap();
        assert!(lo <= c.eval(150.0) && c.eval(150.0) <= hi);
        assert!(hi - lo < 1e-3, "{lo}..{hi}");
    }
}
