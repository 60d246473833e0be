//! Forward selection over a pool of candidate effects, by significance: at
//! each step every candidate is added to the model and tested against it
//! (an F test of the drop in the residual sum of squares over the noise
//! the data show, at the stage's level shared among the candidates tried),
//! and, where the design allows, it must also predict held-out data
//! better. Of those that pass, the one with the lowest held-out gap is
//! added. Two effects that show only together (a lag on a scaled
//! expansion) are tried as a pair when no single one passes. A runner-up
//! the data cannot tell from the effect chosen (neither adds anything
//! significant beyond the other) is named beside it as a candidate.

use super::fit::{self, Problem};
use super::select::{self, Folds};
use super::separation::Separation;
use super::stats::{Test, LEVEL};
use super::test_noise::TestNoise;
use super::verdict::{Ambiguity, CandidateOut, ParamOut, ScoredIn, StepOut};
use crate::error::{Error, ErrorKind, Result};
use crate::model::EffectKind;

/// What a forward selection found.
#[derive(Debug, Clone)]
pub struct Forward {
    pub selected: Vec<EffectKind>,
    /// Held-out RMS gap without and with the selected effects, mm.
    pub cv0: f64,
    pub cv: f64,
    /// The selected effects (and the base) refitted on all rows.
    pub fit: Option<fit::Fit>,
    /// Residual sum of squares of the base on all rows, and its free
    /// parameters.
    pub rss0: f64,
    pub free0: usize,
    pub steps: Vec<StepOut>,
    /// Every candidate's score at the first step.
    pub candidates: Vec<CandidateOut>,
    pub ambiguities: Vec<Ambiguity>,
}

impl Forward {
    /// Residual sum of squares and free parameters of the final model.
    pub fn rss(&self) -> (f64, usize) {
        self.fit
            .as_ref()
            .map_or((self.rss0, self.free0), |f| (f.rss, f.n_free))
    }
}

/// The parameters of a fit as reported. A value beyond its plausible bound
/// (`data/plausible_effects.toml`) is declared implausible, as a reported
/// model's fit holds it ([`fit::fit_plausible`]): a candidate's record of
/// its fit alone (a thermal effect taking up static error with all its
/// parameters, an expansion factor of 10,000) never shows it as a finding.
pub fn params_out(fit: &fit::Fit) -> Vec<ParamOut> {
    fit.effects
        .iter()
        .zip(&fit.params)
        .flat_map(|(e, ps)| {
            e.kind
                .params()
                .iter()
                .zip(ps)
                .enumerate()
                .map(|(i, (info, p))| {
                    let limit = super::plausible::bound(e.kind, i);
                    let wild = p.held.is_none() && p.value.abs() > limit;
                    // A time constant on a bound of its range is not pinned
                    // by the data: held there, said so, no standard error.
                    let bound = e.kind == EffectKind::ThermalLag
                        && p.held.is_none()
                        && (p.value <= 1e-9 || p.value >= fit::MAX_TAU_MIN - 1e-9);
                    ParamOut {
                        name: format!("{}.{}", e.kind.name(), info.name),
                        unit: info.unit.to_string(),
                        value: if wild { 0.0 } else { p.value },
                        stderr: if wild || bound { None } else { p.stderr },
                        held: if wild {
                            Some(super::unidentified::Unidentified::Implausible {
                                value: p.value,
                                limit,
                            })
                        } else if bound {
                            Some(super::unidentified::Unidentified::AtBound { value: p.value })
                        } else {
                            p.held.clone()
                        },
                    }
                })
        })
        .collect()
}

/// Whether the data pin `kind` in `fit`: at least one of its parameters
/// (with a place on the arm) is fitted with a standard error, neither
/// held as not identifiable nor on a bound of its range. An effect none of
/// whose parameters the data pin is never named: what it would say is
/// only its start values.
pub fn pinned(fit: &fit::Fit, kind: EffectKind) -> bool {
    let prefix = format!("{}.", kind.name());
    params_out(fit)
        .iter()
        .filter(|p| p.name.starts_with(&prefix))
        .any(|p| p.held.is_none() && p.stderr.is_some())
}

