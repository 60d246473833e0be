//! How large the gap is: RMS and max of the position gap, the orientation
//! gap, and the measurement noise level the verdict compares them with.

use super::fit::Problem;
use super::instrument::instrument;
use super::prepare::Prepared;
use super::stats::NoiseDof;
use crate::error::{Error, Result};
use nalgebra::Vector3;
use serde::Serialize;
use std::collections::HashMap;

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

/// Per-row orientation gaps (rotation vector of R_model⁻¹·R_measured),
/// mrad; zero for rows without an orientation.
fn rotation_gaps(problem: &Problem) -> Vec<Vector3<f64>> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    problem
        .predict_rows(&[], &all)
        .iter()
        .zip(&problem.rows)
        .map(|(p, r)| {
            r.orientation
                .map(|m| crate::model::chain::rotation_gap(&p.rotation, &m) * 1e3)
                .unwrap_or_else(Vector3::zeros)
        })
        .collect()
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

/// Where the noise level of a diagnosis comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseSource {
    /// Given by the caller.
    Given,
    /// Estimated from this many repeated-pose second differences.
    Estimated { differences: usize },
    /// Not measured: no repeated poses to estimate it from, and none given.
    /// No instrument level stands in: every nested test divides by the
    /// residual variance of its larger model (the extra-sum-of-squares F
    /// test), and the level reported is what the diagnosis's final model
    /// leaves, its residual sum of squares over its `dof` degrees of
    /// freedom. What is left cannot be judged against it (no lack-of-fit
    /// test).
    NotMeasured { dof: usize },
}

/// The measurement noise level used for verdicts.
#[derive(Debug, Clone, Serialize)]
pub struct Noise {
    /// Per axis, mm.
    pub per_axis_mm: f64,
    /// 3-D RMS (per axis × √3), mm.
    pub rms_mm: f64,
    #[serde(serialize_with = "super::prose::serialize_noise_source")]
    pub source: NoiseSource,
}

/// Degrees of freedom per value of a noise level estimated from second
/// differences: a median of absolute values has about 37 % of the
/// efficiency of their mean square, and neighbouring second differences
/// share points (correlation −2/3), which about halves their number.
const DOF_PER_DIFFERENCE_VALUE: f64 = 0.37 * 0.5;

impl Noise {
    /// How well the noise variance is known: exact where the caller gave
    /// it, else the effective degrees of freedom of the estimate (three
    /// values per second difference), or of the residual that stands in
    /// for it where it was not measured.
    pub fn dof(&self) -> NoiseDof {
        match self.source {
            NoiseSource::Given => NoiseDof::EXACT,
            NoiseSource::Estimated { differences } => {
                NoiseDof((3 * differences) as f64 * DOF_PER_DIFFERENCE_VALUE)
            }
            NoiseSource::NotMeasured { dof } => NoiseDof(dof.max(1) as f64),
        }
    }

    /// Whether the noise level was measured from repeats or given: only
    /// then can what is left be tested against it.
    pub fn measured(&self) -> bool {
        !matches!(self.source, NoiseSource::NotMeasured { .. })
    }

    /// The level a residual sum of squares `rss` on `dof` degrees of
    /// freedom stands for, where the noise was not measured.
    pub fn from_residual(rss: f64, dof: usize) -> Noise {
        let d = dof.max(1);
        Noise::new(
            (rss.max(0.0) / d as f64).sqrt(),
            NoiseSource::NotMeasured { dof: d },
        )
    }

    fn new(per_axis_mm: f64, source: NoiseSource) -> Noise {
        Noise {
            per_axis_mm,
            rms_mm: per_axis_mm * 3f64.sqrt(),
            source,
        }
    }
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

/// The noise level of the data: `given` (mm per axis, positive), else
/// estimated from repeated poses, else not measured (no instrument level
/// is assumed: the diagnosis takes its residual instead, and the per-axis
/// level returned is only the instrument's nominal one, for the
/// identifiability of a first fit).
pub fn noise_level(problem: &Problem, gaps: &[Vector3<f64>], given: Option<f64>) -> Result<Noise> {
    let instrument = instrument()?;
    Ok(match given {
        // At most the noisiest instrument's (data/instrument.toml): a
        // noise of 1e300 mm calls every gap noise.
        Some(v) if v.is_finite() && v > 0.0 && v <= instrument.position.max_noise_mm => {
            Noise::new(v, NoiseSource::Given)
        }
        Some(_) => {
            return Err(Error::usage(format!(
                "the measurement noise must be a positive number of mm, at most {} (data/instrument.toml)",
                instrument.position.max_noise_mm
            )))
        }
        None => match estimate_noise(problem, gaps) {
            Some((s, k)) => Noise::new(
                s.max(instrument.position.min_noise_mm),
                NoiseSource::Estimated { differences: k },
            ),
            None => Noise::new(
                instrument.position.noise_mm,
                NoiseSource::NotMeasured { dof: 0 },
            ),
        },
    })
}

/// Weight of orientation residuals, mm per mrad: orientation residuals
/// weigh as much as their own noise allows, position noise over orientation
/// noise, both estimated the same way when the data repeat poses; else the
/// problem's (instrument) weight.
pub fn orientation_weight(problem: &Problem, noise: &Noise) -> f64 {
    if !problem.uses_orientation() {
        return problem.w_ori;
    }
    match estimate_noise(problem, &rotation_gaps(problem)) {
        Some((s, _)) if s > 0.0 => (noise.per_axis_mm / s).clamp(1e-4, 100.0),
        _ => problem.w_ori,
    }
}

/// Where the noise was not measured: the level of the residual a full
/// static calibration (the arm's geometry and the instrument's frame)
/// leaves, its sum of squares over its degrees of freedom. Only the
/// identifiability of the fits and the localisation's bars stand on it;
/// every test divides by its own larger model's residual variance, and
/// the level reported is the final model's.
pub(super) fn first_residual(problem: &Problem, rows: &[usize]) -> Noise {
    let values = problem.residuals(&[], rows).len();
    for kinds in [
        &[
            crate::model::EffectKind::GeometryOffset,
            crate::model::EffectKind::TrackerFrame,
        ][..],
        &[crate::model::EffectKind::TrackerFrame][..],
    ] {
        if let Ok(f) = super::fit::fit(problem, rows, kinds) {
            if values > f.n_free {
                return Noise::from_residual(f.rss, values - f.n_free);
            }
        }
    }
    Noise::from_residual(problem.residuals(&[], rows).norm_squared(), values)
}
