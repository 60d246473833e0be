//! Polynomial heating curves, the paper's method, solved stably: time is
//! mapped to s ∈ [−1, 1] over the fitted window and the least-squares
//! problem is solved by SVD in the Legendre basis, which stays well
//! conditioned at any degree (the paper's normal equations in raw minutes
//! have condition number 5e13 for the cubic over 0–168 min and are singular
//! to working precision from degree 4).

use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// A polynomial fitted over the window `[t_lo, t_hi]` (minutes).
#[derive(Debug, Clone, PartialEq)]
pub struct PolyCurve {
    pub t_lo: f64,
    pub t_hi: f64,
    /// Coefficients of the Legendre polynomials P0..Pn in s.
    pub legendre: Vec<f64>,
}

impl PolyCurve {
    pub fn degree(&self) -> usize {
        self.legendre.len().saturating_sub(1)
    }

    /// s = (2t − t_lo − t_hi) / (t_hi − t_lo): −1 at t_lo, +1 at t_hi.
    pub fn scale(&self, t: f64) -> f64 {
        scale(t, self.t_lo, self.t_hi)
    }

    /// Value at `t`, inside or outside the window (callers that must not
    /// extrapolate check [`PolyCurve::contains`] first).
    pub fn eval(&self, t: f64) -> f64 {
        let s = self.scale(t);
        legendre_row(s, self.legendre.len())
            .iter()
            .zip(&self.legendre)
            .map(|(p, c)| p * c)
            .sum()
    }

    /// Whether `t` lies in the fitted window (with a rounding allowance of
    /// one part in 10⁹ of its length).
    pub fn contains(&self, t: f64) -> bool {
        let slack = 1e-9 * (self.t_hi - self.t_lo).abs().max(1.0);
        t >= self.t_lo - slack && t <= self.t_hi + slack
    }