/// Effects fitted earlier on another form of the data (the thermal effects
/// over time), refitted together with the candidates for their F test:
/// the static stage tests on the poses' means, which carry the error of
/// those effects at each pose's mean temperature, not only noise.
#[derive(Debug, Clone, Copy)]
pub struct Joint<'a> {
    pub problem: &'a Problem,
    pub kinds: &'a [EffectKind],
}

impl Joint<'_> {
    /// Residual sum of squares, free parameters and residual degrees of
    /// freedom of `selected` fitted together with the joint effects.
    fn rss(&self, selected: &[EffectKind]) -> Option<(f64, usize, usize)> {
        let all: Vec<usize> = (0..self.problem.rows.len()).collect();
        let mut kinds = self.kinds.to_vec();
        kinds.extend(selected.iter().copied());
        fit::fit(self.problem, &all, &kinds)
            .ok()
            .map(|f| (f.rss, f.n_free, f.n_obs.saturating_sub(f.n_free)))
    }
}

/// Share of the held-out gap above the noise that going from `cv0` to `cv`
/// (3-D RMS, mm) removes.
/// Where the gap is within the scatter of held-out scores above the noise
/// (5 % of its variance), there is nothing to share out: 0.
pub fn share_above_noise(cv0: f64, cv: f64, noise_rms_mm: f64) -> f64 {
    let n2 = noise_rms_mm * noise_rms_mm;
    let above = cv0 * cv0 - n2;
    if above <= 0.05 * n2 {
        return 0.0;
    }
    ((cv0 * cv0 - cv * cv) / above).clamp(0.0, 1.0)
}

