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
/// T(0) is fixed to that value instead of fitted. Time constants are kept
/// between [`TAU_MIN`] and [`TAU_MAX_SPANS`] times the recorded span.
pub fn fit_saturating(
    t: &[f64],
    y: &[f64],
    n_terms: usize,
    pin_t0: Option<f64>,
) -> Result<SatCurve> {
    if let Some(v) = pin_t0.filter(|v| !v.is_finite()) {
        return Err(Error::usage(format!(
            "T(0) pinned at {v}: not a temperature"
        )));
    }
    if !(1..=2).contains(&n_terms) {
        return Err(Error::usage(
            "saturating models have one or two time constants",
        ));
    }
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
    let mut problem = Problem {
        t: t[..n].to_vec(),
        y: y[..n].to_vec(),
        pin_t0,
        ln_tau_lo: TAU_MIN.ln(),
        ln_tau_hi: (TAU_MAX_SPANS * span).ln(),
        u: DVector::zeros(n_terms),
    };
    let start = grid_start(&problem, span)?;
    problem.set_params(&start);
    let (problem, report) = LevenbergMarquardt::new()
        .with_patience(200)
        .minimize(problem);
    let curve = problem.curve();
    let finite = curve.as_ref().is_some_and(|c| {
        c.t0.is_finite()
            && c.terms
                .iter()
                .all(|k| k.delta.is_finite() && k.tau.is_finite() && k.tau > 0.0)
    });
    let range = {
        let (lo, hi) = problem
            .y
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        hi - lo
    };
    match curve {
        Some(c) if report.termination.was_successful() && finite => {
            match degenerate(&c, range, TAU_MAX_SPANS * span) {
                Some(why) => Err(Error::new(
                    ErrorKind::NoConvergence,
                    format!("the {n_terms}-time-constant fit is degenerate: {why}"),
                )),
                None => Ok(c),
            }
        }
        _ => Err(Error::new(
            ErrorKind::NoConvergence,
            format!(
                "the {n_terms}-time-constant fit did not converge ({:?})",
                report.termination
            ),
        )),
    }
}

/// Why a converged fit is still no result, if it is not one: terms that
/// cancel (ΔT of opposite signs, each far larger than the rise the data
/// show), time constants that merged, or a term whose time constant ran to
/// its bound (a straight line over the record: its ΔT says nothing). A
/// recording shorter than its time constants gives these; the curve would
/// forecast anything.
fn degenerate(c: &SatCurve, range: f64, tau_max: f64) -> Option<String> {
    let big = (MAX_AMPLITUDE_RANGES * range).max(1e-9);
    if c.terms.len() == 2 {
        let (a, b) = (c.terms[0], c.terms[1]);
        if a.delta.signum() != b.delta.signum() && a.delta.abs().min(b.delta.abs()) > big {
            return Some(format!(
                "its terms cancel ({:+.3} and {:+.3} °C, where the data rise {range:.3} °C)",
                a.delta, b.delta
            ));
        }
        if b.tau / a.tau < MERGED_TAU_RATIO && a.delta.abs().max(b.delta.abs()) > big {
            return Some(format!(
                "its time constants merged ({:.1} and {:.1} min)",
                a.tau, b.tau
            ));
        }
    }
    for k in &c.terms {
        if k.tau >= 0.99 * tau_max {
            return Some(format!(
                "a time constant ran to its bound ({:.0} min) with a rise of {:.1} °C: the recording is too short to tell it",
                k.tau, k.delta
            ));
        }
    }
    None
}

/// A term larger than this many times the rise the data show is not one
/// the data can support (see [`degenerate`]).
const MAX_AMPLITUDE_RANGES: f64 = 3.0;
/// Two time constants closer than this ratio are one.
const MERGED_TAU_RATIO: f64 = 1.05;

/// Shortest time constant a fit may take, minutes (well below a 5-s sample
/// step: a jump).
pub const TAU_MIN: f64 = 0.01;
/// Longest time constant, in recorded spans (beyond it the term is a
/// straight line over the record and its ΔT is not identifiable).
pub const TAU_MAX_SPANS: f64 = 100.0;

