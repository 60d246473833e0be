//! The stages of a diagnosis and what they share: one stage over every
//! effect for data that do not repeat poses over time; else two, what
//! changes with time (each pose's own offset free, a step of the whole
//! robot and a growth with the square looked for) and then what stays
//! (the thermal effects found held fixed), with the absolute pass, the
//! sag's ambiguity and the joint signatures. [`super::pipeline`] runs them
//! and reports.

use super::fit::{self, Problem};
use super::forward::{forward, Forward, Joint};
use super::joint_signature;
use super::judge::{judge, with_remainder, Scores};
use super::knock;
use super::locate;
use super::select;
use super::separation::Separation;
use super::signature::QuadraticGrowth;
use super::square;
use super::stability;
use super::stats::{Test, LEVEL};
use super::step::{significant_step, step_of};
use super::test_noise::TestNoise;
use super::verdict::{Ambiguity, ScoredIn, Verdict};
use crate::error::Result;
use crate::model::EffectKind;

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

/// One stage of a diagnosis: what its selection found, its verdict, and
/// the test of what is left against the noise.
pub(super) struct Stage {
    pub(super) forward: Forward,
    pub(super) verdict: Verdict,
    /// `None` where the design leaves no degrees of freedom to judge.
    pub(super) lack_of_fit: Option<Test>,
    pub(super) judged: bool,
    /// How often each effect it selected is named over resampled fits.
    pub(super) stability: Vec<stability::Stability>,
}

/// What every stage of a diagnosis shares.
pub(super) struct Ctx<'a> {
    pub(super) problem: &'a Problem,
    /// Held-out folds by time block and pose group.
    pub(super) folds: &'a select::Folds,
    pub(super) noise: TestNoise,
    pub(super) max_effects: usize,
    pub(super) n_poses: usize,
    /// The poses give more numbers than a full kinematic calibration takes.
    pub(super) static_judged: bool,
    /// Where every fold keeps enough of them to predict its held-out poses:
    /// the drop of the held-out mean-square gap a static effect must make.
    pub(super) static_held_out: Option<f64>,
    /// Temperatures drive the thermal effects ([`temps::TempSource::drives`]).
    pub(super) temps_drive: bool,
}

impl Ctx<'_> {
    /// The level of each test that can call something `unexplained` in one
    /// stage: its lack of fit and, where no temperatures drive anything, a
    /// drift in time, sharing [`LEVEL`] (Bonferroni) where both are run.
    pub(super) fn one_stage_level(&self) -> f64 {
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
    pub(super) fn remainder_level(&self) -> f64 {
        let families = if self.static_judged { 5 } else { 3 };
        LEVEL / families as f64
    }

    /// The stages of the diagnosis: two where poses repeat over time, else
    /// one over all effects; with both parts of the set named.
    pub(super) fn stages(&self, pool: &[EffectKind], two: bool, width: usize) -> Result<AllStaged> {
        Ok(if two {
            let (stages, held, first, knock, quadratic, searched) = two_stages(self, pool)?;
            (
                stages,
                held,
                [first, ScoredIn::Static],
                knock,
                quadratic,
                searched,
            )
        } else {
            (
                vec![self.one_stage(pool, width)?],
                self.problem.clone(),
                [ScoredIn::All, ScoredIn::All],
                None,
                None,
                joint_signature::Searched::default(),
            )
        })
    }

    /// Data without repeats over time: one stage over all effects, its
    /// lack of fit judged where the noise was measured or given.
    pub(super) fn one_stage(&self, pool: &[EffectKind], width: usize) -> Result<Stage> {
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

    pub(super) fn judge(&self, f: &Forward, lof: Option<Test>) -> Verdict {
        judge(&Scores {
            selected: &f.selected,
            lack_of_fit: lof,
            ambiguous: !f.ambiguities.is_empty(),
        })
    }

    /// The problem with `thermal`'s effects held fixed, for the static
    /// effects to be fitted on.
    pub(super) fn held_by(&self, problem: &Problem, thermal: &Forward) -> Problem {
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

    pub(super) fn select(
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
    pub(super) fn static_lack_of_fit(
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
pub(super) type AllStaged = (
    Vec<Stage>,
    Problem,
    [ScoredIn; 2],
    Option<locate::Step>,
    Option<QuadraticGrowth>,
    joint_signature::Searched,
);

/// The stages of a diagnosis, the problem of the last, the first stage's
/// part, and a step in time found over time.
type Staged = (
    Vec<Stage>,
    Problem,
    ScoredIn,
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
    let mut first = ScoredIn::OverTime;
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
        first = ScoredIn::Absolute;
    }
    let (statics, searched) =
        sag_and_signature(ctx, &problem, &thermal, &held, &static_pool, statics)?;
    let (rss, free) = thermal.rss();
    let time_dof = centred
        .residuals(&[], &all)
        .len()
        .saturating_sub(centred.width() * ctx.n_poses + free + square_params);
    let time_lof = (first == ScoredIn::OverTime).then(|| {
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
    let thermal_on = if first == ScoredIn::OverTime {
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
