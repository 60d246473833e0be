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
//! detection limit.

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

/// ρ of the withheld effect (0 where nothing is withheld).
pub fn ratio(set: &Set) -> f64 {
    let Some(effect) = &set.truth.effect else {
        return 0.0;
    };
    let truth = &set.truth;
    let v = stacked(&truth.moved);
    let thermal = effect.kind.is_thermal();
    let repeats = truth.poses < truth.rows.len();
    let own = if thermal && repeats {
        // Each pose's own offset: the move less its mean per pose.
        let mut sum = vec![Vector3::zeros(); truth.poses];
        let mut count = vec![0.0; truth.poses];
        for (r, d) in truth.rows.iter().zip(&truth.moved) {
            sum[r.pose] += d;
            count[r.pose] += 1.0;
        }
        let centred: Vec<Vector3<f64>> = truth
            .rows
            .iter()
            .zip(&truth.moved)
            .map(|(r, d)| d - sum[r.pose] / count[r.pose])
            .collect();
        stacked(&centred).norm()
    } else {
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
        let numbers = 3 * truth.poses;
        let cols = if numbers > rank(&full, truth.noise_mm) {
            full
        } else {
            let mut c = lengths;
            c.extend(frame);
            c
        };
        let a = DMatrix::from_columns(&cols);
        orthogonal(&a, &v).norm()
    };
    let kinds = if thermal { 5.0 } else { 3.0 };
    let lambda = detectable_noncentrality(LEVEL / kinds, effect.params.len() as f64, POWER);
    own / (lambda * truth.noise_mm.powi(2)).sqrt()
}
