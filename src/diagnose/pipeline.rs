//! The diagnosis itself: the noise level, held-out scores of every
//! candidate effect, forward selection while the held-out gap still drops
//! clearly, the final fit, and the verdict.

use super::detect;
use super::detect::DetectionLimit;
use super::drift;
use super::fit::{self, Problem};
use super::forward::{forward, params_out, Forward, Joint};
use super::gap::{first_residual, gap_stats, noise_level, orientation_weight, Noise};
use super::joint_signature;
use super::judge::{advise, combine, judge, with_remainder, Scores};
use super::knock;
use super::listed::{has_place, is_origin_param};
use super::locate;
pub use super::options::Options;
use super::prepare::Prepared;
use super::saved;
use super::select;
use super::separation::Separation;
use super::signature::QuadraticGrowth;
use super::square;
use super::stability;
use super::stats::{Test, LEVEL};
use super::step::{significant_step, step_of};
use super::temps;
use super::test_noise::TestNoise;
use super::verdict::{
    Ambiguity, CandidateOut, Diagnosis, NotNamed, ParamOut, Part, StageSummary, StepOut, Verdict,
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
pub fn diagnose(prepared: &Prepared, opts: &Options) -> Result<Diagnosis> {
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
fn summaries(stages: &[Stage], parts: [Part; 2]) -> Vec<StageSummary> {
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
    opts: &Options,
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
fn as_said(prepared: &Prepared, opts: &Options) -> Result<(Problem, temps::TempSource)> {
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
    opts: &Options,
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
fn folds(problem: &Problem, opts: &Options) -> Result<select::Folds> {
    let folds = select::make_folds(problem, opts.folds);
    if folds.folds.len() < 2 {
        return Err(Error::input(
            "too few measurements for cross-validation: need several poses or times",
        ));
    }
    Ok(folds)
}

/// The problem with each pose's own offset free.
fn centred_of(p: &Problem) -> Problem {
    Problem {
        centre_poses: true,
        ..p.clone()
    }
}

/// The data over time with a step of the whole robot removed where one
/// shows, and the thermal effects selected on them: the problem, its
/// centred form, the selection, and the step removed.
fn without_step(
    ctx: &Ctx,
    time_folds: &select::Folds,
    all: &[usize],
    over_time: &impl Fn(&Problem) -> Result<Forward>,
    mut problem: Problem,
    mut centred: Problem,
    mut thermal: Forward,
) -> Result<(Problem, Problem, Forward, Option<knock::Knock>)> {
    // A step of the whole robot (a knock, a loosened foot) is no effect of
    // the library: where what the thermal effects leave over time holds a
    // significant one, it is removed from the data (every row after it
    // shifted back) and the thermal effects are selected on what is left,
    // so that neither a thermal effect that half-follows it nor, later, a
    // static one that takes up its mean is named. Once a step shows, it is
    // taken whole, as the change over time alone shows it, before the
    // thermal effects are selected again: the step found beyond a mount
    // drift or a scaled expansion is only what they left of it, and the
    // data corrected by that part still held a step for them to follow.
    // The step and the thermal effects are then found in turn (each given
    // the other, as a joint fit would), a few rounds at most; where the
    // thermal effects found explain the change without a step, the data go
    // back as measured.
    let original = centred.clone();
    let as_measured = thermal.clone();
    // The held-out gap over time before anything is that of the data as
    // measured, whatever is later removed from them (a step, a growth with
    // the square): else the stage's shrink would be measured from data
    // already corrected.
    let cv0_measured = thermal.cv0;
    // The step against the selection as measured. Tested only beyond the
    // effects selected, a mount drift that followed most of a knock early
    // in the warm-up left too little of it to test; tested first, a step
    // takes up most of a smooth drift. Where the step passes its test
    // beyond nothing (each pose's own offset) but not beyond the effects
    // selected, the two are alternatives, and the one that predicts the
    // held-out spans better is taken, as between candidates: the step
    // then goes first, and the thermal effects must add significantly
    // beyond it.
    let step_first = || {
        if thermal.selected.is_empty()
            || significant_step(
                &original,
                &Forward::empty(&original),
                &ctx.noise,
                ctx.remainder_level(),
                ctx.temps_drive,
            )
            .is_none()
        {
            return false;
        }
        let gaps = original.position_gaps(&[], all);
        knock::score(&original, time_folds, &gaps).is_some_and(|(cv, _)| cv < thermal.cv)
    };
    if significant_step(
        &original,
        &thermal,
        &ctx.noise,
        ctx.remainder_level(),
        ctx.temps_drive,
    )
    .is_some()
        || step_first()
    {
        thermal = Forward::empty(&original);
    }
    let mut knocked = None;
    for _ in 0..3 {
        let Some(k) = significant_step(
            &original,
            &thermal,
            &ctx.noise,
            ctx.remainder_level(),
            ctx.temps_drive,
        ) else {
            if knocked.is_none() {
                thermal = as_measured;
            } else if knocked.take().is_some() {
                // The thermal effects found on the corrected data explain
                // the change without a step: back to the data as measured.
                problem = ctx.problem.clone();
                centred = original.clone();
                thermal = over_time(&centred)?;
            }
            break;
        };
        let same = knocked.as_ref().is_some_and(|p: &knock::Knock| {
            p.after_min == k.after_min && (p.shift_mm - k.shift_mm).norm() < 0.1 * ctx.noise.rms_mm
        });
        let mut corrected = ctx.problem.clone();
        for r in &mut corrected.rows {
            if r.time_min >= k.after_min - 1e-9 {
                r.position -= k.shift_mm;
            }
        }
        problem = corrected;
        centred = centred_of(&problem);
        knocked = Some(k);
        if same {
            break;
        }
        thermal = over_time(&centred)?;
    }
    if knocked.is_some() {
        thermal.cv0 = cv0_measured;
    }
    Ok((problem, centred, thermal, knocked))
}

/// The data over time with a growth with the square of the temperatures
/// removed where it is taken: the problem, its centred form, the thermal
/// selection, the growth (taken or beside), and the parameters it took.
fn with_square(
    ctx: &Ctx,
    time_folds: &select::Folds,
    over_time: &impl Fn(&Problem) -> Result<Forward>,
    mut problem: Problem,
    mut centred: Problem,
    mut thermal: Forward,
) -> Result<(Problem, Problem, Forward, Option<QuadraticGrowth>, usize)> {
    // A growth with the square of the temperatures, a candidate beside the
    // thermal effects (`square.rs`): where it is taken, it is removed from
    // the data and the effects are those selected beyond it; else it may
    // still be reported beside them, and what it replaces is not named.
    let mut square_params = 0;
    if ctx.temps_drive {
        thermal = square::library_first(
            &centred,
            thermal,
            &ctx.noise,
            ctx.remainder_level(),
            |alt| {
                forward(
                    &centred,
                    time_folds,
                    alt,
                    &[],
                    &ctx.noise,
                    ctx.max_effects,
                    Some(0.0),
                    None,
                )
            },
        )?;
    }
    // The square of the temperatures' rise needs temperatures.
    let choice = if ctx.temps_drive {
        square::choose(
            &problem,
            &centred,
            &thermal,
            &ctx.noise,
            ctx.remainder_level(),
            over_time,
        )?
    } else {
        square::Choice::Absent
    };
    let quadratic = match choice {
        square::Choice::Taken(t) => {
            let t = *t;
            problem = t.problem;
            centred = centred_of(&problem);
            thermal = t.thermal;
            square_params = 4;
            Some(t.growth)
        }
        square::Choice::Beside(q) => Some(q),
        square::Choice::Absent => None,
    };
    if let Some(q) = &quadratic {
        thermal.selected.retain(|k| !q.replaces.contains(k));
        thermal
            .steps
            .retain(|s| !q.replaces.iter().any(|k| k.name() == s.added));
        for c in &mut thermal.candidates {
            if q.replaces.iter().any(|k| k.name() == c.name) {
                c.selected = false;
            }
        }
    }
    Ok((problem, centred, thermal, quadratic, square_params))
}

/// The absolute pass: the thermal effects selected on the absolute level
/// of the gap with the static ones found, and the static ones again with
/// them held. Taken (`Some`: thermal, held problem, statics) when it finds
/// all the free-offset stage found and more, and the whole held-out gap
/// drops clearly with it or stays with fewer static effects.
fn absolute_pass(
    ctx: &Ctx,
    problem: &Problem,
    thermal_pool: &[EffectKind],
    static_pool: &[EffectKind],
    thermal: &Forward,
    statics: &Forward,
) -> Result<Option<(Forward, Problem, Forward)>> {
    let absolute = ctx.select(problem, &statics.selected, thermal_pool, Some(0.0), None)?;
    let superset = thermal
        .selected
        .iter()
        .all(|k| absolute.selected.contains(k));
    if superset && absolute.selected.len() > thermal.selected.len() {
        let held_abs = ctx.held_by(problem, &absolute);
        let statics_abs = ctx.select(
            &held_abs,
            &[],
            static_pool,
            ctx.static_held_out,
            Some(Joint {
                problem,
                kinds: &absolute.selected,
            }),
        )?;
        let nr2 = ctx.noise.rms_mm.powi(2);
        // Better held out, or as good with fewer static effects (a
        // static one had only taken up the thermal effect's average).
        let better = statics_abs.cv.powi(2) < statics.cv.powi(2) - 0.2 * nr2;
        let simpler = statics_abs.selected.len() < statics.selected.len()
            && statics_abs.cv <= 1.02 * statics.cv;
        if better || simpler {
            return Ok(Some((absolute, held_abs, statics_abs)));
        }
    }
    Ok(None)
}

/// The static selection with sag said, not named, where it cannot be told
/// from the arm's geometry, and a joint's own error searched beyond the
/// full calibration.
fn sag_and_signature(
    ctx: &Ctx,
    problem: &Problem,
    thermal: &Forward,
    held: &Problem,
    static_pool: &[EffectKind],
    mut statics: Forward,
) -> Result<(Forward, joint_signature::Searched)> {
    // Where the poses are too few for a full kinematic calibration, sag
    // cannot be told from the arm's own geometry: it would only take up
    // part of that geometry. Said, not named.
    let mut ambiguous_sag = None;
    let without_sag: Vec<EffectKind> = static_pool
        .iter()
        .copied()
        .filter(|k| *k != EffectKind::GravitySag)
        .collect();
    let select_without_sag = |held: &Problem| {
        ctx.select(
            held,
            &[],
            &without_sag,
            ctx.static_held_out,
            Some(Joint {
                problem,
                kinds: &thermal.selected,
            }),
        )
    };
    if !ctx.static_judged && statics.selected.contains(&EffectKind::GravitySag) {
        let sag_cv = statics.cv;
        statics = select_without_sag(held)?;
        ambiguous_sag = Some(Ambiguity {
            pair: ["geometry-offset".into(), "gravity-sag".into()],
            correlation: None,
            separate_by: Separation::CalibrationPoses {
                poses: ctx.n_poses,
                sag_cv_mm: sag_cv,
            },
        });
    }
    statics.ambiguities.extend(ambiguous_sag);
    // A joint's own error the library lacks (a cyclic error of its angle,
    // backlash), tested beyond the full calibration where the poses allow
    // one: the omnibus lack-of-fit test spreads its power over every
    // direction the calibration leaves, and a calibration from 12-20 poses
    // takes up most of such an error. Gravity sag that adds nothing beyond
    // the calibration and the signature only stood in for it.
    let searched = if ctx.static_judged {
        joint_signature::find(held, &statics.selected, &ctx.noise, ctx.remainder_level())
    } else {
        joint_signature::Searched::default()
    };
    if searched
        .found
        .as_ref()
        .and_then(|s| s.sag_beyond)
        .is_some_and(|t| !t.significant())
    {
        statics = select_without_sag(held)?;
    }
    Ok((statics, searched))
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
    parts: [Part; 2],
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

/// One stage of a diagnosis: what its selection found, its verdict, and
/// the test of what is left against the noise.
struct Stage {
    forward: Forward,
    verdict: Verdict,
    /// `None` where the design leaves no degrees of freedom to judge.
    lack_of_fit: Option<Test>,
    judged: bool,
    /// How often each effect it selected is named over resampled fits.
    stability: Vec<stability::Stability>,
}

/// What every stage of a diagnosis shares.
struct Ctx<'a> {
    problem: &'a Problem,
    /// Held-out folds by time block and pose group.
    folds: &'a select::Folds,
    noise: TestNoise,
    max_effects: usize,
    n_poses: usize,
    /// The poses give more numbers than a full kinematic calibration takes.
    static_judged: bool,
    /// Where every fold keeps enough of them to predict its held-out poses:
    /// the drop of the held-out mean-square gap a static effect must make.
    static_held_out: Option<f64>,
    /// Temperatures drive the thermal effects ([`temps::TempSource::drives`]).
    temps_drive: bool,
}

impl Ctx<'_> {
    /// The level of each test that can call something `unexplained` in one
    /// stage: its lack of fit and, where no temperatures drive anything, a
    /// drift in time, sharing [`LEVEL`] (Bonferroni) where both are run.
    fn one_stage_level(&self) -> f64 {
        let families = usize::from(self.noise.measured) + usize::from(!self.temps_drive);
        LEVEL / families.max(1) as f64
    }

    /// The level of each family of tests that can call something
    /// `unexplained` in the two stages, where the set's verdict is
    /// `unexplained` when any of them rejects: the lack of fit over time, a
    /// step in time and the growth with the square, and where the static
    /// stage is judged its lack of fit and the joint signatures. The
    /// family-wise level over the tests actually run is [`LEVEL`]
    /// (Bonferroni; for the one question "is anything unexplained" Holm's
    /// first step is the same). Each family shares its own level among its
    /// members as before (the splits of a step, the signatures tried).
    fn remainder_level(&self) -> f64 {
        let families = if self.static_judged { 5 } else { 3 };
        LEVEL / families as f64
    }

    /// The stages of the diagnosis: two where poses repeat over time, else
    /// one over all effects; with both parts of the set named.
    fn stages(&self, pool: &[EffectKind], two: bool, width: usize) -> Result<AllStaged> {
        Ok(if two {
            let (stages, held, first, knock, quadratic, searched) = two_stages(self, pool)?;
            (
                stages,
                held,
                [first, Part::Static],
                knock,
                quadratic,
                searched,
            )
        } else {
            (
                vec![self.one_stage(pool, width)?],
                self.problem.clone(),
                [Part::All, Part::All],
                None,
                None,
                joint_signature::Searched::default(),
            )
        })
    }

    /// Data without repeats over time: one stage over all effects, its
    /// lack of fit judged where the noise was measured or given.
    fn one_stage(&self, pool: &[EffectKind], width: usize) -> Result<Stage> {
        let problem = self.problem;
        let n = problem.rows.len();
        let tnoise = self.noise;
        let one = self.select(problem, &[], pool, self.static_held_out, None)?;
        let (rss, free) = one.rss();
        // What is left is judged against a noise only where one was
        // measured or given: a residual cannot be tested against itself.
        let lof = tnoise.measured.then(|| {
            Test::lack_of_fit(
                rss,
                (n * width).saturating_sub(free),
                tnoise.sigma2,
                tnoise.dof,
                self.one_stage_level(),
            )
        });
        let verdict = self.judge(&one, lof);
        let stability = stability::of(problem, &one.effects(), &tnoise, 1);
        Ok(Stage {
            forward: one,
            verdict,
            lack_of_fit: lof,
            judged: self.static_judged,
            stability,
        })
    }

    fn judge(&self, f: &Forward, lof: Option<Test>) -> Verdict {
        judge(&Scores {
            selected: &f.selected,
            lack_of_fit: lof,
            ambiguous: !f.ambiguities.is_empty(),
        })
    }

    /// The problem with `thermal`'s effects held fixed, for the static
    /// effects to be fitted on.
    fn held_by(&self, problem: &Problem, thermal: &Forward) -> Problem {
        let mut fixed = problem.fixed.clone();
        fixed.extend(thermal.effects());
        let statics: Vec<EffectKind> = EffectKind::ALL
            .into_iter()
            .filter(|k| !k.is_thermal())
            .collect();
        Problem {
            fixed,
            ..problem.clone()
        }
        .with_zero_jacobians_of(&statics)
    }

    fn select(
        &self,
        problem: &Problem,
        base: &[EffectKind],
        pool: &[EffectKind],
        held_out: Option<f64>,
        joint: Option<Joint>,
    ) -> Result<Forward> {
        forward(
            problem,
            self.folds,
            base,
            pool,
            &self.noise,
            self.max_effects,
            held_out,
            joint,
        )
    }

    /// The lack-of-fit test of the static part: what `statics` leaves of
    /// the poses' means (the residual less its part within each pose).
    /// With thermal effects found over time, they are fitted again together
    /// with the static ones: their error at each pose's mean temperature is
    /// not noise of the means, and would otherwise read as static error.
    fn static_lack_of_fit(
        &self,
        problem: &Problem,
        thermal: &Forward,
        held: &Problem,
        statics: &Forward,
    ) -> Option<Test> {
        let all: Vec<usize> = (0..held.rows.len()).collect();
        let within_of = |p: &Problem| {
            Problem {
                centre_poses: true,
                ..p.clone()
            }
            .residuals(&[], &all)
            .norm_squared()
        };
        let (rss, free) = statics.rss();
        let dof = (held.width() * self.n_poses).saturating_sub(free);
        let between = if thermal.selected.is_empty() {
            rss - within_of(held)
        } else {
            let mut kinds = thermal.selected.clone();
            kinds.extend(statics.selected.iter().copied());
            // Started from the thermal effects found over time and the
            // static ones found with them held: there the joint model's
            // residual is the static stage's, and the fit can only lower it.
            // From a cold start a lag's fit may end in another, worse
            // minimum, and the difference would be taken for static error
            // the model lacks.
            let mut start = thermal.effects();
            start.extend(statics.effects());
            let joint = fit::fit_from(problem, &all, &kinds, &start).ok()?;
            joint.rss - thermal.rss().0
        };
        (dof > 0).then(|| {
            Test::lack_of_fit(
                between.max(0.0),
                dof,
                self.noise.sigma2,
                self.noise.dof,
                self.remainder_level(),
            )
        })
    }
}

/// The stages of a diagnosis, the problem of the last, the parts of both
/// stages, and a step in time found over time.
type AllStaged = (
    Vec<Stage>,
    Problem,
    [Part; 2],
    Option<locate::Step>,
    Option<QuadraticGrowth>,
    joint_signature::Searched,
);

/// The stages of a diagnosis, the problem of the last, the first stage's
/// part, and a step in time found over time.
type Staged = (
    Vec<Stage>,
    Problem,
    Part,
    Option<locate::Step>,
    Option<QuadraticGrowth>,
    joint_signature::Searched,
);

/// The two stages of data that measure poses again and again: what changes
/// with time (each pose's own offset free, held out by time span), then
/// what stays (the thermal effects found held fixed). Returns the stages,
/// the problem of the last, the first stage's part (`absolute` when the
/// absolute pass replaced it), and a step in time found (removed from the
/// data before the static stage).
fn two_stages(ctx: &Ctx, pool: &[EffectKind]) -> Result<Staged> {
    let problem = ctx.problem.clone();
    let mut first = Part::OverTime;
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let centred = centred_of(&problem);
    let time_folds = select::make_folds(&centred, ctx.folds.folds.len());
    let thermal_pool: Vec<EffectKind> = pool.iter().copied().filter(|k| k.is_thermal()).collect();
    let static_pool: Vec<EffectKind> = pool.iter().copied().filter(|k| !k.is_thermal()).collect();
    let over_time = |c: &Problem| {
        forward(
            c,
            &time_folds,
            &[],
            &thermal_pool,
            &ctx.noise,
            ctx.max_effects,
            // Held out by time span: an effect must predict the spans its
            // fit never saw better than the model without it. Its
            // significance is the F test's; a margin on top would be a
            // second threshold no test states (a lone lag with logged
            // temperatures passed F at p < 1e-5 and was refused by a margin
            // of 5 % of the noise variance).
            Some(0.0),
            None,
        )
    };
    let thermal = over_time(&centred)?;
    let (problem, centred, thermal, knocked) = without_step(
        ctx,
        &time_folds,
        &all,
        &over_time,
        problem,
        centred,
        thermal,
    )?;
    let (problem, centred, mut thermal, quadratic, square_params) =
        with_square(ctx, &time_folds, &over_time, problem, centred, thermal)?;
    let mut held = ctx.held_by(&problem, &thermal);
    let mut statics = ctx.select(
        &held,
        &[],
        &static_pool,
        ctx.static_held_out,
        Some(Joint {
            problem: &problem,
            kinds: &thermal.selected,
        }),
    )?;
    // Where the library's static effects leave nothing of the static part
    // (or find none to take up), each pose's offset is known, not free: the
    // absolute level of the gap (thermal effects vanish at the cold start)
    // then shows what the time variation alone misses, such as a small
    // effect or one of two that move the flange alike. Taken when it finds
    // all the free-offset stage found, and more, and the whole held-out gap
    // drops clearly with it or stays with fewer static effects.
    let static_lof = ctx.static_lack_of_fit(&problem, &thermal, &held, &statics);
    let absolute = if knocked.is_none()
        && quadratic.is_none()
        && (statics.selected.is_empty() || static_lof.is_some_and(|t| !t.significant()))
    {
        absolute_pass(
            ctx,
            &problem,
            &thermal_pool,
            &static_pool,
            &thermal,
            &statics,
        )?
    } else {
        None
    };
    if let Some((absolute, held_abs, statics_abs)) = absolute {
        thermal = absolute;
        held = held_abs;
        statics = statics_abs;
        first = Part::Absolute;
    }
    let (statics, searched) =
        sag_and_signature(ctx, &problem, &thermal, &held, &static_pool, statics)?;
    let (rss, free) = thermal.rss();
    let time_dof = centred
        .residuals(&[], &all)
        .len()
        .saturating_sub(centred.width() * ctx.n_poses + free + square_params);
    let time_lof = (first == Part::OverTime).then(|| {
        Test::lack_of_fit(
            rss,
            time_dof,
            ctx.noise.sigma2,
            ctx.noise.dof,
            ctx.remainder_level(),
        )
    });
    let mut thermal_verdict = ctx.judge(&thermal, time_lof);
    if knocked.is_some() || quadratic.is_some() {
        // The step or the growth itself is what no effect of the library
        // explains.
        thermal_verdict = with_remainder(thermal_verdict);
    }
    let static_lof = ctx.static_lack_of_fit(&problem, &thermal, &held, &statics);
    let mut static_verdict = ctx.judge(&statics, static_lof);
    if searched.found.is_some() {
        static_verdict = with_remainder(static_verdict);
    }
    // Each stage's selection over resampled fits, on the data it was
    // selected on: over time with each pose's own offset (time blocks left
    // out), or as the absolute pass saw them; the static effects with the
    // thermal ones held.
    let thermal_on = if first == Part::OverTime {
        &centred
    } else {
        &problem
    };
    let thermal_stability = stability::of(thermal_on, &thermal.effects(), &ctx.noise, 1);
    let static_stability = stability::of(&held, &statics.effects(), &ctx.noise, 2);
    Ok((
        vec![
            Stage {
                forward: thermal,
                verdict: thermal_verdict,
                lack_of_fit: time_lof,
                judged: true,
                stability: thermal_stability,
            },
            Stage {
                forward: statics,
                verdict: static_verdict,
                lack_of_fit: static_lof,
                judged: ctx.static_judged,
                stability: static_stability,
            },
        ],
        held,
        first,
        knocked.map(|k| step_of(&problem, &k)),
        quadratic,
        searched,
    ))
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
