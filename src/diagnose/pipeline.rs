//! The diagnosis itself: the noise level, held-out scores of every
//! candidate effect, forward selection while the held-out gap still drops
//! clearly, the final fit, and the verdict.

use super::fit::{self, Problem};
use super::gap::{gap_stats, noise_level, orientation_weight, NoiseSource};
use super::locate::{self, Where};
use super::prepare::Prepared;
use super::select;
use super::verdict::{Advice, Ambiguity, CandidateOut, Diagnosis, ParamOut, StepOut, Verdict};
use crate::error::{Error, ErrorKind, Result};
use crate::model::{EffectEntry, EffectKind, Model};

/// Options of a diagnosis.
#[derive(Debug, Clone)]
pub struct Options {
    /// Tracker noise per axis (mm, positive); `None`: estimate, else the
    /// instrument's default.
    pub noise_mm: Option<f64>,
    /// Number of cross-validation folds.
    pub folds: usize,
    /// Most effects forward selection adds.
    pub max_effects: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            noise_mm: None,
            folds: 4,
            max_effects: 3,
        }
    }
}

fn params_out(fit: &fit::Fit) -> Vec<ParamOut> {
    fit.effects
        .iter()
        .zip(&fit.params)
        .flat_map(|(e, ps)| {
            e.kind.params().iter().zip(ps).map(|(info, p)| ParamOut {
                name: format!("{}.{}", e.kind.name(), info.name),
                unit: info.unit.to_string(),
                value: p.value,
                stderr: p.stderr,
            })
        })
        .collect()
}

