//! Diagnosis of the sim-to-real gap: where the gap between the model and
//! measured flange positions lies, which physical effect causes it, and how
//! far it shrinks once that effect is in the model.
//!
//! Pipeline: [`prepare`] (resolve temperatures, pose identities, optional
//! registration of a tracker frame) → [`gap`] (RMS/max of the current model)
//! or [`diagnose`] (noise level, localisation, candidate fits with held-out
//! scores, forward selection, verdict).

pub mod arm;
pub mod fit;
pub mod locate;
pub mod measurements;
pub mod plot;
pub mod select;
pub mod simulate;

use crate::error::{Error, ErrorKind, Result};
use crate::model::EffectKind;
use crate::model::{EffectEntry, Model};
use crate::thermal::TempHistory;
use fit::{Problem, Row};
use locate::Where;
use measurements::Measurements;
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use serde::Serialize;
use std::collections::HashMap;

/// Position noise of a laser tracker, mm per axis, when the data cannot
/// tell.
pub const DEFAULT_NOISE_MM: f64 = 0.01;

/// Data ready for the diagnosis.
#[derive(Debug, Clone)]
pub struct Prepared {
    pub problem: Problem,
    /// Pose names by pose id.
    pub pose_names: Vec<String>,
    /// The fitted instrument frame when `register` was asked for.
    pub registration: Option<Registration>,
}

/// The rigid transform from the robot base frame to the instrument's frame
/// (measured = T · base-frame point).
#[derive(Debug, Clone, Serialize)]
pub struct Registration {
    pub translation_mm: [f64; 3],
    /// Rotation vector, degrees.
    pub rotation_deg: [f64; 3],
    /// RMS distance left after the rigid fit, mm.
    pub rms_mm: f64,
    /// Rows the frame was fitted on (the cold start's when it has six or
    /// more poses, else all).
    pub rows_used: usize,
    #[serde(skip)]
    pub transform: Isometry3<f64>,
}

/// Resolve every row's temperatures (measured or from the model's heating
/// profile), pose identity (label, else identical joints) and, with
/// `register`, bring measured points from the instrument's frame into the
/// robot base frame.
pub fn prepare(meas: &Measurements, model: &Model, register: bool) -> Result<Prepared> {
    prepare_arm(meas, model, &arm::Arm::of_model(model), register)
}

/// [`prepare`] for any OPW-shaped arm: its nominal geometry replaces the
/// model's, and the rows' joints and orientations are mapped to the
/// diagnosis chain's convention ([`arm::ArmMap`]).
pub fn prepare_arm(
    meas: &Measurements,
    model: &Model,
    arm: &arm::Arm,
    register: bool,
) -> Result<Prepared> {
    if meas.rows.is_empty() {
        return Err(Error::input(format!("{}: no measurements", meas.file)));
    }
    let profile = model.profile()?;
    let mut ids: HashMap<String, usize> = HashMap::new();
    let mut pose_names = Vec::new();
    let mut rows = Vec::with_capacity(meas.rows.len());
    for m in &meas.rows {
        let key = match &m.pose {
            Some(label) => format!("L:{label}"),
            None => format!(
                "J:{}",
                m.joints.map(|q| format!("{:.6}", q.to_degrees())).join(",")
            ),
        };
        let next = ids.len();
        let id = *ids.entry(key).or_insert_with(|| {
            pose_names.push(m.pose.clone().unwrap_or_else(|| format!("#{}", next + 1)));
            next
        });
        let temps = match m.temps {
            Some(t) => t,
            None => profile.temps_at(m.time_min)?,
        };
        rows.push(Row {
            time_min: m.time_min,
            q: arm.map.to_chain(&m.joints),
            temps,
            position: m.position,
            orientation: m.orientation.map(|o| arm.map.flange_rotation(&o)),
            pose: id,
        });
    }
    let t_ref = model.thermal.t_ref;
    let history = if meas.has_temps() {
        let recs: Vec<_> = rows.iter().map(|r| (r.time_min, r.temps)).collect();
        TempHistory::from_records(&recs, t_ref)
    } else {
        let t_end = rows.iter().map(|r| r.time_min).fold(0.0, f64::max);
        TempHistory::from_profile(profile.as_ref(), t_end)?
    };
    let mut problem = Problem {
        base: arm.base(model),
        fixed: model.effects()?,
        rows,
        history,
        w_ori: DEFAULT_NOISE_MM / simulate::ORIENTATION_NOISE_MRAD,
        noise_mm: DEFAULT_NOISE_MM,
        zero_jacobians: None,
    };
    let registration = if register {
        let reg = register_frame(&problem)?;
        let inv = reg.transform.inverse();
        for r in &mut problem.rows {
            r.position = inv.transform_point(&r.position.into()).coords;
            r.orientation = r.orientation.map(|o| inv.rotation * o);
        }
        Some(reg)
    } else {
        None
    };
    Ok(Prepared {
        problem,
        pose_names,
        registration,
    })
}

