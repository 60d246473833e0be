//! Saturating heating curves: a motor heated at constant mean power in a
//! room at constant temperature approaches a steady temperature
//! exponentially. First order: T(t) = T0 + ΔT·(1 − e^(−t/τ)); two time
//! constants (a fast winding and a slow housing): T0 + ΔT1·(1 − e^(−t/τ1)) +
//! ΔT2·(1 − e^(−t/τ2)). Unlike a polynomial, these stay bounded for any t.
//!
//! Fitted by nonlinear least squares (Levenberg–Marquardt), started from the
//! best point of a grid over the time constants (for fixed τ the model is
//! linear in T0 and the ΔT, solved exactly), which avoids the local minima a
//! fixed starting guess runs into.

use crate::error::{Error, ErrorKind, Result};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Owned};

/// One exponential term: ΔT·(1 − e^(−t/τ)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SatTerm {
    /// Rise of the term at saturation, °C.
    pub delta: f64,
    /// Time constant, minutes.
    pub tau: f64,
}

/// T0 plus a sum of exponential terms, sorted by time constant.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SatCurve {
    /// Temperature at t = 0, °C.
    pub t0: f64,
    pub terms: Vec<SatTerm>,
}

impl SatCurve {
    pub fn eval(&self, t: f64) -> f64 {
        // 1 − e^(−x) as −expm1(−x): exact 0 at t = 0, so T(0) = T0 exactly.
        self.t0
            + self
                .terms
                .iter()
                .map(|k| k.delta * -(-t / k.tau).exp_m1())
                .sum::<f64>()
    }

    /// The temperature the curve tends to, T0 + ΣΔT.
    pub fn steady(&self) -> f64 {
        self.t0 + self.terms.iter().map(|k| k.delta).sum::<f64>()
    }
}

/// Fit `n_terms` exponential terms (1 or 2) to the points. With `pin_t0`,
/// T(0) is fixed to that value instead of fitted.
pub fn fit_saturating(
    t: &[f64],
    y: &[f64],
    n_terms: usize,
    pin_t0: Option<f64>,
) -> Result<SatCurve> {
    let n = t.len().min(y.len());
    let params = n_terms * 2 + usize::from(pin_t0.is_none());
    if n < params {
        return Err(Error::input(format!(
            "{n} points, but the {n_terms}-time-constant model has {params} parameters"
        )));
    }
    let span = t[..n].iter().copied().fold(0.0, f64::max);
    if span <= 0.0 {
        return Err(Error::input(
            "time does not advance past 0 min: no time constant can be fitted",
        ));
    }
    let problem = Problem {
        t: t[..n].to_vec(),
        y: y[..n].to_vec(),
        pin_t0,
        n_terms,
        p: DVector::zeros(params),
    };
    let start = grid_start(&problem, span)?;
    let mut problem = problem;
    problem.set_params(&start);
    let (problem, report) = LevenbergMarquardt::new()
        .with_patience(200)
        .minimize(problem);
    let curve = problem.curve();
    let finite = curve.t0.is_finite()
        && curve
            .terms
            .iter()
            .all(|k| k.delta.is_finite() && k.tau.is_finite() && k.tau > 0.0);
    if !report.termination.was_successful() || !finite {
        return Err(Error::new(
            ErrorKind::NoConvergence,
            format!(
                "the {n_terms}-time-constant fit did not converge ({:?})",
                report.termination
            ),
        ));
    }
    Ok(curve)
}

#[derive(Debug, Clone)]
struct Problem {
    t: Vec<f64>,
    y: Vec<f64>,
    pin_t0: Option<f64>,
    n_terms: usize,
    /// [T0 (unless pinned), ΔT1, ln τ1, ΔT2, ln τ2 ...]
    p: DVector<f64>,
}

impl Problem {
    fn offset(&self) -> usize {
        usize::from(self.pin_t0.is_none())
    }

    fn curve_from(&self, p: &DVector<f64>) -> SatCurve {
        let o = self.offset();
        let mut terms: Vec<SatTerm> = (0..self.n_terms)
            .map(|j| SatTerm {
                delta: p[o + 2 * j],
                tau: p[o + 2 * j + 1].exp(),
            })
            .collect();
        terms.sort_by(|a, b| a.tau.total_cmp(&b.tau));
        SatCurve {
            t0: self.pin_t0.unwrap_or_else(|| p[0]),
            terms,
        }
    }

    fn curve(&self) -> SatCurve {
        self.curve_from(&self.p)
    }

    /// Best linear fit of T0 and the ΔT for fixed time constants: returns
    /// the parameter vector and its sum of squared residuals.
    fn linear_for(&self, taus: &[f64]) -> Option<(DVector<f64>, f64)> {
        let o = self.offset();
        let cols = o + taus.len();
        let base = self.pin_t0.unwrap_or(0.0);
        let a = DMatrix::from_fn(self.t.len(), cols, |i, c| {
            if c < o {
                1.0
            } else {
                -(-self.t[i] / taus[c - o]).exp_m1()
            }
        });
        let b = DVector::from_iterator(self.y.len(), self.y.iter().map(|v| v - base));
        let x = a.clone().svd(true, true).solve(&b, 1e-12).ok()?;
        let sse = (a * &x - b).norm_squared();
        let mut p = DVector::zeros(o + 2 * taus.len());
        if o == 1 {
            p[0] = x[0];
        }
        for (j, tau) in taus.iter().enumerate() {
            p[o + 2 * j] = x[o + j];
            p[o + 2 * j + 1] = tau.ln();
        }
        sse.is_finite().then_some((p, sse))
    }
}