/// Diagnose the gap of the prepared data.
pub fn diagnose(prepared: &Prepared, opts: &Options) -> Result<Diagnosis> {
    let problem = &prepared.problem;
    let n = problem.rows.len();
    const MIN_ROWS: usize = 20;
    if n < MIN_ROWS {
        return Err(Error::input(format!(
            "too few measurements for a diagnosis: {n} rows (at least {MIN_ROWS}, spread over poses and times)"
        )));
    }
    let all: Vec<usize> = (0..n).collect();
    let gaps_before = problem.position_gaps(&[], &all);
    let gap = gap_stats(&gaps_before);
    let noise = noise_level(problem, &gaps_before, opts.noise_mm)?;
    // Fits judge identifiability against the noise of these data.
    let tuned = Problem {
        noise_mm: noise.per_axis_mm,
        w_ori: orientation_weight(problem, &noise),
        ..problem.clone()
    }
    .with_zero_jacobians();
    let problem = &tuned;
    let folds = select::make_folds(problem, opts.folds);
    if folds.folds.len() < 2 {
        return Err(Error::input(
            "too few measurements for cross-validation: need several poses or times",
        ));
    }
    let cv0 = select::cv_rms(problem, &folds, &[])?;
    let rss0: f64 = gaps_before.iter().map(|g| g.norm_squared()).sum();
    let n_obs = (3 * n) as f64;
    let bic0 = n_obs * (rss0.max(1e-300) / n_obs).ln();

    let lag_fixed = problem
        .fixed
        .iter()
        .any(|e| e.kind == EffectKind::ThermalLag);
    let mut pool: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .filter(|k| !(lag_fixed && *k == EffectKind::ThermalLag))
        .collect();
    // The slowest fit first, so that the threads finish together.
    pool.sort_by_key(|k| *k != EffectKind::ThermalLag);
    let mut selected: Vec<EffectKind> = Vec::new();
    let mut current_fit: Option<fit::Fit> = None;
    let mut cur_cv = cv0;
    let mut cur_bic = bic0;
    let mut steps = Vec::new();
    let mut candidates: Vec<CandidateOut> = Vec::new();
    let mut ambiguities = Vec::new();
    let nr2 = noise.rms_mm * noise.rms_mm;
    while selected.len() < opts.max_effects && !pool.is_empty() {
        let cur_effects = current_fit
            .as_ref()
            .map(|f| f.effects.clone())
            .unwrap_or_default();
        let mut scored = select::score_candidates(problem, &folds, &selected, &cur_effects, &pool);
        if steps.is_empty() {
            candidates = scored
                .iter()
                .map(|s| CandidateOut {
                    name: s.kind.name().into(),
                    explained: 1.0 - (s.cv_rms_mm / cv0.max(1e-300)).powi(2),
                    cv_rms_mm: s.cv_rms_mm,
                    bic: s.fit.as_ref().map(fit::Fit::bic),
                    params: s.fit.as_ref().map(params_out).unwrap_or_default(),
                    selected: false,
                    error: s.error.clone(),
                })
                .collect();
        }
        scored.sort_by(|a, b| a.cv_rms_mm.total_cmp(&b.cv_rms_mm));
        let Some(best) = scored.first() else { break };
        let Some(best_fit) = best.fit.clone() else {
            break;
        };
        let drop_ok = best.cv_rms_mm < 0.9 * cur_cv
            && cur_cv * cur_cv - best.cv_rms_mm * best.cv_rms_mm > 0.2 * nr2
            && best_fit.bic() < cur_bic - 10.0;
        if !drop_ok {
            break;
        }
        let runner = scored.get(1).filter(|r| r.fit.is_some());
        if let Some(r) = runner {
            let corr = select::collinearity(&best.contribution, &r.contribution);
            // Nearly equal held-out scores: closer than a quarter of the
            // noise variance (the scores' own scatter is a few percent of it).
            let close = r.cv_rms_mm * r.cv_rms_mm - best.cv_rms_mm * best.cv_rms_mm < 0.25 * nr2;
            if corr > 0.95 && close {
                ambiguities.push(Ambiguity {
                    pair: [best.kind.name().into(), r.kind.name().into()],
                    correlation: corr,
                    separate_by: select::separating_advice(best.kind, r.kind),
                });
            }
        }
        steps.push(StepOut {
            added: best.kind.name().into(),
            gap_before_mm: cur_cv,
            gap_after_mm: best.cv_rms_mm,
            drop_pct: 100.0 * (1.0 - best.cv_rms_mm / cur_cv.max(1e-300)),
            runner_up: runner.map(|r| r.kind.name().to_string()),
        });
        selected.push(best.kind);
        pool.retain(|k| *k != best.kind);
        cur_cv = best.cv_rms_mm;
        cur_bic = best_fit.bic();
        current_fit = Some(best_fit);
        if cur_cv <= 1.05 * noise.rms_mm {
            break;
        }
    }
    // The final model must come from a converged fit: refit and propagate.
    let final_fit = if selected.is_empty() {
        None
    } else {
        Some(fit::fit(problem, &all, &selected).map_err(|e| {
            if e.kind == ErrorKind::NoConvergence {
                Error::new(
                    ErrorKind::NoConvergence,
                    format!("{}; no verdict", e.message),
                )
            } else {
                e
            }
        })?)
    };
    let final_effects = final_fit
        .as_ref()
        .map(|f| f.effects.clone())
        .unwrap_or_default();
    let gaps_after = problem.position_gaps(&final_effects, &all);
    for c in &mut candidates {
        c.selected = selected.iter().any(|k| k.name() == c.name);
    }
    if let Some(f) = &final_fit {
        let finals = params_out(f);
        for c in &mut candidates {
            if c.selected {
                c.params = finals
                    .iter()
                    .filter(|p| p.name.starts_with(&format!("{}.", c.name)))
                    .cloned()
                    .collect();
            }
        }
    }

    let where_ = locate::locate(problem, &gaps_before, &prepared.pose_names, noise.rms_mm);
    let where_after = locate::locate(problem, &gaps_after, &prepared.pose_names, noise.rms_mm);
    let verdict = judge(&Scores {
        selected: &selected,
        cv0,
        cv: cur_cv,
        noise_rms_mm: noise.rms_mm,
        noise_assumed: noise.source == NoiseSource::Default,
        structured: where_.has_structure(),
        ambiguous: !ambiguities.is_empty(),
    });
    let advice = advise(
        &verdict,
        cv0,
        cur_cv,
        noise.rms_mm,
        noise.per_axis_mm,
        [&where_, &where_after],
    );
    let partial = match &verdict {
        Verdict::Unexplained { partial } => partial.iter().map(|k| k.name().to_string()).collect(),
        _ => Vec::new(),
    };
    let fitted = final_fit
        .as_ref()
        .map(|f| {
            f.effects
                .iter()
                .zip(&f.params)
                .map(|(e, ps)| {
                    let se: Vec<Option<f64>> = ps.iter().map(|p| p.stderr).collect();
                    EffectEntry::from_effect(e, Some(&se))
                })
                .collect()
        })
        .unwrap_or_default();
    Ok(Diagnosis {
        verdict,
        gap_before_mm: cv0,
        gap_after_mm: cur_cv,
        gap,
        gap_after: gap_stats(&gaps_after),
        noise,
        candidates,
        steps,
        ambiguous: ambiguities.iter().map(|a| a.pair.clone()).collect(),
        ambiguities,
        partial,
        where_,
        where_after,
        registration: prepared.registration.clone(),
        advice,
        fitted,
        gaps_before,
        gaps_after,
    })
}