/// Rigid fit (Kabsch) of the model's positions onto the measured ones.
fn register_frame(problem: &Problem) -> Result<Registration> {
    // Register on the cold start when it has enough poses: thermal effects
    // vanish there, so the frame does not absorb part of the drift the
    // diagnosis is after.
    let t0 = problem
        .rows
        .iter()
        .map(|r| r.time_min)
        .fold(f64::INFINITY, f64::min);
    let cold: Vec<usize> = (0..problem.rows.len())
        .filter(|&i| problem.rows[i].time_min <= t0 + 1e-9)
        .collect();
    let mut cold_poses: Vec<usize> = cold.iter().map(|&i| problem.rows[i].pose).collect();
    cold_poses.sort_unstable();
    cold_poses.dedup();
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    match rigid_fit(problem, &cold) {
        Ok(reg) if cold_poses.len() >= 6 => Ok(reg),
        _ => rigid_fit(problem, &all),
    }
}

/// Kabsch fit of the model's positions of `rows` onto the measured ones.
fn rigid_fit(problem: &Problem, rows: &[usize]) -> Result<Registration> {
    if rows.len() < 3 {
        return Err(Error::input("--register needs at least 3 measured poses"));
    }
    let all = rows;
    let sim: Vec<Vector3<f64>> = problem
        .predict_rows(&[], all)
        .iter()
        .map(|p| p.translation.vector)
        .collect();
    let meas: Vec<Vector3<f64>> = all.iter().map(|&i| problem.rows[i].position).collect();
    let n = sim.len() as f64;
    let cs = sim.iter().sum::<Vector3<f64>>() / n;
    let cm = meas.iter().sum::<Vector3<f64>>() / n;
    let mut h = Matrix3::zeros();
    for (s, m) in sim.iter().zip(&meas) {
        h += (s - cs) * (m - cm).transpose();
    }
    let svd = h.svd(true, true);
    let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
        return Err(Error::input(
            "--register: the measured points do not fix a frame",
        ));
    };
    let s = svd.singular_values;
    if s.min() < 1e-9 * s.max().max(1e-300) {
        return Err(Error::input(
            "--register needs poses spread in 3-D (these lie on a line or a plane)",
        ));
    }
    let v = vt.transpose();
    let d = (v * u.transpose()).determinant().signum();
    let r = v * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * u.transpose();
    let rot = UnitQuaternion::from_matrix(&r);
    let t = cm - rot * cs;
    let transform = Isometry3::from_parts(Translation3::from(t), rot);
    let rms = (sim
        .iter()
        .zip(&meas)
        .map(|(s, m)| (transform.transform_point(&(*s).into()).coords - m).norm_squared())
        .sum::<f64>()
        / n)
        .sqrt();
    let rv = rot.scaled_axis();
    Ok(Registration {
        translation_mm: [t.x, t.y, t.z],
        rotation_deg: [rv.x.to_degrees(), rv.y.to_degrees(), rv.z.to_degrees()],
        rms_mm: rms,
        rows_used: all.len(),
        transform,
    })
}

/// RMS and max of the position gap.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct GapStats {
    pub rms_mm: f64,
    pub max_mm: f64,
    pub n: usize,
    /// RMS per axis x, y, z.
    pub axis_rms_mm: [f64; 3],
}