/// Starting point: the best of a log-spaced grid of time constants from
/// 0.5 min to 20 times the recorded span.
fn grid_start(problem: &Problem, span: f64) -> Result<DVector<f64>> {
    let (lo, hi) = (0.5f64.ln(), (20.0 * span).max(1.0).ln());
    let steps = 24;
    let grid: Vec<f64> = (0..steps)
        .map(|i| (lo + (hi - lo) * i as f64 / (steps - 1) as f64).exp())
        .collect();
    let mut best: Option<(DVector<f64>, f64)> = None;
    let mut consider = |taus: &[f64]| {
        if let Some((p, sse)) = problem.linear_for(taus) {
            if best.as_ref().is_none_or(|(_, b)| sse < *b) {
                best = Some((p, sse));
            }
        }
    };
    match problem.n_terms {
        1 => grid.iter().for_each(|&tau| consider(&[tau])),
        _ => {
            for (i, &t1) in grid.iter().enumerate() {
                for &t2 in &grid[i + 1..] {
                    consider(&[t1, t2]);
                }
            }
        }
    }
    best.map(|(p, _)| p).ok_or_else(|| {
        Error::new(
            ErrorKind::NoConvergence,
            "no starting point for the saturating fit (data not finite?)",
        )
    })
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.p.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.p.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        // Unsorted evaluation straight from the parameters.
        let o = self.offset();
        let t0 = self.pin_t0.unwrap_or_else(|| self.p[0]);
        let r = DVector::from_iterator(
            self.t.len(),
            self.t.iter().zip(&self.y).map(|(&t, &y)| {
                let mut v = t0;
                for j in 0..self.n_terms {
                    let tau = self.p[o + 2 * j + 1].exp();
                    v += self.p[o + 2 * j] * -(-t / tau).exp_m1();
                }
                v - y
            }),
        );
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let o = self.offset();
        let mut jac = DMatrix::zeros(self.t.len(), self.p.len());
        for (i, &t) in self.t.iter().enumerate() {
            if o == 1 {
                jac[(i, 0)] = 1.0;
            }
            for j in 0..self.n_terms {
                let delta = self.p[o + 2 * j];
                let tau = self.p[o + 2 * j + 1].exp();
                let e = (-t / tau).exp();
                jac[(i, o + 2 * j)] = -(-t / tau).exp_m1();
                // d/d(ln τ) of ΔT·(1 − e^(−t/τ)) = −ΔT·e^(−t/τ)·t/τ
                jac[(i, o + 2 * j + 1)] = -delta * e * t / tau;
            }
        }
        jac.iter().all(|v| v.is_finite()).then_some(jac)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn times() -> Vec<f64> {
        (0..=2016).map(|i| i as f64 / 12.0).collect()
    }

    #[test]
    fn first_order_recovers_parameters() {
        let t = times();
        let y: Vec<f64> = t
            .iter()
            .map(|&x| 7.2 + 11.5 * (1.0 - (-x / 47.0).exp()))
            .collect();
        let c = fit_saturating(&t, &y, 1, None).unwrap();
        assert_relative_eq!(c.t0, 7.2, max_relative = 1e-8);
        assert_relative_eq!(c.terms[0].delta, 11.5, max_relative = 1e-8);
        assert_relative_eq!(c.terms[0].tau, 47.0, max_relative = 1e-8);
    }

    #[test]
    fn two_tau_recovers_parameters_with_pinned_start() {
        let t = times();
        let y: Vec<f64> = t
            .iter()
            .map(|&x| 7.0 + 4.0 * (1.0 - (-x / 6.0).exp()) + 20.0 * (1.0 - (-x / 90.0).exp()))
            .collect();
        let c = fit_saturating(&t, &y, 2, Some(7.0)).unwrap();
        assert_eq!(c.eval(0.0), 7.0);
        assert_relative_eq!(c.terms[0].tau, 6.0, max_relative = 1e-6);
        assert_relative_eq!(c.terms[0].delta, 4.0, max_relative = 1e-6);
        assert_relative_eq!(c.terms[1].tau, 90.0, max_relative = 1e-6);
        assert_relative_eq!(c.terms[1].delta, 20.0, max_relative = 1e-6);
        assert_relative_eq!(c.steady(), 31.0, max_relative = 1e-6);
    }

    #[test]
    fn too_few_points_refused() {
        assert!(fit_saturating(&[0.0, 1.0], &[7.0, 8.0], 1, None).is_err());
        assert!(fit_saturating(&[0.0, 1.0, 2.0, 3.0], &[7.0, 8.0, 9.0, 9.5], 2, None).is_err());
    }
}