/// What the verdict is judged on.
struct Scores<'a> {
    /// Effects forward selection added, in order.
    selected: &'a [EffectKind],
    /// Held-out RMS gap of the current model and with the selected
    /// effects, mm.
    cv0: f64,
    cv: f64,
    /// 3-D RMS of the noise, mm.
    noise_rms_mm: f64,
    /// The noise level is the instrument's default, not measured.
    noise_assumed: bool,
    /// The current model's gap shows structure (see [`Where::has_structure`]).
    structured: bool,
    /// A selected effect has a near-indistinguishable runner-up.
    ambiguous: bool,
}

fn judge(s: &Scores) -> Verdict {
    let nr2 = s.noise_rms_mm * s.noise_rms_mm;
    let base2 = s.cv0 * s.cv0;
    let fin2 = s.cv * s.cv;
    let excess_explained = if base2 > nr2 {
        (base2 - fin2) / (base2 - nr2)
    } else {
        1.0
    };
    if s.selected.is_empty() {
        // Without a measured noise level (no repeated poses) a gap above
        // the assumed level may just be a noisier instrument: call it
        // unexplained only with evidence of structure.
        if s.cv0 <= 1.5 * s.noise_rms_mm || (s.noise_assumed && !s.structured) {
            Verdict::None
        } else {
            Verdict::Unexplained {
                partial: Vec::new(),
            }
        }
    } else if s.cv <= 1.5 * s.noise_rms_mm || excess_explained >= 0.8 {
        let effects = s.selected.to_vec();
        // Most of the gap is explained, but clear structure remains: name
        // the effects and say that something else is there too.
        let remainder = s.cv > 2.0 * s.noise_rms_mm;
        if s.ambiguous {
            Verdict::Ambiguous { effects, remainder }
        } else {
            Verdict::ExplainedBy { effects, remainder }
        }
    } else {
        Verdict::Unexplained {
            partial: s.selected.to_vec(),
        }
    }
}

fn advise(
    verdict: &Verdict,
    cv0: f64,
    cv: f64,
    noise_rms_mm: f64,
    noise_per_axis_mm: f64,
    wheres: [&Where; 2],
) -> Advice {
    match verdict {
        Verdict::None if cv0 > 1.5 * noise_rms_mm => Advice::CheckNoise {
            assumed_mm: noise_per_axis_mm,
        },
        Verdict::None => Advice::Nothing,
        Verdict::Unexplained { .. } => Advice::LookThere {
            axis: wheres.iter().find_map(|w| w.joint.as_ref()).map(|j| j.axis),
            step_min: wheres
                .iter()
                .find_map(|w| w.step.as_ref())
                .map(|s| (s.before_min, s.after_min)),
        },
        Verdict::ExplainedBy { .. } | Verdict::Ambiguous { .. } => Advice::SaveModel {
            from_mm: cv0,
            to_mm: cv,
        },
    }
}

/// The model with the diagnosed effects added.
pub fn diagnosed_model(model: &Model, diagnosis: &Diagnosis) -> Model {
    let mut m = model.clone();
    m.effects.extend(diagnosis.fitted.iter().cloned());
    m
}
