//! Fitting effects to the gap: Levenberg–Marquardt on the perturbed chain
//! with a numeric Jacobian, parameters the data cannot identify found from
//! the SVD of the (column-scaled) Jacobian and held at zero, standard errors
//! from the covariance σ²(JᵀJ)⁻¹. What is fitted to is the problem
//! ([`super::fit_problem`]), what a fit gives is in [`super::fitted`].
//!
//! Written here rather than with the `levenberg-marquardt` crate because the
//! fit needs things that crate does not offer: parameters dropped mid-way
//! when the data cannot identify them, bounds on time constants (active
//! set), a Jacobian reused across steps (the effects are nearly linear), and
//! a statistical stopping rule.

pub use super::fit_problem::{Problem, Row};
use super::fit_steps::{
    at_minimum, gradient_small, identifiable, solve_damped, solve_scaled, Dropped, SE_IN_TYPICAL,
};
pub use super::fitted::{Fit, FitParam};
use super::plausible;
use super::unidentified::Unidentified;
use crate::error::{Error, ErrorKind, Result};
use crate::model::{Effect, EffectKind};
use crate::thermal::MotorTemps;
use nalgebra::{DMatrix, DVector};
use std::collections::BTreeMap;

const MAX_ITER: usize = 100;
/// Longest thermal-lag time constant fitted, minutes: a structure that
/// lags by more than 10 h hardly warms during a test, which
/// expansion-scale (k → 0) describes better than a lag.
pub(super) const MAX_TAU_MIN: f64 = 600.0;

/// Fit the parameters of `kinds` (added to the problem's fixed effects) to
/// the rows `rows`.
pub fn fit(problem: &Problem, rows: &[usize], kinds: &[EffectKind]) -> Result<Fit> {
    fit_bounded(problem, rows, kinds, false, None)
}

/// [`fit`] started from `start` (the values of the effects of those kinds
/// found there; the others start at zero), where a fit of the same model
/// nearby is known: a held-out fold's from the fit on all rows, a joint fit
/// from the fits of its parts. The time constants' grid search is skipped,
/// and the fit ends in the minimum nearest to what was found.
pub fn fit_from(
    problem: &Problem,
    rows: &[usize],
    kinds: &[EffectKind],
    start: &[Effect],
) -> Result<Fit> {
    fit_bounded(
        problem,
        rows,
        kinds,
        false,
        Some(&start_theta(kinds, start)),
    )
}

/// The parameters of `kinds` as found in `start` (zero where absent).
fn start_theta(kinds: &[EffectKind], start: &[Effect]) -> Vec<f64> {
    kinds
        .iter()
        .flat_map(|&k| {
            let found = start.iter().find(|e| e.kind == k);
            (0..k.params().len()).map(move |i| found.map_or(0.0, |e| e.get(i)))
        })
        .collect()
}

/// [`fit_plausible`] started from `start`, the converged fit of the same
/// selection: the reported fit then ends in the minimum the selection was
/// tested at. From a cold start a scaled expansion with a lag (a quadratic
/// growth's look-alike) often crept along the time constants' valley for
/// a hundred iterations and ended the diagnosis without a verdict.
pub fn fit_plausible_from(
    problem: &Problem,
    rows: &[usize],
    kinds: &[EffectKind],
    start: &[Effect],
) -> Result<Fit> {
    fit_bounded(problem, rows, kinds, true, Some(&start_theta(kinds, start)))
}

/// [`fit`] for a model that is reported: a parameter that ends beyond its
/// plausible bound (`data/plausible_effects.toml`) is held at zero, with
/// the value it took as the reason, and the fit goes on without it. Held
/// out scores and the tests between models use [`fit`]: a pair of
/// parameters trading against each other predicts as well as one of them
/// alone, and the extra fits would cost minutes on a thousand poses.
pub fn fit_plausible(problem: &Problem, rows: &[usize], kinds: &[EffectKind]) -> Result<Fit> {
    fit_bounded(problem, rows, kinds, true, None)
}