/// Variable projection: for fixed time constants the model is linear in T0
/// and the ΔT, which are solved exactly; Levenberg–Marquardt searches only
/// the time constants. This stays well posed when two time constants merge
/// or one runs to its bound, where a search over all parameters drifts off
/// to ΔT1 = −ΔT2 → ∞.
#[derive(Debug, Clone)]
struct Problem {
    t: Vec<f64>,
    y: Vec<f64>,
    pin_t0: Option<f64>,
    ln_tau_lo: f64,
    ln_tau_hi: f64,
    /// Unbounded parameters, one per term: ln τ = lo + (hi − lo)·σ(u).
    u: DVector<f64>,
}

impl Problem {
    fn tau(&self, u: f64) -> f64 {
        let sig = 1.0 / (1.0 + (-u).exp());
        (self.ln_tau_lo + (self.ln_tau_hi - self.ln_tau_lo) * sig).exp()
    }

    fn u_of(&self, tau: f64) -> f64 {
        let f = ((tau.ln() - self.ln_tau_lo) / (self.ln_tau_hi - self.ln_tau_lo))
            .clamp(1e-9, 1.0 - 1e-9);
        (f / (1.0 - f)).ln()
    }

    fn taus(&self, u: &DVector<f64>) -> Vec<f64> {
        u.iter().map(|&v| self.tau(v)).collect()
    }

    /// Best T0 (unless pinned) and ΔT for fixed time constants, and the
    /// residuals (model − data).
    fn linear_for(&self, taus: &[f64]) -> Option<(DVector<f64>, DVector<f64>)> {
        let o = usize::from(self.pin_t0.is_none());
        let base = self.pin_t0.unwrap_or(0.0);
        let mut cols: Vec<Vec<f64>> = Vec::with_capacity(o + taus.len());
        if o == 1 {
            cols.push(vec![1.0; self.t.len()]);
        }
        for tau in taus {
            cols.push(self.t.iter().map(|&t| -(-t / tau).exp_m1()).collect());
        }
        let b: Vec<f64> = self.y.iter().map(|v| v - base).collect();
        let x = small_least_squares(&cols, &b)?;
        let r = DVector::from_iterator(
            b.len(),
            (0..b.len()).map(|i| cols.iter().zip(&x).map(|(c, k)| c[i] * k).sum::<f64>() - b[i]),
        );
        let x = DVector::from_vec(x);
        (x.iter().all(|v| v.is_finite()) && r.iter().all(|v| v.is_finite())).then_some((x, r))
    }

    fn curve(&self) -> Option<SatCurve> {
        let taus = self.taus(&self.u);
        let (x, _) = self.linear_for(&taus)?;
        let o = usize::from(self.pin_t0.is_none());
        let mut terms: Vec<SatTerm> = taus
            .iter()
            .enumerate()
            .map(|(j, &tau)| SatTerm {
                delta: x[o + j],
                tau,
            })
            .collect();
        terms.sort_by(|a, b| a.tau.total_cmp(&b.tau));
        Some(SatCurve {
            t0: self.pin_t0.unwrap_or_else(|| x[0]),
            terms,
        })
    }
}