/// Select from `pool` on `problem`, adding at most `max_effects` to `base`
/// (always fitted with them, never reported as selected). With
/// `held_out`, a candidate must also lower the held-out mean-square gap,
/// by more than that margin (mm²).
#[allow(clippy::too_many_arguments)]
pub fn forward(
    problem: &Problem,
    folds: &Folds,
    base: &[EffectKind],
    pool: &[EffectKind],
    noise: &TestNoise,
    max_effects: usize,
    held_out: Option<f64>,
    joint: Option<Joint>,
) -> Result<Forward> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let cv0 = select::cv_rms(problem, folds, base)?;
    let base_fit = match base {
        [] => None,
        _ => Some(fit::fit(problem, &all, base)?),
    };
    let (rss0, free0) = match &base_fit {
        Some(f) => (f.rss, f.n_free),
        None => (problem.residuals(&[], &all).norm_squared(), 0),
    };
    let mut pool: Vec<EffectKind> = pool.iter().copied().filter(|k| !base.contains(k)).collect();
    let offered = pool.clone();
    // The slowest fit first, so that the threads finish together.
    pool.sort_by_key(|k| *k != EffectKind::ThermalLag);
    let mut selected: Vec<EffectKind> = base.to_vec();
    let mut current_fit: Option<fit::Fit> = base_fit;
    let (mut cur_cv, mut cur_rss, mut cur_free) = (cv0, rss0, free0);
    let mut steps = Vec::new();
    let mut candidates: Vec<CandidateOut> = Vec::new();
    // Per step: the effect added and a runner-up that passed too.
    let mut runners: Vec<(EffectKind, select::Scored)> = Vec::new();
    let test_of = |s: &select::Scored, rss: f64, free: usize, level: f64| {
        s.fit
            .as_ref()
            .map(|f| noise.nested_fit(rss, free, f, level))
    };
    while selected.len() < base.len() + max_effects && !pool.is_empty() {
        let cur_effects = current_fit
            .as_ref()
            .map(|f| f.effects.clone())
            .unwrap_or_default();
        let mut scored = select::score_candidates(problem, folds, &selected, &cur_effects, &pool);
        let tried = scored.iter().filter(|s| s.fit.is_some()).count().max(1);
        let level = LEVEL / tried as f64;
        if steps.is_empty() {
            candidates = listed(&scored, cv0, noise, cur_rss, cur_free, level);
        }
        scored.sort_by(|a, b| a.cv_rms_mm.total_cmp(&b.cv_rms_mm));
        let joint_now = match joint {
            Some(j) if !scored.is_empty() => j.rss(&selected),
            _ => None,
        };
        let passes = |s: &select::Scored| {
            s.fit.as_ref().is_some_and(|f| pinned(f, s.kind))
                && test_of(s, cur_rss, cur_free, level).is_some_and(|t| t.significant())
                && held_out.is_none_or(|m| s.cv_rms_mm.powi(2) < cur_cv.powi(2) - m)
                && match (joint, joint_now) {
                    (Some(j), Some((rss0, free0, _))) => {
                        let mut with = selected.clone();
                        with.push(s.kind);
                        j.rss(&with).is_some_and(|(rss1, free1, dof1)| {
                            noise
                                .nested(rss0, rss1, free1.saturating_sub(free0), dof1, level)
                                .significant()
                        })
                    }
                    _ => true,
                }
        };
        let mut eligible = scored.iter().filter(|s| passes(s));
        let Some(best) = eligible.next().cloned() else {
            // Two effects may show only together (a lag on a scaled
            // expansion: either alone fits the warm-up's shape poorly).
            let Some((pair, pair_fit, pair_cv)) = best_pair(
                problem, folds, &selected, &scored, cur_cv, cur_rss, cur_free, noise, held_out,
            )?
            else {
                break;
            };
            let test = noise.nested_fit(cur_rss, cur_free, &pair_fit, LEVEL);
            steps.push(pair_step(&pair, cur_cv, pair_cv, test));
            for k in pair {
                selected.push(k);
                pool.retain(|p| *p != k);
            }
            cur_cv = pair_cv;
            (cur_rss, cur_free) = (pair_fit.rss, pair_fit.n_free);
            current_fit = Some(pair_fit);
            continue;
        };
        let runner = eligible.next().cloned();
        let Some(best_fit) = best.fit.clone() else {
            break;
        };
        let test = test_of(&best, cur_rss, cur_free, level);
        steps.push(best_step(&best, runner.as_ref(), cur_cv, test));
        if let Some(r) = runner {
            runners.push((best.kind, r));
        }
        selected.push(best.kind);
        pool.retain(|k| *k != best.kind);
        cur_cv = best.cv_rms_mm;
        (cur_rss, cur_free) = (best_fit.rss, best_fit.n_free);
        current_fit = Some(best_fit);
    }
    swap_runners(
        problem,
        folds,
        &runners,
        &mut selected,
        &mut cur_cv,
        &mut steps,
    );
    backward(
        problem,
        folds,
        base.len(),
        noise,
        &mut selected,
        &mut steps,
        &mut cur_cv,
    )?;
    let mut ambiguities = ambiguous_runners(problem, &all, &selected, runners, noise);
    ambiguities.extend(unpassed_rivals(
        problem,
        &selected[base.len()..],
        &selected,
        &offered,
        &ambiguities,
        noise,
    ));
    // The final model must come from a converged fit: refit and propagate.
    let fit = final_fit(problem, &all, &selected, current_fit.as_ref())?;
    if let Some(f) = &fit {
        mark_selected(&mut candidates, &selected[base.len()..], f);
    }
    Ok(Forward {
        selected: selected[base.len()..].to_vec(),
        cv0,
        cv: cur_cv,
        fit,
        rss0,
        free0,
        steps,
        candidates,
        ambiguities,
    })
}

/// A runner-up that passed at the same step, put in the place of the
/// effect chosen: kept where the whole set then predicts held-out data
/// better.
fn swap_runners(
    problem: &Problem,
    folds: &Folds,
    runners: &[(EffectKind, select::Scored)],
    selected: &mut Vec<EffectKind>,
    cur_cv: &mut f64,
    steps: &mut [StepOut],
) {
    // A runner-up that passed at the same step, put in the place of the
    // effect chosen: kept where the whole set then predicts held-out data
    // better (which of two near-collinear effects fits may only show with
    // what was added after them).
    for (chosen, runner) in runners {
        if selected.contains(&runner.kind) {
            continue;
        }
        let Some(at) = selected.iter().position(|k| k == chosen) else {
            continue;
        };
        let mut alt = selected.clone();
        alt[at] = runner.kind;
        let Ok(cv_alt) = select::cv_rms(problem, folds, &alt) else {
            continue;
        };
        if cv_alt < *cur_cv {
            *selected = alt;
            *cur_cv = cv_alt;
            if let Some(step) = steps.iter_mut().find(|s| s.added == chosen.name()) {
                step.added = runner.kind.name().into();
                step.runner_up = Some(chosen.name().into());
            }
        }
    }
}