/// A converged `fit` as a reported model holds it, where the reported fit
/// itself could not converge (it went on from the converged values with
/// the implausible ones held, and crept along a time constant's valley):
/// every parameter beyond its plausible bound held at zero with the value
/// it took as the reason, the others as fitted, and the residual of that.
pub fn held_implausible(problem: &Problem, rows: &[usize], fit: &Fit) -> Fit {
    let mut out = fit.clone();
    let mut dropped = 0;
    for (e, ps) in out.effects.iter_mut().zip(out.params.iter_mut()) {
        for (i, p) in ps.iter_mut().enumerate() {
            let limit = super::plausible::bound(e.kind, i);
            if p.held.is_none() && p.value.abs() > limit {
                p.held = Some(Unidentified::Implausible {
                    value: p.value,
                    limit,
                });
                p.value = 0.0;
                p.stderr = None;
                e.params[i] = 0.0;
                dropped += 1;
            }
        }
    }
    if dropped > 0 {
        out.rss = problem.residuals(&out.effects, rows).norm_squared();
        out.n_free = out.n_free.saturating_sub(dropped);
    }
    out
}

fn fit_bounded(
    problem: &Problem,
    rows: &[usize],
    kinds: &[EffectKind],
    plausible_only: bool,
    start: Option<&[f64]>,
) -> Result<Fit> {
    let key = Problem::memo_key(problem, rows, kinds, plausible_only, start);
    if let Some(f) = problem.memo.get(&key) {
        return Ok(f);
    }
    let f = fit_afresh(problem, rows, kinds, plausible_only, start)?;
    problem.memo.put(key, &f);
    Ok(f)
}

/// The time constants (as bits) and the lagged temperatures of each row.
type LagMemo = ([u64; 4], std::rc::Rc<Vec<[MotorTemps; 4]>>);

