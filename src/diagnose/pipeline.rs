//! The diagnosis itself: the noise level, held-out scores of every
//! candidate effect, forward selection while the held-out gap still drops
//! clearly, the final fit, and the verdict.

use super::fit::Problem;
use super::forward::{forward, params_out, Forward};
use super::gap::{gap_stats, noise_level, orientation_weight, NoiseSource};
use super::knock;
use super::locate::{self, Where};
use super::prepare::Prepared;
use super::select;
use super::verdict::{
    Advice, Ambiguity, CandidateOut, Diagnosis, ParamOut, Part, StageSummary, StepOut, Verdict,
};
use crate::error::{Error, Result};
use crate::model::effects::{FULL_GEOMETRY_POSES, GEOMETRY_ORIGINS_FROM};
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
/// predicts held-out time spans better than that static explanation does.
/// Then what stays, with the thermal effects found held fixed: the static
/// effects, judged on held-out poses. Data without such repeats are judged
/// in one stage over all effects.
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
    let lag_fixed = problem
        .fixed
        .iter()
        .any(|e| e.kind == EffectKind::ThermalLag);
    let pool: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .filter(|k| !(lag_fixed && *k == EffectKind::ThermalLag))
        .collect();
    let where_ = locate::locate(problem, &gaps_before, &prepared.pose_names, noise.rms_mm);
    let noise_assumed = noise.source == NoiseSource::Default;
    let n_poses = problem.rows.iter().map(|r| r.pose + 1).max().unwrap_or(0);

    let ctx = Ctx {
        problem,
        folds: &folds,
        noise_rms_mm: noise.rms_mm,
        noise_assumed,
        max_effects: opts.max_effects,
        structured: where_.has_structure(),
        n_poses,
    };
    let (stages, final_problem, parts, judged, knock) = if repeats_over_time(problem) {
        let (stages, held, first, knock) =
            two_stages(&ctx, &pool, &gaps_before, &prepared.pose_names)?;
        (
            stages,
            held,
            [first, Part::Static],
            [true, n_poses >= FULL_GEOMETRY_POSES],
            knock,
        )
    } else {
        let one = forward(problem, &folds, &[], &pool, noise.rms_mm, opts.max_effects)?;
        let verdict = ctx.judge(&one, ctx.structured, true);
        (
            vec![(one, verdict)],
            problem.clone(),
            [Part::All, Part::All],
            [true, true],
            None,
        )
    };
    let last = stages.last().map(|(f, _)| f);
    // Before: the model in use, every position as measured (no pose
    // offsets), on the same held-out folds as the last stage's score.
    let cv0 = select::cv_rms(problem, &folds, &[])?;
    let cur_cv = last.map_or(cv0, |f| f.cv);
    // The last stage's fit: earlier stages' effects are fixed in its
    // problem.
    let last_effects = last
        .and_then(|f| f.fit.as_ref())
        .map(|f| f.effects.clone())
        .unwrap_or_default();
    let gaps_after = final_problem.position_gaps(&last_effects, &all);
    let verdict = combine(stages.iter().map(|(_, v)| v.clone()).collect());
    let mut candidates = Vec::new();
    let mut steps = Vec::new();
    let mut ambiguities = Vec::new();
    let mut fitted = Vec::new();
    for ((f, _), part) in stages.iter().zip(parts) {
        // What each stage selected, with the parameters of its final fit
        // (the base an absolute pass fitted with them left out).
        let finals = f.fit.as_ref().map(params_out).unwrap_or_default();
        for c in &f.candidates {
            let selected = f.selected.iter().any(|k| k.name() == c.name);
            let prefix = format!("{}.", c.name);
            // Geometry's joint origins are not fitted from too few poses:
            // not listed, rather than listed as unidentifiable.
            let listed = |p: &ParamOut| {
                (n_poses >= FULL_GEOMETRY_POSES || !is_origin_param(&p.name))
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
                    .filter(|(e, _)| f.selected.contains(&e.kind))
                    .map(|(e, ps)| {
                        let se: Vec<Option<f64>> = ps.iter().map(|p| p.stderr).collect();
                        EffectEntry::from_effect(e, Some(&se))
                    }),
            );
        }
    }
    // What the first of two stages leaves over time is located with each
    // pose's own offset taken out: static error the poses cannot attribute
    // would otherwise hide it (a knock at minute 88 under tenths of a mm of
    // geometry).
    let time_left = stages.len() > 1
        && matches!(
            stages.first().map(|(_, v)| v),
            Some(Verdict::Unexplained { .. })
                | Some(Verdict::ExplainedBy {
                    remainder: true,
                    ..
                })
                | Some(Verdict::Ambiguous {
                    remainder: true,
                    ..
                })
        );
    let where_after = if time_left {
        let centred = Problem {
            centre_poses: true,
            ..problem.clone()
        };
        let left = select::centred(&centred, &all, gaps_after.clone());
        let w = locate::locate(&centred, &left, &prepared.pose_names, noise.rms_mm);
        match knock {
            Some(step) => w.with_step(step),
            None => w,
        }
    } else {
        locate::locate(problem, &gaps_after, &prepared.pose_names, noise.rms_mm)
    };
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
        left_over_time: time_left,
        registration: prepared.registration.clone(),
        stages: stages
            .iter()
            .zip(parts.into_iter().zip(judged))
            .map(|((f, _), (part, judged))| StageSummary {
                part,
                gap_before_mm: f.cv0,
                gap_after_mm: f.cv,
                effects: f.selected.iter().map(|k| k.name().to_string()).collect(),
                judged,
            })
            .collect(),
        advice,
        fitted,
        gaps_before,
        gaps_after,
    })
}

