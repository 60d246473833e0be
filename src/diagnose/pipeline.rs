//! The diagnosis itself: the noise level, held-out scores of every
//! candidate effect, forward selection while the held-out gap still drops
//! clearly, the final fit, and the verdict.

use super::detect;
use super::detect::DetectionLimit;
use super::drift;
use super::fit::Problem;
use super::forward::{params_out, Forward};
use super::gap::{first_residual, gap_stats, noise_level, orientation_weight, Noise};
use super::joint_signature;
use super::judge::{advise, combine, with_remainder};
use super::listed::{has_place, is_origin_param};
use super::locate;
pub use super::options::DiagnoseOptions;
use super::prepare::Prepared;
use super::saved;
use super::select;
use super::stability;
use super::stages::{Ctx, Stage};
use super::stats::LEVEL;
use super::temps;
use super::test_noise::TestNoise;
use super::verdict::{
    Ambiguity, CandidateOut, Diagnosis, NotNamed, ParamOut, ScoredIn, StageSummary, StepOut,
    Verdict,
};
use crate::error::{Error, Result};
use crate::model::{EffectEntry, EffectKind, Model};

/// Rows enough, spread over enough poses and times, to tell what changes
/// with time from what stays: at least 3 poses each measured at 4 or more
/// distinct times.
fn repeats_over_time(problem: &Problem) -> bool {
    let mut times: std::collections::HashMap<usize, Vec<f64>> = Default::default();
    for r in &problem.rows {
        times.entry(r.pose).or_default().push(r.time_min);
    }
    let repeated = times
        .values_mut()
        .filter_map(|ts| {
            ts.sort_by(f64::total_cmp);
            ts.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
            (ts.len() >= 4).then_some(())
        })
        .count();
    repeated >= 3
}

