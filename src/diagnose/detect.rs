//! The detection limit of every effect of the library: the smallest
//! magnitude these poses, times and noise would have revealed, at the
//! stage's level with 90 % power, beyond the rest of the model the
//! diagnosis ended with. Each effect is taken along its default parameters
//! (its shape), its size said as the largest displacement of the flange at
//! the calibration pose over the data's temperatures and times (static
//! effects: at the cold start).

use super::fit::Problem;
use super::signature::effects_jacobian;
use super::stats::{detectable_noncentrality, LEVEL, POWER};
use super::test_noise::TestNoise;
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

/// The effects of `found` an effect of `kind` is judged beyond: every
/// other one for a static effect; for a thermal one (judged over time,
/// each pose's own offset taken out) only the other thermal ones. A static
/// effect changes over time only through the expansion of its own error
/// (α·ΔT of a tenth of a mm: a few nanometres), and its columns, scaled
/// to unit norm, would take up any shape over time: beyond geometry's 52,
/// a bending that took 97 % of the change over time was "below" a limit
/// of twice its size.
///
/// Where no pose is measured again over time (`over_time` false) there is
/// no pose's own offset to take out: a thermal effect then shows only in
/// the whole gap, as a static one does, and is judged beyond every other
/// effect found (centred on poses measured once, every effect's own part
/// is zero and its limit infinite: a lag that took 72 % of the held-out
/// gap was "below" it).
fn beyond(found: &[Effect], kind: EffectKind, over_time: bool) -> Vec<Effect> {
    let centred = over_time && kind.is_thermal();
    found
        .iter()
        .filter(|e| e.kind != kind && (!centred || e.kind.is_thermal()))
        .cloned()
        .collect()
}

/// Whether an effect of `kind` is judged over time (each pose's own offset
/// taken out): a thermal one, where poses are measured again over time.
fn centred(kind: EffectKind, over_time: bool) -> bool {
    over_time && kind.is_thermal()
}

/// The kinds judged in one family with `kind`, at a level shared among
/// them: over time the thermal ones, on the whole gap the rest; every
/// kind where the data hold one stage.
fn family(problem: &Problem, kind: EffectKind, over_time: bool) -> Vec<EffectKind> {
    let c = centred(kind, over_time);
    EffectKind::ALL
        .into_iter()
        .filter(|k| centred(*k, over_time) == c)
        .filter(|k| !problem.fixed.iter().any(|f| f.kind == *k))
        .collect()
}

/// A named effect's own part of the data, beyond the rest found, in noise
/// variances: the noncentrality its nested test had (the drop of the
/// residual sum of squares its fitted values make, orthogonal to what the
/// others can take up).
fn own_lambda(p: &Problem, others: &[Effect], effect: &Effect, rows: &[usize], sigma2: f64) -> f64 {
    let model = effects_jacobian(p, others, rows);
    let r0 = p.residuals(others, rows);
    let mut with = others.to_vec();
    with.push(effect.clone());
    let moved = &r0 - p.residuals(&with, rows);
    orthogonal(&model, &moved).norm_squared() / sigma2.max(1e-300)
}

/// The largest move of the flange `effect` makes at the calibration pose:
/// over the rows' temperatures and times for a thermal effect (a lag
/// shows early, an expansion late), at the cold start for a static one.
fn flange_size(problem: &Problem, effect: &Effect) -> f64 {
    let lags = crate::model::LinkLags::new(&problem.history, std::slice::from_ref(effect));
    let at = |temps: [f64; 6], time: f64| {
        let state = RowState {
            q: [0.0; 6],
            temps,
            lagged: lags.as_ref().map(|l| l.at(time)),
        };
        let a = predict(&problem.base, std::slice::from_ref(effect), &state);
        let b = predict(&problem.base, &[], &state);
        (a.translation.vector - b.translation.vector).norm()
    };
    if effect.kind.is_thermal() {
        problem
            .rows
            .iter()
            .map(|r| at(r.temps, r.time_min))
            .fold(0.0, f64::max)
    } else {
        at([problem.base.thermal.t_ref; 6], 0.0)
    }
}

/// An effect that fits but lies below what the data could reveal.
#[derive(Debug, Clone, Serialize)]
pub struct BelowLimit {
    pub effect: EffectKind,
    /// Its fitted size (the flange's largest move at the calibration pose).
    pub size_mm: f64,
    /// The size its own shape would need to be revealed (at the level of
    /// its family, with 90 % power, beyond the rest found), in the same
    /// measure.
    pub limit_mm: f64,
}

/// Of the `found` effects (fitted values), those below their detection
/// limit on `problem` (its fixed effects the model in use): the
/// noncentrality their fitted values give, beyond the rest found, is below
/// the one the test needs for 90 % power ([`limits`]: the same level, the
/// same family; thermal effects over time, each pose's own offset taken
/// out). Judged along each effect's own fitted shape, and said in the
/// limits' measure: its flange size, and the size at which that shape
/// would be revealed.
pub fn below(
    problem: &Problem,
    found: &[Effect],
    noise: &TestNoise,
    over_time: bool,
) -> Vec<BelowLimit> {
    let rows: Vec<usize> = (0..problem.rows.len()).collect();
    let mut out = Vec::new();
    for e in found {
        let p = Problem {
            centre_poses: centred(e.kind, over_time),
            ..problem.clone()
        };
        let level = LEVEL / family(problem, e.kind, over_time).len().max(1) as f64;
        let others = beyond(found, e.kind, over_time);
        let lambda = own_lambda(&p, &others, e, &rows, noise.sigma2);
        let needed = detectable_noncentrality(level, e.kind.params().len() as f64, POWER);
        if lambda < needed {
            let size = flange_size(problem, e);
            out.push(BelowLimit {
                effect: e.kind,
                size_mm: size,
                limit_mm: if lambda > 0.0 {
                    size * (needed / lambda).sqrt()
                } else {
                    f64::INFINITY
                },
            });
        }
    }
    out
}

/// Detection limits of every effect not fixed in the model in use, beyond
/// `found` (the effects the diagnosis fitted, in their fitted values) on
/// `problem` (whose own fixed effects are the model in use). Where poses
/// are measured again over time (`over_time`) thermal effects are judged
/// over time (each pose's own offset taken out) and static ones on the
/// whole gap; else every effect on the whole gap.
pub fn limits(
    problem: &Problem,
    found: &[Effect],
    noise: &TestNoise,
    over_time: bool,
) -> Vec<DetectionLimit> {
    let rows: Vec<usize> = (0..problem.rows.len()).collect();
    let mut out = Vec::new();
    for centred in [true, false] {
        let p = Problem {
            centre_poses: centred,
            ..problem.clone()
        };
        let kinds: Vec<EffectKind> = EffectKind::ALL
            .into_iter()
            .filter(|k| self::centred(*k, over_time) == centred)
            .filter(|k| !problem.fixed.iter().any(|e| e.kind == *k))
            .collect();
        let level = LEVEL / kinds.len().max(1) as f64;
        for kind in kinds {
            // Beyond everything found but the effect itself: what would
            // have revealed it had it not been named.
            let others = beyond(found, kind, over_time);
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
            // The same measure as a fitted effect's ([`flange_size`]).
            let flange_mm = flange_size(problem, &sized);
            out.push(DetectionLimit {
                effect: kind,
                flange_mm,
                of_default: m,
            });
        }
    }
    out
}