/// What every stage of a diagnosis shares.
struct Ctx<'a> {
    problem: &'a Problem,
    /// Held-out folds by time block and pose group.
    folds: &'a select::Folds,
    noise_rms_mm: f64,
    noise_assumed: bool,
    max_effects: usize,
    /// The current model's gap shows structure.
    structured: bool,
    n_poses: usize,
}

impl Ctx<'_> {
    fn judge(&self, f: &Forward, structured: bool, judge_remainder: bool) -> Verdict {
        judge(&Scores {
            selected: &f.selected,
            cv0: f.cv0,
            cv: f.cv,
            noise_rms_mm: self.noise_rms_mm,
            noise_assumed: self.noise_assumed,
            structured,
            ambiguous: !f.ambiguities.is_empty(),
            judge_remainder,
        })
    }

    /// The problem with `thermal`'s effects held fixed, for the static
    /// effects to be fitted on.
    fn held_by(&self, thermal: &Forward) -> Problem {
        let mut fixed = self.problem.fixed.clone();
        fixed.extend(thermal.effects());
        let statics: Vec<EffectKind> = EffectKind::ALL
            .into_iter()
            .filter(|k| !k.is_thermal())
            .collect();
        Problem {
            fixed,
            ..self.problem.clone()
        }
        .with_zero_jacobians_of(&statics)
    }

    fn select(
        &self,
        problem: &Problem,
        base: &[EffectKind],
        pool: &[EffectKind],
    ) -> Result<Forward> {
        forward(
            problem,
            self.folds,
            base,
            pool,
            self.noise_rms_mm,
            self.max_effects,
        )
    }
}

/// The stages of a diagnosis, the problem of the last, and the first
/// stage's part.
type Staged = (Vec<(Forward, Verdict)>, Problem, Part, Option<locate::Step>);

/// A knock as a step between the measurement times around it.
fn step_of(problem: &Problem, k: &knock::Knock) -> locate::Step {
    let before = problem
        .rows
        .iter()
        .map(|r| r.time_min)
        .filter(|&t| t < k.after_min - 1e-9)
        .fold(f64::NEG_INFINITY, f64::max);
    let size = k.shift_mm.norm();
    let dir = if size > 0.0 {
        k.shift_mm / size
    } else {
        k.shift_mm
    };
    locate::Step {
        before_min: before,
        after_min: k.after_min,
        size_mm: size,
        direction: [dir.x, dir.y, dir.z],
    }
}

