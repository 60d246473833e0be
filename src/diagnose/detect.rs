//! The detection limit of every effect of the library: the smallest
//! magnitude these poses, times and noise would have revealed, at the
//! stage's level with 90 % power, beyond the rest of the model the
//! diagnosis ended with. Each effect is taken along its default parameters
//! (its shape), its size said as the largest displacement of the flange at
//! the calibration pose over the data's temperatures and times (static
//! effects: at the cold start).

use super::fit::Problem;
use super::forward::TestNoise;
use super::signature::effects_jacobian;
use super::stats::{detectable_noncentrality, LEVEL, POWER};
use crate::model::{predict, Effect, EffectKind, RowState};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// The smallest size of one effect the data would have revealed.
#[derive(Debug, Clone, Serialize)]
pub struct DetectionLimit {
    pub effect: EffectKind,
    /// Flange displacement at the calibration pose, mm.
    pub flange_mm: f64,
    /// The same as a multiple of the effect's default parameters.
    pub of_default: f64,
}

/// `v` less its least-squares fit on the columns of `a`.
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

/// Detection limits of every effect not fixed in the model in use, beyond
/// `found` (the effects the diagnosis fitted, in their fitted values) on
/// `problem` (whose own fixed effects are the model in use). Thermal
/// effects are judged over time (each pose's own offset taken out), static
/// ones on the whole gap.
pub fn limits(problem: &Problem, found: &[Effect], noise: &TestNoise) -> Vec<DetectionLimit> {
    let rows: Vec<usize> = (0..problem.rows.len()).collect();
    let mut out = Vec::new();
    for centred in [true, false] {
        let p = Problem {
            centre_poses: centred,
            ..problem.clone()
        };
        let kinds: Vec<EffectKind> = EffectKind::ALL
            .into_iter()
            .filter(|k| k.is_thermal() == centred)
            .filter(|k| !problem.fixed.iter().any(|e| e.kind == *k))
            .collect();
        let level = LEVEL / kinds.len().max(1) as f64;
        for kind in kinds {
            // Beyond everything found but the effect itself: what would
            // have revealed it had it not been named.
            let others: Vec<Effect> = found.iter().filter(|e| e.kind != kind).cloned().collect();
            let model = effects_jacobian(&p, &others, &rows);
            let r0 = p.residuals(&others, &rows);
            let shape = Effect::with_defaults(kind);
            let mut with = others.clone();
            with.push(shape.clone());
            let moved = &r0 - p.residuals(&with, &rows);
            let own = orthogonal(&model, &moved).norm();
            if own <= 1e-12 {
                continue;
            }
            let lambda = detectable_noncentrality(level, kind.params().len() as f64, POWER);
            let m = (lambda * noise.sigma2).sqrt() / own;
            let sized = Effect {
                kind,
                params: shape.params.iter().map(|v| v * m).collect(),
            };
            // The largest displacement of the flange at the calibration
            // pose over the rows' temperatures and times (a lag shows
            // early, an expansion late); static effects at the cold start.
            let lags = crate::model::LinkLags::new(&problem.history, std::slice::from_ref(&sized));
            let at = |temps: [f64; 6], time: f64| {
                let state = RowState {
                    q: [0.0; 6],
                    temps,
                    lagged: lags.as_ref().map(|l| l.at(time)),
                };
                let a = predict(&problem.base, std::slice::from_ref(&sized), &state);
                let b = predict(&problem.base, &[], &state);
                (a.translation.vector - b.translation.vector).norm()
            };
            let flange_mm = if centred {
                problem
                    .rows
                    .iter()
                    .map(|r| at(r.temps, r.time_min))
                    .fold(0.0, f64::max)
            } else {
                at([problem.base.thermal.t_ref; 6], 0.0)
            };
            out.push(DetectionLimit {
                effect: kind,
                flange_mm,
                of_default: m,
            });
        }
    }
    out
}