pub fn gap_stats(gaps: &[Vector3<f64>]) -> GapStats {
    let n = gaps.len();
    let nf = n.max(1) as f64;
    let mut sq = Vector3::zeros();
    let mut max: f64 = 0.0;
    for g in gaps {
        sq += g.component_mul(g);
        max = max.max(g.norm());
    }
    GapStats {
        rms_mm: (sq.sum() / nf).sqrt(),
        max_mm: max,
        n,
        axis_rms_mm: [(sq.x / nf).sqrt(), (sq.y / nf).sqrt(), (sq.z / nf).sqrt()],
    }
}

/// The gap of the prepared data's model (base plus the model's effects).
pub fn gap(prepared: &Prepared) -> GapStats {
    let all: Vec<usize> = (0..prepared.problem.rows.len()).collect();
    gap_stats(&prepared.problem.position_gaps(&[], &all))
}

/// RMS and max orientation gap (rotation vector of R_model⁻¹·R_measured),
/// mrad, when every row carries an orientation.
pub fn orientation_gap(prepared: &Prepared) -> Option<(f64, f64)> {
    let problem = &prepared.problem;
    if problem.rows.is_empty() || problem.rows.iter().any(|r| r.orientation.is_none()) {
        return None;
    }
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let poses = problem.predict_rows(&[], &all);
    let angles: Vec<f64> = poses
        .iter()
        .zip(&problem.rows)
        .filter_map(|(p, r)| {
            r.orientation
                .map(|m| crate::model::chain::rotation_gap(&p.rotation, &m).norm() * 1e3)
        })
        .collect();
    let rms = (angles.iter().map(|a| a * a).sum::<f64>() / angles.len() as f64).sqrt();
    Some((rms, angles.iter().copied().fold(0.0, f64::max)))
}

/// The measurement noise level used for verdicts.
#[derive(Debug, Clone, Serialize)]
pub struct Noise {
    /// Per axis, mm.
    pub per_axis_mm: f64,
    /// 3-D RMS (per axis × √3), mm.
    pub rms_mm: f64,
    pub source: String,
}

/// Estimate tracker noise from repeated measurements of each pose: second
/// differences over adjacent times cancel slow (thermal) drift; a median
/// resists steps.
pub fn estimate_noise(problem: &Problem, gaps: &[Vector3<f64>]) -> Option<(f64, usize)> {
    let mut by_pose: HashMap<usize, Vec<(f64, Vector3<f64>)>> = HashMap::new();
    for (r, g) in problem.rows.iter().zip(gaps) {
        by_pose.entry(r.pose).or_default().push((r.time_min, *g));
    }
    let mut d2 = Vec::new();
    for series in by_pose.values_mut() {
        series.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in series.windows(3) {
            let d = w[0].1 - 2.0 * w[1].1 + w[2].1;
            d2.extend([d.x.abs(), d.y.abs(), d.z.abs()]);
        }
    }
    if d2.len() < 30 {
        return None;
    }
    d2.sort_by(f64::total_cmp);
    let med = d2[d2.len() / 2];
    // |N(0, 6σ²)| has median 0.6745·√6·σ.
    Some((med / (0.6745 * 6f64.sqrt()), d2.len() / 3))
}