/// The two stages of data that measure poses again and again: what changes
/// with time (each pose's own offset free, held out by time span), then
/// what stays (the thermal effects found held fixed). Returns the stages,
/// the problem of the last, the first stage's part (`absolute` when the
/// absolute pass replaced it), and a knock that explains the change over
/// time better than any thermal effect.
fn two_stages(
    ctx: &Ctx,
    pool: &[EffectKind],
    gaps_before: &[nalgebra::Vector3<f64>],
    pose_names: &[String],
) -> Result<Staged> {
    let problem = ctx.problem;
    let mut first = Part::OverTime;
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let centred = Problem {
        centre_poses: true,
        ..problem.clone()
    };
    let time_folds = select::make_folds(&centred, ctx.folds.folds.len());
    let thermal_pool: Vec<EffectKind> = pool.iter().copied().filter(|k| k.is_thermal()).collect();
    let static_pool: Vec<EffectKind> = pool.iter().copied().filter(|k| !k.is_thermal()).collect();
    let mut thermal = forward(
        &centred,
        &time_folds,
        &[],
        &thermal_pool,
        ctx.noise_rms_mm,
        ctx.max_effects,
    )?;
    // The held-out gap over time with no thermal effect.
    let centred_cv0 = thermal.cv0;
    let mut held = ctx.held_by(&thermal);
    let mut statics = ctx.select(&held, &[], &static_pool)?;
    // Where the library's static effects leave nothing of the static part
    // (or find none to take up), each pose's offset is known, not free: the
    // absolute level of the gap (thermal effects vanish at the cold start)
    // then shows what the time variation alone misses, such as a small
    // effect or one of two that move the flange alike. Taken when it finds
    // all the free-offset stage found, and more, and the whole held-out gap
    // drops clearly with it or stays with fewer static effects.
    if statics.selected.is_empty() || statics.cv <= 1.2 * ctx.noise_rms_mm {
        let absolute = ctx.select(problem, &statics.selected, &thermal_pool)?;
        let superset = thermal
            .selected
            .iter()
            .all(|k| absolute.selected.contains(k));
        if superset && absolute.selected.len() > thermal.selected.len() {
            let held_abs = ctx.held_by(&absolute);
            let statics_abs = ctx.select(&held_abs, &[], &static_pool)?;
            let nr2 = ctx.noise_rms_mm.powi(2);
            // Better held out, or as good with fewer static effects (a
            // static one had only taken up the thermal effect's average).
            let better = statics_abs.cv.powi(2) < statics.cv.powi(2) - 0.2 * nr2;
            let simpler = statics_abs.selected.len() < statics.selected.len()
                && statics_abs.cv <= 1.02 * statics.cv;
            if better || simpler {
                thermal = absolute;
                held = held_abs;
                statics = statics_abs;
                first = Part::Absolute;
            }
        }
    }
    // A step of the whole robot competes with the thermal effects found:
    // where it predicts the held-out time spans clearly better (by a fifth
    // of the noise variance, as an effect must to be added), the change
    // over time is no thermal effect of the library (a knock early in the
    // warm-up looks like the base motor's rise); where nothing thermal is
    // found, a step that beats "no change" the same way is structure.
    let mut knocked = None;
    if let Some((knock_cv, knock)) = knock::score(&centred, &time_folds, gaps_before) {
        let nr2 = ctx.noise_rms_mm.powi(2);
        let cv0 = centred_cv0;
        let beats = |cv: f64| cv.powi(2) - knock_cv.powi(2) > 0.2 * nr2;
        let thermal_cv = match thermal.selected.is_empty() {
            true => cv0,
            false => select::cv_rms(&centred, &time_folds, &thermal.selected)?,
        };
        if beats(cv0) && beats(thermal_cv) {
            knocked = Some(knock);
            if !thermal.selected.is_empty() {
                thermal = Forward {
                    selected: Vec::new(),
                    cv0,
                    cv: cv0,
                    fit: None,
                    steps: Vec::new(),
                    ambiguities: Vec::new(),
                    candidates: std::mem::take(&mut thermal.candidates),
                };
                first = Part::OverTime;
                held = ctx.held_by(&thermal);
                statics = ctx.select(&held, &[], &static_pool)?;
            }
        }
    }
    // From too few poses for a full kinematic calibration, with static
    // error left over, sag cannot be told from the arm's own geometry: it
    // would only take up part of that geometry. Said, not named.
    let mut ambiguous_sag = None;
    if ctx.n_poses < FULL_GEOMETRY_POSES
        && statics.cv > 1.5 * ctx.noise_rms_mm
        && statics.selected.contains(&EffectKind::GravitySag)
    {
        let without: Vec<EffectKind> = static_pool
            .iter()
            .copied()
            .filter(|k| *k != EffectKind::GravitySag)
            .collect();
        let sag_cv = statics.cv;
        statics = ctx.select(&held, &[], &without)?;
        ambiguous_sag = Some(Ambiguity {
            pair: ["geometry-offset".into(), "gravity-sag".into()],
            correlation: None,
            separate_by: format!(
                "measure {FULL_GEOMETRY_POSES} poses or more spread over the joint ranges, with the upper arm horizontal and vertical: from these, gravity-sag would take the static gap to {sag_cv:.3} mm held-out, but the arm's own geometry, fitted in full only from that many poses, may explain it as well"
            ),
        });
    }
    statics.ambiguities.extend(ambiguous_sag);
    // Structure over time, each pose's own offset taken out.
    let over_time = locate::locate(
        &centred,
        &select::centred(&centred, &all, gaps_before.to_vec()),
        pose_names,
        ctx.noise_rms_mm,
    );
    let thermal_verdict = if knocked.is_some() {
        Verdict::Unexplained {
            partial: Vec::new(),
        }
    } else {
        ctx.judge(&thermal, over_time.has_structure(), true)
    };
    // With fewer poses than a full kinematic calibration needs, pose-to-pose
    // structure left may still be geometry: reported, not called
    // unexplained.
    let static_verdict = ctx.judge(&statics, ctx.structured, ctx.n_poses >= FULL_GEOMETRY_POSES);
    Ok((
        vec![(thermal, thermal_verdict), (statics, static_verdict)],
        held,
        first,
        knocked.map(|k| step_of(problem, &k)),
    ))
}

