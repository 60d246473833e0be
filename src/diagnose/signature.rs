//! Signatures of what the library lacks, tested like its effects: here a
//! growth with the square of the links' temperature rise (a structure whose
//! expansion coefficient grows with temperature, or a warm-up that heats
//! the castings faster than the motors say), which the library's linear
//! expansion only half-follows. It is tested over time, with each pose's
//! own offset, beyond the thermal effects found; the effects that add
//! nothing significant beyond it are not named (they only stood in for it).

use super::fit::{fit, Problem};
use super::stats::{Test, LEVEL};
use super::test_noise::TestNoise;
use crate::model::{Effect, EffectKind};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// A growth with the square of the link temperatures found over time.
#[derive(Debug, Clone, Serialize)]
pub struct QuadraticGrowth {
    /// RMS of what it adds over time, mm.
    pub rms_mm: f64,
    /// Its F test beyond the thermal effects found.
    pub test: Test,
    /// Thermal effects that add nothing significant beyond it, and so are
    /// not named.
    pub replaces: Vec<EffectKind>,
    /// Where the growth adds nothing significant beyond the thermal effects
    /// found either, but takes fewer parameters: their F test beyond it.
    /// The two fit about equally well; both are candidates, and the one
    /// with fewer parameters is taken.
    pub alike: Option<Test>,
}

/// Columns of the residual's derivative along each link's expansion, each
/// row's entry times that link's temperature rise over 10 K: a length that
/// grows with the square of the rise. Centred by pose when the problem is.
pub(crate) fn quadratic_columns(problem: &Problem, rows: &[usize]) -> DMatrix<f64> {
    let mut q = plain_quadratic_columns(problem, rows);
    if problem.centre_poses {
        problem.centre_columns(&mut q, rows);
    }
    q
}

/// [`quadratic_columns`] never centred: what the growth adds to each row's
/// residual itself, zero at the reference temperature.
pub(crate) fn plain_quadratic_columns(problem: &Problem, rows: &[usize]) -> DMatrix<f64> {
    let plain = Problem {
        centre_poses: false,
        ..problem.clone()
    };
    let w = plain.width();
    let r0 = plain.residuals(&[], rows);
    let th = &plain.base.thermal;
    let mut q = DMatrix::zeros(r0.len(), 4);
    for link in 0..4 {
        let mut e = Effect::zero(EffectKind::ExpansionScale);
        let h = 1e-2;
        e.params[link] = h;
        let r1 = plain.residuals(&[e], rows);
        for (k, &i) in rows.iter().enumerate() {
            let rise = th.link_temps(&plain.rows[i].temps)[link] - th.t_ref;
            for d in 0..w {
                q[(k * w + d, link)] = (r1[k * w + d] - r0[k * w + d]) / h * rise / 10.0;
            }
        }
    }
    q
}

/// The numeric Jacobian of the residual along every parameter of
/// `effects` at their values.
pub(crate) fn effects_jacobian(
    problem: &Problem,
    effects: &[Effect],
    rows: &[usize],
) -> DMatrix<f64> {
    let r0 = problem.residuals(effects, rows);
    let mut cols = Vec::new();
    for (ei, e) in effects.iter().enumerate() {
        for p in 0..e.params.len() {
            let h = e.kind.step(p, e.params[p]);
            let mut moved = effects.to_vec();
            moved[ei].params[p] += h;
            cols.push((problem.residuals(&moved, rows) - &r0) / h);
        }
    }
    if cols.is_empty() {
        DMatrix::zeros(r0.len(), 0)
    } else {
        DMatrix::from_columns(&cols)
    }
}

/// Residual sum of squares of `r` less its least-squares fit on `a`.
pub(crate) fn rss_after(a: &DMatrix<f64>, r: &DVector<f64>) -> f64 {
    lstsq(a, r).1
}

/// Least squares of `r` on `a`: the coefficients and the residual sum of
/// squares. Columns are scaled to unit norm (the parameters' units differ
/// by orders), and directions the data cannot tell apart are left out.
pub(crate) fn lstsq(a: &DMatrix<f64>, r: &DVector<f64>) -> (DVector<f64>, f64) {
    match LsqFactor::new(a) {
        Some(f) => f.solve(r),
        None => (DVector::zeros(a.ncols()), r.norm_squared()),
    }
}

/// A tall design `a` factored once for least squares on it: its columns
/// scaled to unit norm, a Householder QR of those, and the SVD of the
/// small triangle R. The scaled design's singular values and right
/// vectors are R's (`a = Q·R`, Q orthonormal), so a solve cut at the same
/// singular values gives the coefficients of an SVD of the whole design
/// to rounding; but the SVD of a 6,000 × 50 design built its 6,000 × 50
/// left vectors by Givens rotations, and was half of a diagnosis (the
/// joint signatures' detection limits, one solve per column on one
/// calibration's design).
pub(crate) struct LsqFactor {
    scaled: DMatrix<f64>,
    norms: Vec<f64>,
    qr: nalgebra::linalg::QR<f64, nalgebra::Dyn, nalgebra::Dyn>,
    svd: Option<nalgebra::linalg::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>>,
}