/// Diagnose the gap of the prepared data.
///
/// Where poses are measured again and again as the robot warms, the
/// diagnosis works in two stages. First what changes with time: every pose
/// gets its own constant offset, which takes up whatever stays the same at
/// every visit (the arm's geometric error of any form, the reflector, the
/// instrument's frame, sag), so that a thermal effect is named only when it
/// is significant against the noise over time and predicts held-out time
/// spans better. A step in time found there is removed from the data before
/// the second stage. Then what stays, with the thermal effects found held
/// fixed: the static effects, tested on the poses' means and held out by
/// pose where the poses are enough. Data without such repeats are judged in
/// one stage over all effects.
pub fn diagnose(prepared: &Prepared, opts: &DiagnoseOptions) -> Result<Diagnosis> {
    let (as_said, temp_source) = as_said(prepared, opts)?;
    let problem = &as_said;
    let n = problem.rows.len();
    let all: Vec<usize> = (0..n).collect();
    let gaps_before = problem.position_gaps(&[], &all);
    let gap = gap_stats(&gaps_before);
    let (mut noise, measured) = measured_noise(problem, &gaps_before, opts, &all)?;
    let Tuned {
        problem: tuned,
        n_poses,
        static_rank,
        width,
        static_judged,
    } = tuned(problem, &noise, &all);
    let problem = &tuned;
    let folds = folds(problem, opts)?;
    let static_held_out = static_held_out(problem, &folds, width, static_rank);
    let pool = pool(problem, temp_source.drives());
    let where_ = locate::locate(problem, &gaps_before, &prepared.pose_names, noise.rms_mm);
    let mut tnoise = test_noise(&noise, measured);

    let ctx = Ctx {
        problem,
        folds: &folds,
        noise: tnoise,
        max_effects: opts.max_effects,
        n_poses,
        static_judged,
        static_held_out,
        temps_drive: temp_source.drives(),
    };
    // Two stages need the noise measured: what is left over time is
    // judged against it (a step, the square, the lack of fit).
    let two = measured && repeats_over_time(problem);
    let (stages, final_problem, parts, knock, quadratic, searched) =
        ctx.stages(&pool, two, width)?;
    let joint_signature::Searched {
        found: joint_sig,
        limits: joint_limits,
    } = searched;
    let last = stages.last().map(|s| &s.forward);
    // Before: the model in use, every position as measured (no pose
    // offsets), on the same held-out folds as the last stage's score.
    let cv0 = select::cv_rms(problem, &folds, &[])?;
    let cur_cv = last.map_or(cv0, |f| f.cv);
    let last_effects = fitted_effects(last);
    let gaps_after = final_problem.position_gaps(&last_effects, &all);
    // Where the noise was not measured, the level reported (and the one
    // the detection limits are held to) is what the final model leaves:
    // its residual sum of squares over its degrees of freedom.
    if !measured {
        let (rss, free) = last.map_or((0.0, 0), |f| f.rss());
        noise = Noise::from_residual(rss, (n * width).saturating_sub(free));
        tnoise = test_noise(&noise, measured);
    }
    // Without temperatures, what changes over time is a drift in time,
    // said with its shape and size: with poses repeated, beyond each
    // pose's own offset; else beyond the model and a constant.
    let time_drift = time_drift(&ctx, &final_problem, &gaps_after, two, last, &tnoise);
    let Limits {
        detection_limits,
        stability,
        not_named,
    } = limits(
        &stages,
        problem,
        &final_problem,
        &last_effects,
        &tnoise,
        two,
    );
    let mut verdict = combined(&stages, time_drift.as_ref());
    let out: Vec<EffectKind> = not_named.iter().map(|n| n.effect).collect();
    verdict = verdict.without(&out);
    let Reported {
        candidates,
        steps,
        ambiguities,
        fitted,
    } = report(&stages, parts, &out, static_judged, problem);
    // What the first of two stages leaves over time is located with each
    // pose's own offset taken out: static error the poses cannot attribute
    // would otherwise hide it (a knock at minute 88 under tenths of a mm of
    // geometry).
    let time_left = left_over_time(&stages);
    let where_after = where_after(
        problem,
        &all,
        &gaps_after,
        &prepared.pose_names,
        noise.rms_mm,
        time_left,
        knock,
    );
    // Every number after the diagnosis is the saved model's: its effects
    // fitted without each fold's rows, written, read back and scored on
    // them as `gap --model` scores a file (`saved.rs`). What the model
    // cannot hold (each pose's own offset, a step removed, the square, a
    // signature) is not in it.
    let saved = saved_score(prepared, problem, &folds, &fitted, stages.len() > 1, opts)?;
    let cur_cv = saved.as_ref().map_or(cur_cv, |s| s.held_out_mm);
    let (gap_after, gaps_after) = match &saved {
        Some(s) => (s.gap, s.gaps.clone()),
        None => (gap_stats(&gaps_after), gaps_after),
    };
    let advice = advise(
        &verdict,
        cv0,
        cur_cv,
        &noise,
        [&where_, &where_after],
        joint_sig.as_ref().map(|s| s.axis),
    );
    let partial = partial(&verdict);
    Ok(Diagnosis {
        verdict,
        gap_before_mm: cv0,
        gap_after_mm: cur_cv,
        gap,
        gap_after,
        noise,
        level: LEVEL,
        candidates,
        steps,
        ambiguous: ambiguities.iter().map(|a| a.pair.clone()).collect(),
        ambiguities,
        partial,
        where_,
        where_after,
        left_over_time: time_left,
        quadratic_growth: quadratic,
        joint_signature: joint_sig,
        joint_limits,
        detection_limits,
        registration: prepared.registration.clone(),
        temperatures: temp_source,
        time_drift,
        stability,
        not_named,
        stages: summaries(&stages, parts),
        advice,
        fitted,
        gaps_before,
        gaps_after,
        saved,
    })
}

/// Whether the first of two stages leaves something over time: unexplained,
/// or explained with a remainder.
fn left_over_time(stages: &[Stage]) -> bool {
    stages.len() > 1
        && matches!(
            stages.first().map(|s| &s.verdict),
            Some(Verdict::Unexplained { .. })
                | Some(Verdict::ExplainedBy {
                    remainder: true,
                    ..
                })
                | Some(Verdict::Ambiguous {
                    remainder: true,
                    ..
                })
        )
}

/// Each stage in short: its part, its held-out gap before and after, what
/// it selected, and its test of what is left.
fn summaries(stages: &[Stage], parts: [ScoredIn; 2]) -> Vec<StageSummary> {
    stages
        .iter()
        .zip(parts)
        .map(|(st, part)| StageSummary {
            part,
            gap_before_mm: st.forward.cv0,
            gap_after_mm: st.forward.cv,
            effects: st
                .forward
                .selected
                .iter()
                .map(|k| k.name().to_string())
                .collect(),
            judged: st.judged,
            lack_of_fit: st.lack_of_fit,
        })
        .collect()
}