/// Whether the parameter `name` (`effect.param`) has a place on the arm
/// ([`crate::model::Geometry::has_param`]): one without is not listed.
fn has_place(geometry: &crate::model::Geometry, name: &str) -> bool {
    let Some((effect, param)) = name.split_once('.') else {
        return true;
    };
    let Some(kind) = EffectKind::from_name(effect) else {
        return true;
    };
    kind.params()
        .iter()
        .position(|p| p.name == param)
        .is_none_or(|i| geometry.has_param(kind, i))
}

/// Whether `name` (`effect.param`) is one of geometry-offset's joint-origin
/// or measured-point parameters.
fn is_origin_param(name: &str) -> bool {
    name.strip_prefix("geometry-offset.").is_some_and(|p| {
        EffectKind::GeometryOffset.params()[GEOMETRY_ORIGINS_FROM..]
            .iter()
            .any(|info| info.name == p)
    })
}

/// One verdict from the stages': every effect named, in stage order; an
/// unexplained remainder anywhere is one.
fn combine(verdicts: Vec<Verdict>) -> Verdict {
    let mut effects = Vec::new();
    let mut partial = Vec::new();
    let mut remainder = false;
    let mut unexplained = false;
    let mut ambiguous = false;
    for v in verdicts {
        match v {
            Verdict::None => {}
            Verdict::ExplainedBy {
                effects: e,
                remainder: r,
            } => {
                effects.extend(e);
                remainder |= r;
            }
            Verdict::Ambiguous {
                effects: e,
                remainder: r,
            } => {
                effects.extend(e);
                remainder |= r;
                ambiguous = true;
            }
            Verdict::Unexplained { partial: p } => {
                partial.extend(p);
                unexplained = true;
            }
        }
    }
    if unexplained && effects.is_empty() {
        Verdict::Unexplained { partial }
    } else if effects.is_empty() {
        Verdict::None
    } else {
        effects.extend(partial);
        let remainder = remainder || unexplained;
        if ambiguous {
            Verdict::Ambiguous { effects, remainder }
        } else {
            Verdict::ExplainedBy { effects, remainder }
        }
    }
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
    /// Whether structure left after the selected effects may be called
    /// unexplained (else it is reported, not judged).
    judge_remainder: bool,
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
    // With the noise measured on these data (thousands of values), a
    // held-out gap a fifth above it that has structure (a step, growth, a
    // joint it follows) is not noise: a 0.03 mm knock in 0.035 mm of noise
    // is that.
    let clearly_above = s.cv0 > 1.5 * s.noise_rms_mm
        || (!s.noise_assumed && s.structured && s.cv0 > 1.2 * s.noise_rms_mm);
    if s.selected.is_empty() {
        // Without a measured noise level (no repeated poses) a gap above
        // the assumed level may just be a noisier instrument: call it
        // unexplained only with evidence of structure.
        if !clearly_above || (s.noise_assumed && !s.structured) || !s.judge_remainder {
            Verdict::None
        } else {
            Verdict::Unexplained {
                partial: Vec::new(),
            }
        }
    } else if s.cv <= 1.5 * s.noise_rms_mm || excess_explained >= 0.8 || !s.judge_remainder {
        let effects = s.selected.to_vec();
        // Most of the gap is explained, but clear structure remains: name
        // the effects and say that something else is there too.
        let remainder = s.cv > 2.0 * s.noise_rms_mm && s.judge_remainder;
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