fn fit_afresh(
    problem: &Problem,
    rows: &[usize],
    kinds: &[EffectKind],
    plausible_only: bool,
    start: Option<&[f64]>,
) -> Result<Fit> {
    let layout: Vec<(EffectKind, usize)> = kinds
        .iter()
        .flat_map(|&k| (0..k.params().len()).map(move |i| (k, i)))
        .collect();
    let m = layout.len();
    let n_obs = rows.len() * problem.width();
    let effects_of = |theta: &[f64]| effects_from(kinds, theta);
    // The lagged temperatures of the last time constants seen: every
    // Jacobian column but the time constants' own reuses them.
    let lag_memo: std::cell::RefCell<Option<LagMemo>> = Default::default();
    let residual = |theta: &[f64]| {
        let all = problem.with_fixed(&effects_of(theta));
        let lagged = crate::model::lag_taus(&all).and_then(|taus| {
            let key = taus.map(f64::to_bits);
            let mut memo = lag_memo.borrow_mut();
            match memo.as_ref() {
                Some((k, v)) if *k == key => Some(v.clone()),
                _ => {
                    let v = std::rc::Rc::new(problem.lagged_states(&all, rows)?);
                    *memo = Some((key, v.clone()));
                    Some(v)
                }
            }
        });
        problem.residuals_with(&all, rows, lagged.as_deref().map(Vec::as_slice))
    };
    let jacobian = |theta: &[f64], r0: &DVector<f64>, free: &[usize]| -> DMatrix<f64> {
        let mut j = DMatrix::zeros(r0.len(), free.len());
        for (c, &p) in free.iter().enumerate() {
            let (kind, idx) = layout[p];
            let h = kind.step(idx, theta[p]);
            let mut t = theta.to_vec();
            t[p] += h;
            let r1 = residual(&t);
            // Residual = measured − predicted: the model's derivative is −dr.
            j.set_column(c, &((r0 - r1) / h));
        }
        j
    };

    let mut theta = match start {
        Some(t) if t.len() == m => t.to_vec(),
        _ => vec![0.0; m],
    };
    let warm = theta.iter().any(|&v| v != 0.0);
    // The thermal-lag time constants: nonlinear, and never negative.
    let lag_params: Vec<usize> = (0..m)
        .filter(|&p| layout[p].0 == EffectKind::ThermalLag)
        .collect();
    if n_obs <= m {
        return Err(Error::input(format!(
            "too few measurements for a fit: {} rows give {n_obs} values for {m} parameters",
            rows.len()
        )));
    }
    if !lag_params.is_empty() && !warm {
        theta = lag_grid_start(m, &lag_params, &residual, &jacobian, &theta);
    }

    // Identifiability at the start point.
    let r0 = residual(&theta);
    let all: Vec<usize> = (0..m).collect();
    // Without a lag the effects are nearly linear: the Jacobian at zero
    // serves a warm start too (a step that fails refreshes it).
    let j0 = match lag_params.is_empty() {
        true => problem.cached_jacobian(kinds, rows),
        false => None,
    }
    .unwrap_or_else(|| jacobian(&theta, &r0, &all));
    let typical = typical_sizes(&layout);
    let allowed = problem.allowed(&layout);
    let bounds = plausible_bounds(&layout);
    let (mut free, mut held) =
        identified(&j0, &allowed, &layout, &typical, &bounds, problem.noise_mm);
    // Levenberg–Marquardt with Marquardt's diagonal scaling; for a reported
    // model, repeated while parameters end beyond their plausible bounds
    // (those are held at zero, with the value each took as the reason): a
    // value no real arm has is the fit wandering along a direction the data
    // hardly constrain, often two parameters trading against each other.
    let mut total_iterations = 0;
    for (p, value) in theta.iter_mut().enumerate() {
        // A time constant the data cannot pin keeps its grid value (zero
        // would mean "no lag", a claim the data do not support either).
        if !free.contains(&p) && !lag_params.contains(&p) {
            *value = 0.0;
        }
    }
    let mut j = DMatrix::zeros(rows.len() * problem.width(), free.len());
    for (c, &p) in free.iter().enumerate() {
        j.set_column(c, &j0.column(p));
    }
    let mut fresh = true;
    let (theta, rss, j, free) = loop {
        // The Jacobian is reused while steps keep lowering the residual (the
        // effects are nearly linear in their parameters) and recomputed when
        // one fails.
        let descent = descend(
            theta,
            j,
            fresh,
            &free,
            &lag_params,
            n_obs,
            &residual,
            &jacobian,
        );
        theta = descent.theta;
        j = descent.j;
        let (rss, iterations, converged) = (descent.rss, descent.iterations, descent.converged);
        total_iterations += iterations;
        if !converged {
            return Err(no_convergence(kinds, iterations));
        }
        // Every parameter beyond its bound at once: one at a time, each
        // with a fit of its own, cost minutes on a thousand poses where a
        // thermal effect took up a static error with all its parameters.
        let beyond: Vec<usize> = free
            .iter()
            .copied()
            .filter(|&p| theta[p].abs() > bounds[p])
            .collect();
        if beyond.is_empty() || !plausible_only {
            break (theta, rss, j, free);
        }
        // The fit goes on from where it stopped, those held at zero and
        // their columns dropped.
        j = hold_implausible(beyond, &j, &mut theta, &mut free, &mut held, &bounds);
        fresh = false;
    };
    let iterations = total_iterations;
    let dof = (n_obs - free.len()).max(1) as f64;
    let sigma2 = rss / dof;
    let cov = (j.transpose() * &j).try_inverse();
    let params = params_of(kinds, &layout, &free, cov.as_ref(), sigma2, &theta, &held);
    Ok(Fit {
        effects: effects_of(&theta),
        params,
        rss,
        n_obs,
        n_free: free.len(),
        iterations,
    })
}