/// Held out by pose where every fold keeps more numbers than the static
/// rank: else a held-out pose cannot be predicted, and the tests stand on
/// the fitted data alone.
fn static_held_out(
    problem: &Problem,
    folds: &select::Folds,
    width: usize,
    static_rank: usize,
) -> Option<f64> {
    folds
        .folds
        .iter()
        .all(|(train, _)| {
            let poses: std::collections::BTreeSet<usize> =
                train.iter().map(|&i| problem.rows[i].pose).collect();
            width * poses.len() > static_rank
        })
        .then_some(0.0)
}

/// The candidate effects: every kind but a lag already fixed, and the
/// thermal ones only where temperatures drive them.
fn pool(problem: &Problem, temps_drive: bool) -> Vec<EffectKind> {
    let lag_fixed = problem
        .fixed
        .iter()
        .any(|e| e.kind == EffectKind::ThermalLag);
    EffectKind::ALL
        .into_iter()
        .filter(|k| !(lag_fixed && *k == EffectKind::ThermalLag))
        .filter(|k| temps_drive || !k.is_thermal())
        .collect()
}

/// Without temperatures, a drift in time beyond what the diagnosis fitted
/// (see [`drift::find`]); `None` where temperatures drive the model.
fn time_drift(
    ctx: &Ctx,
    final_problem: &Problem,
    gaps_after: &[nalgebra::Vector3<f64>],
    two: bool,
    last: Option<&Forward>,
    tnoise: &TestNoise,
) -> Option<drift::TimeDrift> {
    if ctx.temps_drive {
        return None;
    }
    let times: Vec<f64> = final_problem.rows.iter().map(|r| r.time_min).collect();
    let poses: Vec<usize> = final_problem.rows.iter().map(|r| r.pose).collect();
    let free = if two {
        0
    } else {
        last.map_or(0, |f| f.rss().1)
    };
    let level = if two {
        ctx.remainder_level()
    } else {
        ctx.one_stage_level()
    };
    drift::find(&times, &poses, gaps_after, two, free, tnoise, level)
}

/// The noise as the tests take it: its variance per axis and its degrees
/// of freedom.
fn test_noise(noise: &Noise, measured: bool) -> TestNoise {
    TestNoise {
        rms_mm: noise.rms_mm,
        sigma2: noise.per_axis_mm * noise.per_axis_mm,
        dof: noise.dof(),
        measured,
    }
}

/// The problem as the fits take it, and what the poses allow of the static
/// stage.
struct Tuned {
    /// Its noise, orientation weight and joint origins set from the data.
    problem: Problem,
    n_poses: usize,
    /// The rank a full kinematic calibration with the instrument frame takes.
    static_rank: usize,
    /// Numbers per row.
    width: usize,
    /// The poses give more numbers than `static_rank`.
    static_judged: bool,
}

/// Tune `problem` to the noise of these data and tell whether its static
/// stage can be judged.
fn tuned(problem: &Problem, noise: &Noise, all: &[usize]) -> Tuned {
    // Fits judge identifiability against the noise of these data.
    let tuned = Problem {
        noise_mm: noise.per_axis_mm,
        w_ori: orientation_weight(problem, noise),
        origins: true,
        ..problem.clone()
    }
    .with_zero_jacobians();
    let n_poses = tuned.rows.iter().map(|r| r.pose + 1).max().unwrap_or(0);
    // The static stage can be judged where the poses give more numbers than
    // a full kinematic calibration (with the instrument frame) can take up:
    // what is left then has degrees of freedom of its own.
    let static_rank =
        tuned.identifiable_rank(&[EffectKind::GeometryOffset, EffectKind::TrackerFrame], all);
    let width = tuned.width();
    let static_judged = width * n_poses > static_rank;
    let tuned = Problem {
        origins: static_judged,
        ..tuned
    };
    Tuned {
        problem: tuned,
        n_poses,
        static_rank,
        width,
        static_judged,
    }
}