impl LsqFactor {
    /// `None` for a design without columns.
    pub(crate) fn new(a: &DMatrix<f64>) -> Option<LsqFactor> {
        if a.ncols() == 0 {
            return None;
        }
        let norms: Vec<f64> = a.column_iter().map(|c| c.norm().max(1e-300)).collect();
        let scaled = DMatrix::from_fn(a.nrows(), a.ncols(), |i, c| a[(i, c)] / norms[c]);
        // A design wider than tall (never one of the fits here) keeps
        // the SVD of the whole.
        let qr = scaled.clone().qr();
        let svd = (a.nrows() >= a.ncols()).then(|| qr.r().svd(true, true));
        Some(LsqFactor {
            scaled,
            norms,
            qr,
            svd,
        })
    }

    /// The coefficients of `r` on the design and the residual sum of
    /// squares (all zero and `r`'s own where the solve fails).
    pub(crate) fn solve(&self, r: &DVector<f64>) -> (DVector<f64>, f64) {
        let x = match &self.svd {
            Some(svd) => {
                let mut qtr = r.clone();
                self.qr.q_tr_mul(&mut qtr);
                let top = qtr.rows(0, self.scaled.ncols()).into_owned();
                let smax = svd.singular_values.max();
                svd.solve(&top, 1e-9 * smax)
            }
            None => {
                let svd = self.scaled.clone().svd(true, true);
                let smax = svd.singular_values.max();
                svd.solve(r, 1e-9 * smax)
            }
        };
        match x {
            Ok(x) => {
                let rss = (r - &self.scaled * &x).norm_squared();
                (DVector::from_fn(x.len(), |c, _| x[c] / self.norms[c]), rss)
            }
            Err(_) => (DVector::zeros(self.scaled.ncols()), r.norm_squared()),
        }
    }
}

/// `a` with the columns `extra` after its own.
pub(crate) fn hcat(a: &DMatrix<f64>, extra: &[DVector<f64>]) -> DMatrix<f64> {
    let mut cols: Vec<DVector<f64>> = a.column_iter().map(|c| c.into_owned()).collect();
    cols.extend(extra.iter().cloned());
    DMatrix::from_columns(&cols)
}

/// Test a growth with the square of the link temperatures beyond the
/// thermal `effects` fitted on the (pose-centred) `problem`, linearised at
/// their values. `None` where it is not significant at `level` (the
/// family's: it names `unexplained`); the library's effects against it are
/// tested at the stage's [`LEVEL`].
pub fn quadratic_growth(
    problem: &Problem,
    effects: &[Effect],
    noise: &TestNoise,
    level: f64,
) -> Option<QuadraticGrowth> {
    let rows: Vec<usize> = (0..problem.rows.len()).collect();
    let r = problem.residuals(effects, &rows);
    let q = quadratic_columns(problem, &rows);
    let j = effects_jacobian(problem, effects, &rows);
    let q_cols: Vec<DVector<f64>> = q.column_iter().map(|c| c.into_owned()).collect();
    let with_q = |j: &DMatrix<f64>| hcat(j, &q_cols);
    let rss_model = rss_after(&j, &r);
    let rss_full = rss_after(&with_q(&j), &r);
    let test = Test::nested(
        rss_model,
        rss_full,
        q.ncols(),
        noise.sigma2,
        noise.dof,
        level,
    );
    if !test.significant() {
        // The other way round: the thermal effects found against the growth
        // alone (linear in its parameters at zero). Neither adding anything
        // beyond the other, the one with fewer parameters is taken, and the
        // other named beside it: a scaled expansion with a lag follows a
        // square of a saturating warm-up closely.
        if effects.is_empty() || j.ncols() <= q.ncols() {
            return None;
        }
        let r0 = problem.residuals(&[], &rows);
        let rss_q = rss_after(&q, &r0);
        let alike = Test::nested(rss_q, rss_full, j.ncols(), noise.sigma2, noise.dof, LEVEL);
        let alone = Test::nested(
            r0.norm_squared(),
            rss_q,
            q.ncols(),
            noise.sigma2,
            noise.dof,
            level,
        );
        if alike.significant() || !alone.significant() {
            return None;
        }
        return Some(QuadraticGrowth {
            rms_mm: ((r0.norm_squared() - rss_q).max(0.0) / rows.len().max(1) as f64).sqrt(),
            test: alone,
            replaces: effects.iter().map(|e| e.kind).collect(),
            alike: Some(alike),
        });
    }
    // What the quadratic part adds: the fit on the full design less the
    // fit on the effects alone, over the rows.
    let rms_mm = ((rss_model - rss_full).max(0.0) / rows.len().max(1) as f64).sqrt();
    // Each effect against the others refitted with the growth: one that
    // adds nothing significant beyond them only stood in for it.
    let mut replaces = Vec::new();
    for e in effects {
        let others: Vec<EffectKind> = effects
            .iter()
            .map(|x| x.kind)
            .filter(|k| *k != e.kind)
            .collect();
        let refitted = match others.as_slice() {
            [] => Vec::new(),
            kinds => match fit(problem, &rows, kinds) {
                Ok(f) => f.effects,
                Err(_) => continue,
            },
        };
        let r_others = problem.residuals(&refitted, &rows);
        let j_others = effects_jacobian(problem, &refitted, &rows);
        let t = Test::nested(
            rss_after(&with_q(&j_others), &r_others),
            rss_full,
            e.params.len(),
            noise.sigma2,
            noise.dof,
            LEVEL,
        );
        if !t.significant() {
            replaces.push(e.kind);
        }
    }
    Some(QuadraticGrowth {
        rms_mm,
        test,
        replaces,
        alike: None,
    })
}