/// Backward elimination beyond the first `base_len` effects: the least
/// significant of those not significant against the model without it is
/// dropped, until none is.
fn backward(
    problem: &Problem,
    folds: &Folds,
    base_len: usize,
    noise: &TestNoise,
    selected: &mut Vec<EffectKind>,
    steps: &mut Vec<StepOut>,
    cur_cv: &mut f64,
) -> Result<()> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    // Backward: an effect added early may have only stood in for those
    // added after it (a joint drift for a lag on a scaled expansion). Each
    // is tested against the model without it; the least significant that
    // is not significant is dropped, and the test repeats.
    while selected.len() > base_len + 1 {
        let Ok(full) = fit::fit(problem, &all, selected) else {
            break;
        };
        let mut weakest: Option<(f64, EffectKind)> = None;
        for &k in &selected[base_len..] {
            let without: Vec<EffectKind> = selected.iter().copied().filter(|x| *x != k).collect();
            let Ok(f) = fit::fit(problem, &all, &without) else {
                continue;
            };
            let t = noise.nested_fit(f.rss, f.n_free, &full, LEVEL);
            if !t.significant() && weakest.is_none_or(|(p, _)| t.p_value > p) {
                weakest = Some((t.p_value, k));
            }
        }
        let Some((_, k)) = weakest else { break };
        selected.retain(|x| *x != k);
        steps.retain(|s| s.added != k.name());
        *cur_cv = select::cv_rms(problem, folds, selected)?;
    }
    Ok(())
}

/// Runners-up that the effect chosen adds nothing significant beyond: the
/// data cannot tell the two apart.
fn ambiguous_runners(
    problem: &Problem,
    all: &[usize],
    selected: &[EffectKind],
    runners: Vec<(EffectKind, select::Scored)>,
    noise: &TestNoise,
) -> Vec<Ambiguity> {
    // A runner-up that passed at the same step and that the effect chosen
    // adds nothing significant beyond: the data cannot tell the two apart,
    // and both are named as candidates.
    let mut ambiguities = Vec::new();
    for (first, runner) in runners {
        // The effect now in that place (the runner-up, where it was put
        // in), against the other.
        let (chosen, runner) = if selected.contains(&first) {
            (first, runner)
        } else if selected.contains(&runner.kind) {
            // The effect put out's own contribution is not kept: no
            // correlation is said.
            (
                runner.kind,
                select::Scored {
                    kind: first,
                    contribution: Vec::new(),
                    ..runner
                },
            )
        } else {
            continue;
        };
        let mut with_runner = selected.to_vec();
        with_runner.push(runner.kind);
        let swapped: Vec<EffectKind> = with_runner
            .iter()
            .copied()
            .filter(|k| *k != chosen)
            .collect();
        let (Ok(both), Ok(alone)) = (
            fit::fit(problem, all, &with_runner),
            fit::fit(problem, all, &swapped),
        ) else {
            continue;
        };
        let beyond = noise.nested_fit(alone.rss, alone.n_free, &both, LEVEL);
        if !beyond.significant() {
            let best_contribution = select::score_contribution(problem, selected, chosen);
            ambiguities.push(Ambiguity {
                pair: [chosen.name().into(), runner.kind.name().into()],
                correlation: best_contribution
                    .filter(|_| !runner.contribution.is_empty())
                    .map(|c| select::collinearity(&c, &runner.contribution)),
                separate_by: Separation::of(chosen, runner.kind),
            });
        }
    }
    ambiguities
}

/// The selection's final fit, converged, with implausible values held;
/// `None` where nothing is selected.
fn final_fit(
    problem: &Problem,
    all: &[usize],
    selected: &[EffectKind],
    current_fit: Option<&fit::Fit>,
) -> Result<Option<fit::Fit>> {
    if selected.is_empty() {
        return Ok(None);
    }
    // From the selection's own converged fit (remembered from the
    // backward pass), else from the last fit the forward pass made.
    let converged = fit::fit(problem, all, selected).ok();
    let start = converged
        .as_ref()
        .or(current_fit)
        .map(|f| f.effects.clone());
    let reported = match &start {
        Some(s) => fit::fit_plausible_from(problem, all, selected, s),
        None => fit::fit_plausible(problem, all, selected),
    };
    // Where the reported fit creeps on without converging, the
    // selection's converged fit with its implausible values held.
    let reported = match (reported, &converged) {
        (Err(e), Some(c)) if e.kind == ErrorKind::NoConvergence => {
            Ok(fit::held_implausible(problem, all, c))
        }
        (r, _) => r,
    };
    Ok(Some(reported.map_err(|e| {
        if e.kind == ErrorKind::NoConvergence {
            Error::new(
                ErrorKind::NoConvergence,
                format!("{}; no verdict", e.message),
            )
        } else {
            e
        }
    })?))
}