/// The start of a fit with thermal lags and no warm start: the best of a
/// coarse grid of one time constant for all links.
fn lag_grid_start(
    m: usize,
    lag_params: &[usize],
    residual: &impl Fn(&[f64]) -> DVector<f64>,
    jacobian: &impl Fn(&[f64], &DVector<f64>, &[usize]) -> DMatrix<f64>,
    theta: &[f64],
) -> Vec<f64> {
    // τ is strongly nonlinear: start from the best of a coarse grid (one
    // τ for all links), with the other parameters solved linearly at
    // each τ.
    let mut best = (f64::INFINITY, theta.to_vec());
    for tau in [2.0, 5.0, 10.0, 20.0, 40.0, 80.0, 160.0, 320.0] {
        let mut t = vec![0.0; m];
        for &li in lag_params {
            t[li] = tau;
        }
        let others: Vec<usize> = (0..m).filter(|p| !lag_params.contains(p)).collect();
        if !others.is_empty() {
            let r0 = residual(&t);
            let j = jacobian(&t, &r0, &others);
            if let Some(step) = solve_scaled(&j, &r0) {
                for (c, &p) in others.iter().enumerate() {
                    t[p] += step[c];
                }
            }
        }
        let rss = residual(&t).norm_squared();
        if rss < best.0 {
            best = (rss, t);
        }
    }
    best.1
}

/// The parameters the data identify at the start point, and why each of
/// the others is held.
fn identified(
    j0: &DMatrix<f64>,
    allowed: &[usize],
    layout: &[(EffectKind, usize)],
    typical: &[f64],
    bounds: &[f64],
    noise_mm: f64,
) -> (Vec<usize>, BTreeMap<usize, Unidentified>) {
    let mut held: BTreeMap<usize, Unidentified> = BTreeMap::new();
    let sub = j0.select_columns(allowed.iter());
    let typ: Vec<f64> = allowed.iter().map(|&p| typical[p]).collect();
    let bnd: Vec<(EffectKind, f64)> = allowed.iter().map(|&p| (layout[p].0, bounds[p])).collect();
    let (kept, dropped) = identifiable(&sub, &typ, &bnd, noise_mm);
    for (c, why) in dropped {
        held.insert(
            allowed[c],
            match why {
                Dropped::NoLever(lever_mm) => Unidentified::NoLever { lever_mm },
                Dropped::Unresolved(stderr) => Unidentified::Unresolved {
                    stderr,
                    limit: SE_IN_TYPICAL * typical[allowed[c]],
                },
                Dropped::SameAs(independent, partners) => Unidentified::SameAs {
                    independent,
                    same_as: partners
                        .iter()
                        .map(|&k| name_of(layout[allowed[k]]))
                        .collect(),
                },
            },
        );
    }
    let free = kept.into_iter().map(|c| allowed[c]).collect();
    (free, held)
}

/// What one run of Levenberg–Marquardt ends with.
struct Descent {
    theta: Vec<f64>,
    j: DMatrix<f64>,
    rss: f64,
    iterations: usize,
    converged: bool,
}

