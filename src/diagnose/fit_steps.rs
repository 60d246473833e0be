//! The numerical steps of the effect fit (`fit.rs`): which parameter
//! directions the data identify, the damped and scaled least-squares
//! steps, and the statistical stopping rule. Kept apart from the fit's
//! bookkeeping of effects and parameters so that each reads alone.

use crate::model::EffectKind;
use nalgebra::{DMatrix, DVector};

/// Relative singular value under which a parameter direction counts as not
/// identifiable on these data.
pub(super) const IDENTIFIABLE: f64 = 1e-5;
/// Largest standard error of an identifiable direction, in typical sizes
/// (the defaults of `data/effects.toml`): real errors run to several times
/// those illustrations (an arm's joint origins off by 0.1 mm where the
/// default is 0.03), and a direction pinned to a fifth of its real size is
/// worth fitting. Its noise floor: the singular value of the scaled
/// columns (mm of the data per typical step) at least the noise over this.
pub(super) const SE_IN_TYPICAL: f64 = 5.0;

/// Parameters the data identify, and why each other one is held. Columns
/// are scaled by each parameter's typical size, so a singular value is how
/// far (mm, over all residuals) the data move when the parameters move one
/// typical size along that direction. A direction that moves them less than
/// the noise `sigma` over [`SE_IN_TYPICAL`] (its standard error would
/// exceed that many typical sizes), or is numerically degenerate, cannot be
/// told from noise: of the parameters that carry it, the one with the
/// smallest plausible bound (`bounds`: each column's effect and bound, in
/// its unit; compared within one effect) is held at zero, and the test
/// repeats. Of two parameters that move the data
/// alike, the one that can plausibly take the larger value is kept (a
/// reflector 31 mm off the flange is the measured point's offset, not a
/// wrist origin 28 mm off). This drops the axis-6 zero without orientation
/// data, c1 against a tracker's z, or a base tilt seen from a single pose,
/// instead of fitting them to huge values.
pub(super) fn identifiable(
    j: &DMatrix<f64>,
    typical: &[f64],
    bounds: &[(EffectKind, f64)],
    sigma: f64,
) -> (Vec<usize>, Vec<(usize, Dropped)>) {
    let scale: Vec<f64> = (0..j.ncols())
        .map(|c| typical.get(c).copied().unwrap_or(1.0))
        .collect();
    let norms: Vec<f64> = j
        .column_iter()
        .zip(&scale)
        .map(|(c, t)| c.norm() * t)
        .collect();
    let mut dropped: Vec<(usize, Dropped)> = Vec::new();
    let mut free: Vec<usize> = Vec::new();
    for (c, &norm) in norms.iter().enumerate() {
        if norm > 1e-9 {
            free.push(c);
        } else {
            let lever = j.column(c).amax();
            dropped.push((c, Dropped::NoLever(lever)));
        }
    }
    // The Gram matrix of the scaled columns, once: the singular values and
    // right singular vectors of any set of columns are the square roots
    // and eigenvectors of its block (a tall SVD per dropped parameter cost
    // seconds on 10,000 rows and 52 parameters). Eigenvalues down to 1e-10
    // of the largest, the threshold below, are far above rounding.
    let scaled = DMatrix::from_fn(j.nrows(), j.ncols(), |r, c| j[(r, c)] * scale[c]);
    let gram = scaled.transpose() * &scaled;
    while !free.is_empty() {
        let block = DMatrix::from_fn(free.len(), free.len(), |a, b| gram[(free[a], free[b])]);
        let eig = block.symmetric_eigen();
        let values: Vec<f64> = eig.eigenvalues.iter().map(|v| v.max(0.0).sqrt()).collect();
        let (imin, smin) =
            values
                .iter()
                .copied()
                .enumerate()
                .fold(
                    (0, f64::INFINITY),
                    |a, (i, v)| if v < a.1 { (i, v) } else { a },
                );
        let smax = values.iter().copied().fold(0.0, f64::max);
        if smin >= (sigma / SE_IN_TYPICAL).max(IDENTIFIABLE * smax) {
            break;
        }
        let row = eig.eigenvectors.column(imin);
        // Of the parameters that carry a good part of the direction (a
        // third of the largest weight or more), the one with the least room
        // (the smallest plausible bound) is held; among equal bounds, the
        // one weighing most, the later in the order of preference on a tie.
        let largest = row.amax();
        // Bounds are compared within one effect only: between effects
        // (an instrument frame against a joint origin) the order of
        // preference decides, as before bounds were known.
        let bound = |c: usize| bounds.get(free[c]).copied();
        let mut worst = 0;
        for c in 0..free.len() {
            if row[c].abs() < largest / 3.0 {
                continue;
            }
            let room = match (bound(c), bound(worst)) {
                (Some((ka, a)), Some((kb, b))) if ka == kb => a.total_cmp(&b),
                _ => std::cmp::Ordering::Equal,
            };
            let better = if row[worst].abs() < largest / 3.0 {
                true
            } else if room != std::cmp::Ordering::Equal {
                room == std::cmp::Ordering::Less
            } else {
                row[c].abs() >= row[worst].abs() * (1.0 - 1e-6)
            };
            if better {
                worst = c;
            }
        }
        let p = free[worst];
        // Its partners: the others that carry a good part of it.
        let partners: Vec<usize> = (0..free.len())
            .filter(|&c| c != worst && row[c].abs() >= largest / 3.0)
            .map(|c| free[c])
            .collect();
        let why = if partners.is_empty() {
            Dropped::Unresolved(sigma / smin.max(1e-300) * scale[p])
        } else {
            Dropped::SameAs((smin / norms[p]).min(1.0), partners)
        };
        dropped.push((p, why));
        free.remove(worst);
    }
    (free, dropped)
}