/// Every candidate of the first step as reported: its held-out gap, its
/// test against the base, its parameters.
fn listed(
    scored: &[select::Scored],
    cv0: f64,
    noise: &TestNoise,
    cur_rss: f64,
    cur_free: usize,
    level: f64,
) -> Vec<CandidateOut> {
    scored
        .iter()
        .map(|s| CandidateOut {
            name: s.kind.name().into(),
            part: ScoredIn::All,
            explained: share_above_noise(cv0, s.cv_rms_mm, noise.rms_mm),
            cv_rms_mm: s.cv_rms_mm,
            bic: s.fit.as_ref().map(fit::Fit::bic),
            test: s
                .fit
                .as_ref()
                .map(|f| noise.nested_fit(cur_rss, cur_free, f, level)),
            params: s.fit.as_ref().map(params_out).unwrap_or_default(),
            selected: false,
            error: s.error.clone(),
        })
        .collect()
}

/// The step that adds the best candidate, with the runner-up that passed
/// too.
fn best_step(
    best: &select::Scored,
    runner: Option<&select::Scored>,
    cur_cv: f64,
    test: Option<Test>,
) -> StepOut {
    StepOut {
        added: best.kind.name().into(),
        part: ScoredIn::All,
        gap_before_mm: cur_cv,
        gap_after_mm: best.cv_rms_mm,
        drop_pct: 100.0 * (1.0 - best.cv_rms_mm / cur_cv.max(1e-300)),
        runner_up: runner.map(|r| r.kind.name().to_string()),
        test,
    }
}

/// The step that adds two effects together.
fn pair_step(pair: &[EffectKind; 2], cur_cv: f64, pair_cv: f64, test: Test) -> StepOut {
    StepOut {
        added: format!("{} + {}", pair[0].name(), pair[1].name()),
        part: ScoredIn::All,
        gap_before_mm: cur_cv,
        gap_after_mm: pair_cv,
        drop_pct: 100.0 * (1.0 - pair_cv / cur_cv.max(1e-300)),
        runner_up: None,
        test: Some(test),
    }
}

/// Ties with a thermal rival that did not pass on its own. A rival whose
/// parameters the data cannot pin (a lag whose time constants reach their
/// bound, longer than the session: the links then barely warm, which is
/// what a negative scale on the expansion says too) is never eligible, so
/// it never stands as a runner-up; yet it may explain all the effect
/// chosen explains. Where the chosen effect adds nothing significant
/// beyond the rival put in its place, and the rival itself adds
/// significantly beyond the rest, the data cannot tell the two apart: the
/// pair is said, with how to separate them. Thermal pairs only: they share
/// the temperatures' time course, and a lag is the one effect whose
/// parameters run to a bound within what the data show (on the widened
/// evaluation, 8 of the 15 missed lags: withheld at the 600 min bound,
/// named as an expansion scaled by about −1).
fn unpassed_rivals(
    problem: &Problem,
    chosen: &[EffectKind],
    selected: &[EffectKind],
    offered: &[EffectKind],
    known: &[Ambiguity],
    noise: &TestNoise,
) -> Vec<Ambiguity> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let paired = |a: EffectKind, b: EffectKind| {
        known
            .iter()
            .any(|p| p.pair.iter().any(|n| n == a.name()) && p.pair.iter().any(|n| n == b.name()))
    };
    let mut out = Vec::new();
    for &c in chosen.iter().filter(|k| k.is_thermal()) {
        let without: Vec<EffectKind> = selected.iter().copied().filter(|k| *k != c).collect();
        let rest = if without.is_empty() {
            Some((problem.residuals(&[], &all).norm_squared(), 0))
        } else {
            fit::fit(problem, &all, &without)
                .ok()
                .map(|f| (f.rss, f.n_free))
        };
        let Some((rss_rest, free_rest)) = rest else {
            continue;
        };
        for &r in offered {
            if !r.is_thermal() || selected.contains(&r) || paired(c, r) {
                continue;
            }
            let mut swapped = without.clone();
            swapped.push(r);
            let mut both = selected.to_vec();
            both.push(r);
            let (Ok(alone), Ok(both)) = (
                fit::fit(problem, &all, &swapped),
                fit::fit(problem, &all, &both),
            ) else {
                continue;
            };
            let chosen_beyond = noise.nested_fit(alone.rss, alone.n_free, &both, LEVEL);
            let rival_own = noise.nested_fit(rss_rest, free_rest, &alone, LEVEL);
            if !chosen_beyond.significant() && rival_own.significant() {
                out.push(Ambiguity {
                    pair: [c.name().into(), r.name().into()],
                    correlation: None,
                    separate_by: Separation::of(c, r),
                });
            }
        }
    }
    out
}

