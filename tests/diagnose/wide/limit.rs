//! The detection limit of the withheld effect, computed from the truth: how
//! far its move of the measured points stands out of what the nuisance
//! could take up, against the noise, as a multiple of the smallest such
//! move a test of its shape would reveal.
//!
//! The definition is the library's (`src/diagnose/detect.rs`, docs/
//! diagnose.md): the effect's move less its least-squares fit by the rest
//! of the model, whose squared norm over the noise variance is the
//! noncentrality of its F test; at the limit that noncentrality is the one
//! an F test at the stage's level (1 % shared among the effects of the
//! stage: 5 thermal, 3 static) detects with 90 % power. What the rest is:
//! where poses are measured again and again, each pose's own offset for a
//! thermal effect (the over-time stage); otherwise, and for static effects,
//! the geometric calibration (zeros, lengths and, where the poses give more
//! numbers than it has identifiable directions, every joint origin and the
//! measured point) and the tracker frame. Computed here from the true
//! temperatures and the true noise, not the diagnosis's: whether the data
//! could reveal the effect at all, whatever the diagnosis knows.
//!
//! The ratio ρ = ‖own move‖ / √(λ·σ²): below 1, the effect is below its
//! detection limit. The same for the drift in time of a set without
//! temperature columns (`world::Truth::drift`), taken as a thermal move of
//! the expansion's four parameters.

use super::world::{points, Set};
use nalgebra::{DMatrix, DVector, Vector3};
use rapidtherm::diagnose::stats::{detectable_noncentrality, LEVEL, POWER};
use rapidtherm::model::{Effect, EffectKind};

/// `v` less its least-squares fit on the columns of `a` (columns scaled,
/// directions below 1e-9 of the largest dropped).
fn orthogonal(a: &DMatrix<f64>, v: &DVector<f64>) -> DVector<f64> {
    if a.ncols() == 0 {
        return v.clone();
    }
    let norms: Vec<f64> = a.column_iter().map(|c| c.norm().max(1e-300)).collect();
    let scaled = DMatrix::from_fn(a.nrows(), a.ncols(), |i, c| a[(i, c)] / norms[c]);
    let svd = scaled.clone().svd(true, true);
    let smax = svd.singular_values.max();
    match svd.solve(v, 1e-9 * smax) {
        Ok(x) => v - scaled * x,
        Err(_) => v.clone(),
    }
}

fn stacked(v: &[Vector3<f64>]) -> DVector<f64> {
    DVector::from_iterator(v.len() * 3, v.iter().flat_map(|d| [d.x, d.y, d.z]))
}

/// Numeric columns of `kind`'s parameters `params` at zero on the
/// nominal arm (mm of the measured point per unit): linear at the sizes of
/// a real arm's errors, so the geometry drawn does not change them.
fn columns(set: &Set, kind: EffectKind, params: std::ops::Range<usize>) -> Vec<DVector<f64>> {
    let at = |e: &Effect| {
        stacked(&points(
            &set.base,
            &set.history,
            &set.truth.rows,
            std::slice::from_ref(e),
        ))
    };
    let zero = at(&Effect::zero(kind));
    params
        .map(|i| {
            let mut e = Effect::zero(kind);
            let h = 1e-3;
            e.params[i] = h;
            (at(&e) - &zero) / h
        })
        .collect()
}

fn rank(cols: &[DVector<f64>], noise_mm: f64) -> usize {
    if cols.is_empty() {
        return 0;
    }
    let a = DMatrix::from_columns(cols);
    let sv = a.svd(false, false).singular_values;
    let smax = sv.max();
    sv.iter()
        .filter(|&&s| s > 1e-6 * smax && s > noise_mm * 1e-3)
        .count()
}

/// The norm of `moved` beyond what the rest of the model takes up: each
/// pose's own offset for a thermal move where poses are measured again and
/// again, else the geometric calibration and the tracker frame.
fn own(set: &Set, moved: &[Vector3<f64>], thermal: bool) -> f64 {
    let truth = &set.truth;
    let repeats = truth.poses < truth.rows.len();
    if thermal && repeats {
        let mut sum = vec![Vector3::zeros(); truth.poses];
        let mut count = vec![0.0; truth.poses];
        for (r, d) in truth.rows.iter().zip(moved) {
            sum[r.pose] += d;
            count[r.pose] += 1.0;
        }
        let centred: Vec<Vector3<f64>> = truth
            .rows
            .iter()
            .zip(moved)
            .map(|(r, d)| d - sum[r.pose] / count[r.pose])
            .collect();
        return stacked(&centred).norm();
    }
    let n_geom = EffectKind::GeometryOffset.params().len();
    let lengths = columns(set, EffectKind::GeometryOffset, 0..13);
    let origins = columns(set, EffectKind::GeometryOffset, 13..n_geom);
    let frame = columns(
        set,
        EffectKind::TrackerFrame,
        0..EffectKind::TrackerFrame.params().len(),
    );
    let mut full: Vec<DVector<f64>> = lengths.clone();
    full.extend(origins);
    full.extend(frame.iter().cloned());
    let cols = if 3 * truth.poses > rank(&full, truth.noise_mm) {
        full
    } else {
        let mut c = lengths;
        c.extend(frame);
        c
    };
    orthogonal(&DMatrix::from_columns(&cols), &stacked(moved)).norm()
}

/// ‖own move‖ / √(λ·σ²) of a move of `params` parameters.
fn ratio_of(set: &Set, moved: &[Vector3<f64>], thermal: bool, params: usize) -> f64 {
    let kinds = if thermal { 5.0 } else { 3.0 };
    let lambda = detectable_noncentrality(LEVEL / kinds, params as f64, POWER);
    own(set, moved, thermal) / (lambda * set.truth.noise_mm.powi(2)).sqrt()
}

/// ρ of the withheld effect (0 where nothing is withheld).
pub fn ratio(set: &Set) -> f64 {
    match &set.truth.effect {
        Some(e) => ratio_of(set, &set.truth.moved, e.kind.is_thermal(), e.params.len()),
        None => 0.0,
    }
}

/// ρ of the drift in time of a set without temperature columns, judged as
/// a thermal move of the expansion's shape (four parameters); 0 with the
/// columns.
pub fn drift_ratio(set: &Set) -> f64 {
    if set.truth.drift.iter().all(|d| d.norm() == 0.0) {
        return 0.0;
    }
    ratio_of(set, &set.truth.drift, true, 4)
}