/// Whether the fit is done: the gradient is negligible, or what a full
/// Gauss–Newton step could still gain is a negligible fraction of one
/// residual's variance (ill-conditioned fits otherwise crawl for ever).
pub(super) fn at_minimum(a: &DMatrix<f64>, g: &DVector<f64>, rss: f64, n_obs: usize) -> bool {
    if gradient_small(a, g, rss) {
        return true;
    }
    match solve_damped(a, g, 1e-12) {
        Some(step) => g.dot(&step) <= 1e-4 * rss / n_obs.max(1) as f64,
        None => false,
    }
}

/// Whether the gradient is negligible: every parameter direction's cosine
/// with the residual is tiny.
pub(super) fn gradient_small(a: &DMatrix<f64>, g: &DVector<f64>, rss: f64) -> bool {
    (0..g.len()).all(|i| {
        let d = a[(i, i)].max(1e-300);
        g[i].abs() <= 1e-7 * (d * rss.max(1e-300)).sqrt()
    })
}

pub(super) fn solve_damped(
    a: &DMatrix<f64>,
    g: &DVector<f64>,
    lambda: f64,
) -> Option<DVector<f64>> {
    let mut m = a.clone();
    for i in 0..m.nrows() {
        m[(i, i)] += lambda * a[(i, i)].max(1e-300);
    }
    m.cholesky().map(|c| c.solve(g))
}

/// Least-squares step J·x ≈ r with column scaling and SVD (rank-safe).
pub(super) fn solve_scaled(j: &DMatrix<f64>, r: &DVector<f64>) -> Option<DVector<f64>> {
    let norms: Vec<f64> = j.column_iter().map(|c| c.norm().max(1e-300)).collect();
    let mut s = j.clone();
    for (c, n) in norms.iter().enumerate() {
        s.column_mut(c).scale_mut(1.0 / n);
    }
    let svd = s.svd(true, true);
    let smax = svd.singular_values.max();
    let x = svd.solve(r, IDENTIFIABLE * smax).ok()?;
    Some(DVector::from_iterator(
        x.len(),
        x.iter().zip(&norms).map(|(v, n)| v / n),
    ))
}

/// Why [`identifiable`] held a column, before it is named.
pub(super) enum Dropped {
    /// The column hardly moves the data at all: its largest entry per unit
    /// of the parameter, mm.
    NoLever(f64),
    /// Its direction moves the data less than the noise over
    /// [`SE_IN_TYPICAL`] typical sizes: the standard error it would have, in
    /// its unit.
    Unresolved(f64),
    /// It moves the data (nearly) as the columns listed do: the share of
    /// its scaled norm along the direction the data do not pin.
    SameAs(f64, Vec<usize>),
}