/// Options of a diagnosis.
#[derive(Debug, Clone)]
pub struct Options {
    /// Tracker noise per axis (mm); `None`: estimate, else the default.
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

#[derive(Debug, Clone, Serialize)]
pub struct ParamOut {
    pub name: String,
    pub unit: String,
    pub value: f64,
    /// `null` when the data cannot identify it (held at zero).
    pub stderr: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct CandidateOut {
    pub name: String,
    /// Fraction of the base model's held-out mean-square gap this effect
    /// alone removes.
    pub explained: f64,
    pub cv_rms_mm: f64,
    pub bic: Option<f64>,
    pub params: Vec<ParamOut>,
    pub selected: bool,
    pub error: Option<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct StepOut {
    pub added: String,
    pub gap_before_mm: f64,
    pub gap_after_mm: f64,
    pub drop_pct: f64,
    pub runner_up: Option<String>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Ambiguity {
    pub pair: [String; 2],
    pub correlation: f64,
    pub separate_by: String,
}

/// The whole diagnosis.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnosis {
    pub verdict: Vec<String>,
    /// Held-out RMS gap of the current model, mm.
    pub gap_before_mm: f64,
    /// Held-out RMS gap with the selected effects, mm.
    pub gap_after_mm: f64,
    pub gap: GapStats,
    pub gap_after: GapStats,
    pub noise: Noise,
    pub candidates: Vec<CandidateOut>,
    pub steps: Vec<StepOut>,
    /// Pairs of effects the data cannot tell apart.
    pub ambiguous: Vec<[String; 2]>,
    pub ambiguities: Vec<Ambiguity>,
    /// Effects that explain part of a gap that stays unexplained.
    pub partial: Vec<String>,
    /// Where the gap of the current model lies.
    #[serde(rename = "where")]
    pub where_: Where,
    /// Where what is left after the selected effects lies.
    pub where_after: Where,
    pub registration: Option<Registration>,
    pub words: Vec<String>,
    /// The selected effects with their fitted parameters.
    #[serde(skip)]
    pub fitted: Vec<EffectEntry>,
    #[serde(skip)]
    pub gaps_before: Vec<Vector3<f64>>,
    #[serde(skip)]
    pub gaps_after: Vec<Vector3<f64>>,
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
    let noise = match opts.noise_mm {
        Some(v) if v.is_finite() && v > 0.0 => Noise {
            per_axis_mm: v,
            rms_mm: v * 3f64.sqrt(),
            source: "given".into(),
        },
        Some(_) => return Err(Error::usage("--noise must be a positive number of mm")),
        None => match estimate_noise(problem, &gaps_before) {
            Some((s, k)) => Noise {
                per_axis_mm: s.max(1e-4),
                rms_mm: s.max(1e-4) * 3f64.sqrt(),
                source: format!("estimated from {k} repeated-pose second differences"),
            },
            None => Noise {
                per_axis_mm: DEFAULT_NOISE_MM,
                rms_mm: DEFAULT_NOISE_MM * 3f64.sqrt(),
                source: "default (no repeated poses to estimate it from)".into(),
            },
        },
    };
    // Fits judge identifiability against the noise of these data.
    // Orientation residuals weigh as much as their own noise allows: the
    // weight (mm per mrad) is position noise over orientation noise, both
    // estimated the same way when the data repeat poses.
    let w_ori = if problem.uses_orientation() {
        let poses = problem.predict_rows(&[], &all);
        let rot_gaps: Vec<Vector3<f64>> = poses
            .iter()
            .zip(&problem.rows)
            .map(|(p, r)| {
                r.orientation
                    .map(|m| crate::model::chain::rotation_gap(&p.rotation, &m) * 1e3)
                    .unwrap_or_else(Vector3::zeros)
            })
            .collect();
        match estimate_noise(problem, &rot_gaps) {
            Some((s, _)) if s > 0.0 => (noise.per_axis_mm / s).clamp(0.01, 100.0),
            _ => problem.w_ori,
        }
    } else {
        problem.w_ori
    };
    let tuned = Problem {
        noise_mm: noise.per_axis_mm,
        w_ori,
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

    // Verdict.
    let base2 = cv0 * cv0;
    let fin2 = cur_cv * cur_cv;
    let excess_explained = if base2 > nr2 {
        (base2 - fin2) / (base2 - nr2)
    } else {
        1.0
    };
    let mut partial = Vec::new();
    let where_ = locate::locate(problem, &gaps_before, &prepared.pose_names, noise.rms_mm);
    // Without a measured noise level (no repeated poses) a gap above the
    // assumed 0.01 mm may just be a noisier instrument: call it unexplained
    // only with evidence of structure.
    let noise_assumed = opts.noise_mm.is_none() && noise.source.starts_with("default");
    let verdict: Vec<String> = if selected.is_empty() {
        if cv0 <= 1.5 * noise.rms_mm || (noise_assumed && !where_.has_structure()) {
            vec!["none".into()]
        } else {
            vec!["unexplained".into()]
        }
    } else if cur_cv <= 1.5 * noise.rms_mm || excess_explained >= 0.8 {
        let mut v: Vec<String> = selected.iter().map(|k| k.name().to_string()).collect();
        // Most of the gap is explained, but clear structure remains: name
        // the effects and say that something else is there too.
        if cur_cv > 2.0 * noise.rms_mm {
            v.push("unexplained".into());
        }
        v
    } else {
        partial = selected.iter().map(|k| k.name().to_string()).collect();
        vec!["unexplained".into()]
    };
    let where_after = locate::locate(problem, &gaps_after, &prepared.pose_names, noise.rms_mm);

    let mut words = Vec::new();
    words.push(format!(
        "Gap of the current model: {:.3} mm RMS (x {:.3}, y {:.3}, z {:.3}), {:.3} mm max over {} rows (noise {:.3} mm RMS, {}).",
        gap.rms_mm,
        gap.axis_rms_mm[0],
        gap.axis_rms_mm[1],
        gap.axis_rms_mm[2],
        gap.max_mm,
        n,
        noise.rms_mm,
        noise.source
    ));
    match verdict.first().map(String::as_str) {
        Some("none") if cv0 > 1.5 * noise.rms_mm => words.push(format!(
            "Verdict: none. The gap ({cv0:.3} mm held-out) shows no structure in time, direction, poses or joints: it looks like measurement noise larger than the assumed {:.3} mm per axis (no repeated poses to measure it; give --noise if the instrument is better).",
            noise.per_axis_mm
        )),
        Some("none") => words
            .push("Verdict: none. The gap is at the measurement noise; nothing to explain.".into()),
        Some("unexplained") => {
            words.push(format!(
                "Verdict: unexplained. No effect of the library explains the gap (held-out {:.3} mm, {:.3} mm after the best candidates{}).",
                cv0,
                cur_cv,
                if partial.is_empty() {
                    String::new()
                } else {
                    format!(", which explain only part of it: {}", partial.join(", "))
                }
            ));
            words.extend(where_.words.iter().cloned());
            if !partial.is_empty() && !where_after.words.is_empty() {
                words.push(format!("What {} leaves:", partial.join(" + ")));
                words.extend(where_after.words.iter().map(|w| format!("  {w}")));
            }
        }
        _ => {
            words.push(format!("Verdict: {}.", verdict.join(" + ")));
            words.extend(where_.words.iter().cloned());
            for s in &steps {
                words.push(format!(
                    "Adding {}: held-out gap {:.3} → {:.3} mm (−{:.0} %).",
                    s.added, s.gap_before_mm, s.gap_after_mm, s.drop_pct
                ));
            }
            if verdict.iter().any(|v| v == "unexplained") {
                words.push(format!(
                    "What they leave ({:.3} mm held-out, noise {:.3} mm) is not explained by the library:",
                    cur_cv, noise.rms_mm
                ));
                words.extend(where_after.words.iter().map(|w| format!("  {w}")));
            }
        }
    }
    // What to do about it.
    match verdict.first().map(String::as_str) {
        Some("none") => words.push("Nothing to do: the model is as good as the measurement.".into()),
        Some("unexplained") => {
            let mut hint = String::from("Look where it points");
            let joint = where_.joint.as_ref().or(where_after.joint.as_ref());
            let step = where_.step.as_ref().or(where_after.step.as_ref());
            if let Some(j) = joint {
                hint.push_str(&format!(" (axis {}: its gearbox or encoder)", j.axis));
            }
            if let Some(s) = step {
                hint.push_str(&format!(
                    " (what happened between minute {:.0} and {:.0}: a knock, a slipping fixture or tracker)",
                    s.before_min, s.after_min
                ));
            }
            hint.push_str(", and measure more poses and times there before trusting a correction.");
            words.push(hint);
        }
        _ => words.push(format!(
            "Save the model with --save-model FILE.toml and correct programs with it: the held-out gap goes from {:.3} to {:.3} mm.",
            cv0, cur_cv
        )),
    }
    for a in &ambiguities {
        words.push(format!(
            "{} and {} are nearly indistinguishable on these poses (correlation {:.2}): {}.",
            a.pair[0], a.pair[1], a.correlation, a.separate_by
        ));
    }
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
        words,
        fitted,
        gaps_before,
        gaps_after,
    })
}

/// The model with the diagnosed effects added.
pub fn diagnosed_model(model: &Model, diagnosis: &Diagnosis) -> Model {
    let mut m = model.clone();
    m.effects.extend(diagnosis.fitted.iter().cloned());
    m
}