/// Of the effects the stages selected, those their final fits do not pin.
fn unpinned(stages: &[Stage]) -> Vec<EffectKind> {
    stages
        .iter()
        .filter_map(|st| st.forward.fit.as_ref().map(|f| (f, &st.forward.selected)))
        .flat_map(|(f, sel)| {
            sel.iter()
                .copied()
                .filter(|k| !super::forward::pinned(f, *k))
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Where the gap is after the diagnosis: with each pose's own offset taken
/// out where the first of two stages leaves something over time, and the
/// step found there added.
fn where_after(
    problem: &Problem,
    all: &[usize],
    gaps_after: &[nalgebra::Vector3<f64>],
    pose_names: &[String],
    noise_rms_mm: f64,
    time_left: bool,
    knock: Option<locate::Step>,
) -> locate::Where {
    if time_left {
        let centred = Problem {
            centre_poses: true,
            ..problem.clone()
        };
        let left = select::centred(&centred, all, gaps_after.to_vec());
        let w = locate::locate(&centred, &left, pose_names, noise_rms_mm);
        match knock {
            Some(step) => w.with_step(step),
            None => w,
        }
    } else {
        locate::locate(problem, gaps_after, pose_names, noise_rms_mm)
    }
}

/// The saved model's scores, where the data came with a model file.
fn saved_score(
    prepared: &Prepared,
    problem: &Problem,
    folds: &select::Folds,
    fitted: &[EffectEntry],
    two_stages: bool,
    opts: &DiagnoseOptions,
) -> Result<Option<saved::Saved>> {
    Ok(match &prepared.source {
        Some(source) => Some(saved::score(
            source,
            prepared.registration.as_ref(),
            problem,
            folds,
            fitted,
            two_stages,
            opts.assume_cold_start,
        )?),
        None => None,
    })
}

/// What the data could reveal beyond everything fitted, and which of the
/// effects selected are said rather than named.
struct Limits {
    detection_limits: Vec<DetectionLimit>,
    stability: Vec<stability::Stability>,
    not_named: Vec<NotNamed>,
}

/// The detection limits beyond everything fitted, the stability of what
/// was selected, and what is not named for want of either.
fn limits(
    stages: &[Stage],
    problem: &Problem,
    final_problem: &Problem,
    last_effects: &[crate::model::Effect],
    tnoise: &TestNoise,
    two: bool,
) -> Limits {
    // Detection limits beyond everything fitted: the thermal effects held
    // fixed in the last stage's problem and its own effects, on the data
    // as the diagnosis ended with them (a step removed).
    let mut found: Vec<crate::model::Effect> = final_problem.fixed[problem.fixed.len()..].to_vec();
    found.extend(last_effects.iter().cloned());
    let judged = Problem {
        fixed: problem.fixed.clone(),
        ..final_problem.clone()
    };
    let detection_limits = detect::limits(&judged, &found, tnoise, two);
    // Named only what the data pin, above what they could reveal, and
    // again over resampled fits: of the effects the stages selected, the
    // others are said, not named.
    let unpinned = unpinned(stages);
    let below = detect::below(&judged, &found, tnoise, two);
    let stability: Vec<stability::Stability> =
        stages.iter().flat_map(|st| st.stability.clone()).collect();
    let not_named = NotNamed::of(&unpinned, &below, &stability);
    Limits {
        detection_limits,
        stability,
        not_named,
    }
}

/// The effects an unexplained verdict names as explaining part of the gap.
fn partial(verdict: &Verdict) -> Vec<String> {
    match verdict {
        Verdict::Unexplained { partial } => partial.iter().map(|k| k.name().to_string()).collect(),
        _ => Vec::new(),
    }
}

/// The problem with its temperatures as the data say them, refused where
/// its rows are too few for a diagnosis.
fn as_said(prepared: &Prepared, opts: &DiagnoseOptions) -> Result<(Problem, temps::TempSource)> {
    // Without a source of temperatures every row is held at the reference
    // temperature: the model's profile would be a heating (of an IRB 140,
    // from a cold start at the first row) that the data do not show.
    let mut as_said = prepared.problem.clone();
    let temp_source = temps::as_said(&mut as_said, &prepared.temps, opts.assume_cold_start)?;
    const MIN_ROWS: usize = 20;
    let n = as_said.rows.len();
    if n < MIN_ROWS {
        return Err(Error::input(format!(
            "too few measurements for a diagnosis: {n} rows (at least {MIN_ROWS}, spread over poses and times)"
        )));
    }
    Ok((as_said, temp_source))
}

/// The noise of the data, and whether it was measured (or given) rather
/// than taken from what a first fit leaves.
fn measured_noise(
    problem: &Problem,
    gaps_before: &[nalgebra::Vector3<f64>],
    opts: &DiagnoseOptions,
    all: &[usize],
) -> Result<(Noise, bool)> {
    let mut noise = noise_level(problem, gaps_before, opts.noise_mm)?;
    let measured = noise.measured();
    if !measured {
        noise = first_residual(problem, all);
    }
    Ok((noise, measured))
}

/// The stages' verdicts as one, with a remainder where a drift in time is
/// left that the data could not have missed.
fn combined(stages: &[Stage], time_drift: Option<&drift::TimeDrift>) -> Verdict {
    let mut verdict = combine(stages.iter().map(|s| s.verdict.clone()).collect());
    if time_drift.is_some_and(|t| t.below_limit_mm.is_none()) {
        verdict = with_remainder(verdict);
    }
    verdict
}

/// The effects of the last stage's fit: earlier stages' effects are fixed
/// in its problem.
fn fitted_effects(last: Option<&Forward>) -> Vec<crate::model::Effect> {
    last.and_then(|f| f.fit.as_ref())
        .map(|f| f.effects.clone())
        .unwrap_or_default()
}

/// The held-out folds, refused where they are fewer than two.
fn folds(problem: &Problem, opts: &DiagnoseOptions) -> Result<select::Folds> {
    let folds = select::make_folds(problem, opts.folds);
    if folds.folds.len() < 2 {
        return Err(Error::input(
            "too few measurements for cross-validation: need several poses or times",
        ));
    }
    Ok(folds)
}

/// What the stages found, as reported: every candidate with its parameters
/// (those of the final fit where selected), the steps and ambiguities met,
/// and the effects fitted for the saved model.
struct Reported {
    candidates: Vec<CandidateOut>,
    steps: Vec<StepOut>,
    ambiguities: Vec<Ambiguity>,
    fitted: Vec<EffectEntry>,
}

/// Gather what each stage found into what is reported, leaving out the
/// effects `out` (said, not named).
fn report(
    stages: &[Stage],
    parts: [ScoredIn; 2],
    out: &[EffectKind],
    static_judged: bool,
    problem: &Problem,
) -> Reported {
    let mut candidates = Vec::new();
    let mut steps = Vec::new();
    let mut ambiguities = Vec::new();
    let mut fitted = Vec::new();
    for (stage, part) in stages.iter().zip(parts) {
        let f = &stage.forward;
        // What each stage selected, with the parameters of its final fit
        // (the base an absolute pass fitted with them left out).
        let finals = f.fit.as_ref().map(params_out).unwrap_or_default();
        for c in &f.candidates {
            // What is not named is not reported as selected, nor saved.
            let selected = f
                .selected
                .iter()
                .any(|k| k.name() == c.name && !out.contains(k));
            let prefix = format!("{}.", c.name);
            // Geometry's joint origins are not fitted from too few poses:
            // not listed, rather than listed as unidentifiable.
            let listed = |p: &ParamOut| {
                (static_judged || !is_origin_param(&p.name))
                    && has_place(&problem.base.nominal, &p.name)
            };
            candidates.push(CandidateOut {
                part,
                selected,
                params: if selected {
                    finals
                        .iter()
                        .filter(|p| p.name.starts_with(&prefix) && listed(p))
                        .cloned()
                        .collect()
                } else {
                    c.params.iter().filter(|p| listed(p)).cloned().collect()
                },
                ..c.clone()
            });
        }
        steps.extend(f.steps.iter().map(|s| StepOut { part, ..s.clone() }));
        ambiguities.extend(f.ambiguities.iter().cloned());
        if let Some(fit) = &f.fit {
            fitted.extend(
                fit.effects
                    .iter()
                    .zip(&fit.params)
                    .filter(|(e, _)| f.selected.contains(&e.kind) && !out.contains(&e.kind))
                    .map(|(e, ps)| {
                        let se: Vec<Option<f64>> = ps.iter().map(|p| p.stderr).collect();
                        EffectEntry::from_effect(e, Some(&se))
                    }),
            );
        }
    }
    Reported {
        candidates,
        steps,
        ambiguities,
        fitted,
    }
}

/// The model with the diagnosed effects added: the saved model where the
/// diagnosis was of measurements (its arm, measured point and instrument
/// frame with it), else `model` with the effects.
pub fn diagnosed_model(model: &Model, diagnosis: &Diagnosis) -> Model {
    if let Some(s) = &diagnosis.saved {
        return s.model.clone();
    }
    let mut m = model.clone();
    m.effects.extend(diagnosis.fitted.iter().cloned());
    m
}