/// Mark the `candidates` that are `selected`, each with its parameters of
/// the final `fit` (a candidate's own fit alone is what it was scored by).
pub fn mark_selected(candidates: &mut [CandidateOut], selected: &[EffectKind], fit: &fit::Fit) {
    let finals = params_out(fit);
    for c in candidates {
        c.selected = selected.iter().any(|k| k.name() == c.name);
        if c.selected {
            c.params = finals
                .iter()
                .filter(|p| p.name.starts_with(&format!("{}.", c.name)))
                .cloned()
                .collect();
        }
    }
}

impl Forward {
    /// Nothing selected on `problem`: its residual as the model in use
    /// leaves it.
    pub fn empty(problem: &Problem) -> Forward {
        let all: Vec<usize> = (0..problem.rows.len()).collect();
        Forward {
            selected: Vec::new(),
            cv0: f64::NAN,
            cv: f64::NAN,
            fit: None,
            rss0: problem.residuals(&[], &all).norm_squared(),
            free0: 0,
            steps: Vec::new(),
            candidates: Vec::new(),
            ambiguities: Vec::new(),
        }
    }

    /// The fitted effects of the selected kinds (the base left out).
    pub fn effects(&self) -> Vec<crate::model::Effect> {
        self.fit
            .iter()
            .flat_map(|f| f.effects.iter())
            .filter(|e| self.selected.contains(&e.kind))
            .cloned()
            .collect()
    }
}

/// The best pair of the three best single candidates, added together,
/// when it is significant at the stage's level shared among the pairs
/// tried and, where the design allows, lowers the held-out gap.
#[allow(clippy::too_many_arguments)]
fn best_pair(
    problem: &Problem,
    folds: &Folds,
    selected: &[EffectKind],
    scored: &[select::Scored],
    cur_cv: f64,
    cur_rss: f64,
    cur_free: usize,
    noise: &TestNoise,
    held_out: Option<f64>,
) -> Result<Option<([EffectKind; 2], fit::Fit, f64)>> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let top: Vec<EffectKind> = scored
        .iter()
        .filter(|s| s.fit.is_some())
        .take(3)
        .map(|s| s.kind)
        .collect();
    let pairs = (top.len() * top.len().saturating_sub(1) / 2).max(1);
    let level = LEVEL / pairs as f64;
    let mut best: Option<([EffectKind; 2], fit::Fit, f64)> = None;
    for (i, &a) in top.iter().enumerate() {
        for &b in &top[i + 1..] {
            let mut kinds = selected.to_vec();
            kinds.extend([a, b]);
            let Ok(f) = fit::fit(problem, &all, &kinds) else {
                continue;
            };
            if !(pinned(&f, a) && pinned(&f, b)) {
                continue;
            }
            let t = noise.nested_fit(cur_rss, cur_free, &f, level);
            if !t.significant() {
                continue;
            }
            let Ok(cv) = select::cv_rms(problem, folds, &kinds) else {
                continue;
            };
            if held_out.is_some_and(|m| cv.powi(2) >= cur_cv.powi(2) - m) {
                continue;
            }
            if best.as_ref().is_none_or(|(_, _, c)| cv < *c) {
                best = Some(([a, b], f, cv));
            }
        }
    }
    Ok(best)
}