/// Least squares with a few columns by modified Gram–Schmidt (run twice for
/// orthogonality): stable like QR, and plain loops rather than a general
/// matrix decomposition, which matters as it runs thousands of times per
/// fit. A column that is (nearly) a combination of earlier ones, as when two
/// time constants merge, gets coefficient 0.
fn small_least_squares(cols: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let k = cols.len();
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
    let mut q: Vec<Vec<f64>> = Vec::with_capacity(k);
    let mut r = vec![vec![0.0; k]; k];
    let mut kept = vec![false; k];
    for j in 0..k {
        let mut v = cols[j].clone();
        let norm0 = dot(&v, &v).sqrt();
        for _ in 0..2 {
            for (i, qi) in q.iter().enumerate() {
                if !kept[i] {
                    continue;
                }
                let c = dot(qi, &v);
                r[i][j] += c;
                v.iter_mut().zip(qi).for_each(|(a, b)| *a -= c * b);
            }
        }
        let norm = dot(&v, &v).sqrt();
        if norm > 1e-10 * norm0 && norm > 0.0 {
            v.iter_mut().for_each(|a| *a /= norm);
            r[j][j] = norm;
            kept[j] = true;
        }
        q.push(v);
    }
    // Back substitution over the kept columns.
    let qb: Vec<f64> = q.iter().map(|qi| dot(qi, b)).collect();
    let mut x = vec![0.0; k];
    for j in (0..k).rev() {
        if !kept[j] {
            continue;
        }
        let s: f64 = (j + 1..k)
            .filter(|&l| kept[l])
            .map(|l| r[j][l] * x[l])
            .sum();
        x[j] = (qb[j] - s) / r[j][j];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// Starting point: the best of a log-spaced grid of time constants from
/// 0.5 min to 20 times the recorded span.
fn grid_start(problem: &Problem, span: f64) -> Result<DVector<f64>> {
    let (lo, hi) = (0.5f64.ln(), (20.0 * span).max(1.0).ln());
    let steps = 24;
    let grid: Vec<f64> = (0..steps)
        .map(|i| (lo + (hi - lo) * i as f64 / (steps - 1) as f64).exp())
        .collect();
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut consider = |taus: &[f64]| {
        if let Some((_, r)) = problem.linear_for(taus) {
            let sse = r.norm_squared();
            if best.as_ref().is_none_or(|(_, b)| sse < *b) {
                best = Some((taus.to_vec(), sse));
            }
        }
    };
    match problem.u.len() {
        1 => grid.iter().for_each(|&tau| consider(&[tau])),
        _ => {
            for (i, &t1) in grid.iter().enumerate() {
                for &t2 in &grid[i + 1..] {
                    consider(&[t1, t2]);
                }
            }
        }
    }
    let (taus, _) = best.ok_or_else(|| {
        Error::new(
            ErrorKind::NoConvergence,
            "no starting point for the saturating fit (data not finite?)",
        )
    })?;
    Ok(DVector::from_iterator(
        taus.len(),
        taus.iter().map(|&tau| problem.u_of(tau)),
    ))
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.u.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.u.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.linear_for(&self.taus(&self.u)).map(|(_, r)| r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        // Central differences of the projected residuals: two linear solves
        // per time constant, cheaper to get right than the analytic VarPro
        // Jacobian and accurate enough for the search.
        let mut jac = DMatrix::zeros(self.t.len(), self.u.len());
        for j in 0..self.u.len() {
            let h = 1e-6 * self.u[j].abs().max(1.0);
            let mut up = self.u.clone();
            let mut down = self.u.clone();
            up[j] += h;
            down[j] -= h;
            let (_, ru) = self.linear_for(&self.taus(&up))?;
            let (_, rd) = self.linear_for(&self.taus(&down))?;
            jac.set_column(j, &((ru - rd) / (2.0 * h)));
        }
        Some(jac)
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
    fn overflowing_data_is_no_convergence_not_a_curve() {
        let t: Vec<f64> = (0..20).map(f64::from).collect();
        let y: Vec<f64> = (0..20)
            .map(|i| if i % 2 == 0 { 1e308 } else { -1e308 })
            .collect();
        let e = fit_saturating(&t, &y, 2, None).unwrap_err();
        assert_eq!(e.kind, ErrorKind::NoConvergence);
    }

    #[test]
    fn too_few_points_refused() {
        assert!(fit_saturating(&[0.0, 1.0], &[7.0, 8.0], 1, None).is_err());
        assert!(fit_saturating(&[0.0, 1.0, 2.0, 3.0], &[7.0, 8.0, 9.0, 9.5], 2, None).is_err());
    }
}