/// Levenberg–Marquardt with Marquardt's diagonal scaling over the `free`
/// parameters, from `theta` on the Jacobian `j` (`fresh` when computed
/// at `theta`), to where it stops.
#[allow(clippy::too_many_arguments)]
fn descend(
    mut theta: Vec<f64>,
    mut j: DMatrix<f64>,
    mut fresh: bool,
    free: &[usize],
    lag_params: &[usize],
    n_obs: usize,
    residual: &impl Fn(&[f64]) -> DVector<f64>,
    jacobian: &impl Fn(&[f64], &DVector<f64>, &[usize]) -> DMatrix<f64>,
) -> Descent {
    let mut r = residual(&theta);
    let mut rss = r.norm_squared();
    let mut lambda = 1e-6;
    let mut iterations = 0;
    let mut converged = free.is_empty();
    // RSS at the end of each iteration: a fit that creeps along a flat
    // valley (a time constant the data hardly pin) has converged for every
    // statistical purpose once ten iterations lower χ² by less than 0.1.
    let mut history: Vec<f64> = Vec::new();
    while !converged && iterations < MAX_ITER {
        iterations += 1;
        history.push(rss);
        if history.len() > 10 && history[history.len() - 11] - rss <= 0.1 * rss / n_obs as f64 {
            converged = true;
            break;
        }
        let mut g = j.transpose() * &r;
        let mut a = j.transpose() * &j;
        // A time constant on a bound (0, or MAX_TAU_MIN) that the data push
        // beyond it: hold it there this iteration (active set).
        for (c, &p) in free.iter().enumerate() {
            let at_bound =
                (theta[p] <= 0.0 && g[c] < 0.0) || (theta[p] >= MAX_TAU_MIN && g[c] > 0.0);
            if lag_params.contains(&p) && at_bound {
                g[c] = 0.0;
                for k in 0..free.len() {
                    if k != c {
                        a[(c, k)] = 0.0;
                        a[(k, c)] = 0.0;
                    }
                }
            }
        }
        if at_minimum(&a, &g, rss, n_obs) {
            if fresh {
                converged = true;
                break;
            }
            j = jacobian(&theta, &r, free);
            fresh = true;
            continue;
        }
        let Some(step) = solve_damped(&a, &g, lambda) else {
            lambda = (lambda * 10.0).max(1e-9);
            if lambda > 1e12 {
                break;
            }
            continue;
        };
        let mut t = theta.clone();
        for (c, &p) in free.iter().enumerate() {
            t[p] += step[c];
        }
        for &li in lag_params {
            t[li] = t[li].clamp(0.0, MAX_TAU_MIN);
        }
        let r1 = residual(&t);
        let rss1 = r1.norm_squared();
        if rss1.is_finite() && rss1 <= rss {
            let gain = (rss - rss1) / rss.max(1e-300);
            theta = t;
            r = r1;
            rss = rss1;
            lambda = (lambda / 5.0).max(1e-12);
            if gain < 1e-12 && fresh {
                converged = true;
            } else if gain < 1e-4 && !lag_params.is_empty() {
                // Slow progress on a reused Jacobian: the step direction is
                // stale (a time constant, the one strongly nonlinear
                // parameter, moved); refresh it.
                j = jacobian(&theta, &r, free);
                fresh = true;
            } else {
                fresh = false;
            }
        } else if !fresh {
            j = jacobian(&theta, &r, free);
            fresh = true;
        } else {
            lambda = (lambda * 8.0).max(1e-9);
            if lambda > 1e12 {
                // No step lowers the residual, not even a vanishing one
                // along the gradient of a fresh Jacobian: a minimum as far
                // as the arithmetic can tell (a time constant on its bound
                // leaves a gradient it may not follow).
                converged = fresh || gradient_small(&a, &g, rss * 1e4);
                break;
            }
        }
    }
    Descent {
        theta,
        j,
        rss,
        iterations,
        converged,
    }
}

/// The error of a fit that did not converge.
fn no_convergence(kinds: &[EffectKind], iterations: usize) -> Error {
    Error::new(
        ErrorKind::NoConvergence,
        format!(
            "the fit of {} did not converge in {iterations} iterations",
            kinds
                .iter()
                .map(|k| k.name())
                .collect::<Vec<_>>()
                .join(" + ")
        ),
    )
}

/// The effects of `kinds` with their parameters in order from `theta`.
fn effects_from(kinds: &[EffectKind], theta: &[f64]) -> Vec<Effect> {
    let mut it = theta.iter();
    kinds
        .iter()
        .map(|&k| Effect {
            kind: k,
            params: (0..k.params().len())
                .map(|_| it.next().copied().unwrap_or(0.0))
                .collect(),
        })
        .collect()
}