    /// Power-series coefficients in s, constant first.
    pub fn scaled_coefficients(&self) -> Vec<f64> {
        let n = self.legendre.len();
        let basis = legendre_power_basis(n);
        (0..n)
            .map(|k| {
                basis
                    .iter()
                    .zip(&self.legendre)
                    .map(|(p, c)| c * p.get(k).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect()
    }

    /// Power-series coefficients in t (minutes), constant first: the form
    /// the paper prints (y = a·x³ + b·x² + c·x + d is `[d, c, b, a]`).
    pub fn coefficients(&self) -> Vec<f64> {
        // s = alpha·t + beta; expand Σ q_k (alpha·t + beta)^k.
        let q = self.scaled_coefficients();
        let alpha = 2.0 / (self.t_hi - self.t_lo);
        let beta = -(self.t_lo + self.t_hi) / (self.t_hi - self.t_lo);
        let n = q.len();
        let mut out = vec![0.0; n];
        // Coefficients of (alpha·t + beta)^k, built up one power at a time.
        let mut pow = vec![1.0];
        for (k, qk) in q.iter().enumerate() {
            for (j, p) in pow.iter().enumerate() {
                out[j] += qk * p;
            }
            if k + 1 < n {
                let mut next = vec![0.0; pow.len() + 1];
                for (j, p) in pow.iter().enumerate() {
                    next[j] += beta * p;
                    next[j + 1] += alpha * p;
                }
                pow = next;
            }
        }
        out
    }
}

impl PolyCurve {
    /// The polynomial with these power-series coefficients in t (constant
    /// first), valid over `[t_lo, t_hi]`: for curves printed elsewhere, such
    /// as the paper's. Errors if the window is empty or a coefficient is not
    /// finite.
    pub fn from_coefficients(t_lo: f64, t_hi: f64, coefficients: &[f64]) -> Result<PolyCurve> {
        if t_hi.partial_cmp(&t_lo) != Some(std::cmp::Ordering::Greater)
            || coefficients.is_empty()
            || !coefficients.iter().all(|c| c.is_finite())
        {
            return Err(Error::usage(
                "a polynomial needs finite coefficients and a window with t_hi > t_lo",
            ));
        }
        // Interpolating values at enough points recovers the coefficients in
        // the Legendre basis to rounding error.
        let n = coefficients.len() * 4;
        let t: Vec<f64> = (0..n)
            .map(|i| t_lo + (t_hi - t_lo) * i as f64 / (n - 1) as f64)
            .collect();
        let y: Vec<f64> = t
            .iter()
            .map(|&x| coefficients.iter().rev().fold(0.0, |acc, c| acc * x + c))
            .collect();
        fit_poly(&t, &y, coefficients.len() - 1)
    }
}

fn scale(t: f64, lo: f64, hi: f64) -> f64 {
    (2.0 * t - lo - hi) / (hi - lo)
}

/// P0(s)..P_{n−1}(s) by the three-term recurrence.
fn legendre_row(s: f64, n: usize) -> Vec<f64> {
    let mut p = Vec::with_capacity(n);
    for k in 0..n {
        let v = match k {
            0 => 1.0,
            1 => s,
            _ => {
                let kf = k as f64;
                ((2.0 * kf - 1.0) * s * p[k - 1] - (kf - 1.0) * p[k - 2]) / kf
            }
        };
        p.push(v);
    }
    p
}

/// Power-series coefficients of P0..P_{n−1}, constant first.
fn legendre_power_basis(n: usize) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::with_capacity(n);
    for k in 0..n {
        let v = match k {
            0 => vec![1.0],
            1 => vec![0.0, 1.0],
            _ => {
                let kf = k as f64;
                let mut v = vec![0.0; k + 1];
                for (j, c) in out[k - 1].iter().enumerate() {
                    v[j + 1] += (2.0 * kf - 1.0) / kf * c;
                }
                for (j, c) in out[k - 2].iter().enumerate() {
                    v[j] -= (kf - 1.0) / kf * c;
                }
                v
            }
        };
        out.push(v);
    }
    out
}

/// Least-squares polynomial of `degree` through the points, fitted over
/// their time window. Errors (without location: the caller knows the file)
/// when there are fewer points than coefficients or time does not advance.
pub fn fit_poly(t: &[f64], y: &[f64], degree: usize) -> Result<PolyCurve> {
    let n = t.len().min(y.len());
    let params = degree + 1;
    if n < params {
        return Err(Error::input(format!(
            "{n} points, but a degree-{degree} polynomial has {params} coefficients"
        )));
    }
    let (lo, hi) = t[..n]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return Err(Error::input(format!(
            "time does not advance (every row at {lo} min): no curve can be fitted"
        )));
    }
    let rows: Vec<Vec<f64>> = t[..n]
        .iter()
        .map(|&x| legendre_row(scale(x, lo, hi), params))
        .collect();
    let a = DMatrix::from_fn(n, params, |i, k| rows[i][k]);
    let b = DVector::from_column_slice(&y[..n]);
    let svd = a.svd(true, true);
    // Distinct times fewer than the coefficients: the problem has no unique
    // solution, which is an input error rather than a curve to report.
    let smax = svd.singular_values.max();
    let rank = svd
        .singular_values
        .iter()
        .filter(|&&sv| sv > smax * 1e-12 * n as f64)
        .count();
    if rank < params {
        return Err(Error::input(format!(
            "only {rank} distinct times, but a degree-{degree} polynomial has {params} coefficients"
        )));
    }
    let x = svd
        .solve(&b, 0.0)
        .map_err(|e| Error::input(format!("polynomial fit failed: {e}")))?;
    Ok(PolyCurve {
        t_lo: lo,
        t_hi: hi,
        legendre: x.iter().copied().collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn exact_cubic_is_recovered_in_original_units() {
        let t: Vec<f64> = (0..=2016).map(|i| i as f64 / 12.0).collect();
        let f = |x: f64| 0.000005 * x.powi(3) - 0.001969 * x * x + 0.247369 * x + 7.769163;
        let y: Vec<f64> = t.iter().map(|&x| f(x)).collect();
        let c = fit_poly(&t, &y, 3).unwrap();
        let k = c.coefficients();
        assert_relative_eq!(k[0], 7.769163, max_relative = 1e-12);
        assert_relative_eq!(k[1], 0.247369, max_relative = 1e-12);
        assert_relative_eq!(k[2], -0.001969, max_relative = 1e-11);
        assert_relative_eq!(k[3], 0.000005, max_relative = 1e-9);
        assert_relative_eq!(c.eval(100.0), f(100.0), max_relative = 1e-13);
    }

    #[test]
    fn high_degree_stays_stable() {
        // A degree-12 fit of a smooth curve: the raw normal equations are
        // singular to working precision here, the Legendre solve is not.
        let t: Vec<f64> = (0..=2016).map(|i| i as f64 / 12.0).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|&x| 7.0 + 12.0 * (1.0 - (-x / 40.0).exp()))
            .collect();
        let c = fit_poly(&t, &y, 12).unwrap();
        let worst = t
            .iter()
            .zip(&y)
            .map(|(&x, &v)| (c.eval(x) - v).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "max error {worst}");
    }

    #[test]
    fn too_few_points_or_one_time_refused() {
        assert!(fit_poly(&[0.0, 1.0, 2.0], &[1.0, 2.0, 3.0], 3).is_err());
        assert!(fit_poly(&[1.0; 5], &[1.0, 2.0, 3.0, 4.0, 5.0], 1).is_err());
        assert!(fit_poly(&[0.0, 0.0, 1.0, 1.0], &[1.0, 2.0, 3.0, 4.0], 3).is_err());
    }
}