/// Each effect's parameters as fitted: value, standard error where free
/// and the covariance exists, and why one is held.
fn params_of(
    kinds: &[EffectKind],
    layout: &[(EffectKind, usize)],
    free: &[usize],
    cov: Option<&DMatrix<f64>>,
    sigma2: f64,
    theta: &[f64],
    held: &BTreeMap<usize, Unidentified>,
) -> Vec<Vec<FitParam>> {
    let mut params: Vec<Vec<FitParam>> = kinds
        .iter()
        .map(|k| Vec::with_capacity(k.params().len()))
        .collect();
    let mut effect_index = 0;
    for (p, &(_, idx)) in layout.iter().enumerate() {
        if idx == 0 && p > 0 {
            effect_index += 1;
        }
        let stderr = free.iter().position(|&f| f == p).and_then(|c| {
            cov.map(|cov| (cov[(c, c)] * sigma2).max(0.0).sqrt())
                .filter(|s| s.is_finite())
        });
        if let Some(list) = params.get_mut(effect_index) {
            list.push(FitParam {
                value: theta[p],
                stderr,
                held: held.get(&p).cloned(),
            });
        }
    }
    params
}

/// Hold the parameters `beyond` their plausible bounds at zero, with the
/// value each took as the reason; the Jacobian without their columns.
fn hold_implausible(
    beyond: Vec<usize>,
    j: &DMatrix<f64>,
    theta: &mut [f64],
    free: &mut Vec<usize>,
    held: &mut BTreeMap<usize, Unidentified>,
    bounds: &[f64],
) -> DMatrix<f64> {
    let keep: Vec<usize> = (0..free.len())
        .filter(|&c| !beyond.contains(&free[c]))
        .collect();
    let j = j.select_columns(keep.iter());
    for p in beyond {
        held.insert(
            p,
            Unidentified::Implausible {
                value: theta[p],
                limit: bounds[p],
            },
        );
        theta[p] = 0.0;
        free.retain(|&f| f != p);
    }
    j
}

/// Each parameter's typical size: its default's, at least 1e-6.
fn typical_sizes(layout: &[(EffectKind, usize)]) -> Vec<f64> {
    layout
        .iter()
        .map(|&(k, i)| k.params().get(i).map_or(1.0, |p| p.default.abs().max(1e-6)))
        .collect()
}

/// Each parameter's plausible bound ([`plausible::bound`]).
fn plausible_bounds(layout: &[(EffectKind, usize)]) -> Vec<f64> {
    layout
        .iter()
        .map(|&(k, i)| plausible::bound(k, i))
        .collect()
}

/// `effect.param`, as reports name a parameter.
fn name_of((kind, index): (EffectKind, usize)) -> String {
    format!(
        "{}.{}",
        kind.name(),
        kind.params().get(index).map_or("?", |p| p.name)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two parameters that move the data alike (a wrist origin along the
    /// last axis and the measured point along the flange's z, on a UR5): the
    /// one that can plausibly take the larger value is kept, and the other
    /// is held as the same effect, whichever comes first.
    #[test]
    fn of_two_alike_the_one_with_room_is_kept() {
        let column = DVector::from_fn(30, |i, _| ((i * 7 % 11) as f64) - 5.0);
        let mut j = DMatrix::zeros(30, 3);
        j.set_column(0, &column);
        j.set_column(1, &column);
        j.set_column(2, &DVector::from_fn(30, |i, _| (i % 3) as f64));
        let g = EffectKind::GeometryOffset;
        for (bounds, kept, held) in [
            ([(g, 10.0), (g, 100.0), (g, 10.0)], 1, 0),
            ([(g, 100.0), (g, 10.0), (g, 10.0)], 0, 1),
        ] {
            let (free, dropped) = identifiable(&j, &[0.03, 0.03, 0.03], &bounds, 0.01);
            assert!(free.contains(&kept) && free.contains(&2), "{free:?}");
            assert_eq!(dropped.len(), 1);
            assert_eq!(dropped[0].0, held);
            assert!(
                matches!(&dropped[0].1, Dropped::SameAs(_, with) if with == &vec![kept]),
                "{:?}",
                dropped[0].0
            );
        }
    }
}
