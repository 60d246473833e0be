//! Signatures of a joint's own error that the library lacks, tested beyond
//! the static calibration like its effects: a cyclic error of a joint angle
//! (n cycles per turn, as a gear's or an encoder's) and an error that
//! depends on the direction the joint last moved (backlash). Each is a
//! joint-angle error of a known shape, so its columns are the joint's zero
//! column times the shape: sin and cos of n·q for a cycle, ±1 by the
//! direction of approach for backlash. What the calibration cannot take up
//! of it is tested by F against the noise, at the stage's level shared
//! among the signatures tried; the largest significant one is reported,
//! with its size from the fit (never from the located gap).

use super::fit::Problem;
use super::signature::{hcat, lstsq, LsqFactor};
use super::stats::{detectable_noncentrality, Test, LEVEL, POWER};
use super::test_noise::TestNoise;
use crate::model::EffectKind;
use nalgebra::DVector;
use serde::Serialize;

/// Most cycles per turn tried: gears and encoders of robot axes show their
/// first few harmonics; higher ones need more poses than a session has.
const MAX_CYCLES: u32 = 4;
/// Least lever of a joint (mm of the measured point's move per mrad) for a
/// signature of it to be tried: joint 6 turns about a line a tenth of a mm
/// from the reflector, and no position shows its angle.
const MIN_LEVER_MM_PER_MRAD: f64 = 0.01;

/// The shape of a joint signature.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum JointShape {
    /// Δq = A·sin(n·q + φ).
    Cyclic { cycles: u32, phase_rad: f64 },
    /// The joint stops `amplitude / 2` behind (`lags`) or ahead of where
    /// it was sent, by the direction it last moved; the play is the
    /// amplitude.
    Backlash { lags: bool },
}

/// A joint signature found beyond the static calibration.
#[derive(Debug, Clone, Serialize)]
pub struct JointSignature {
    /// 1-based axis.
    pub axis: usize,
    #[serde(flatten)]
    pub shape: JointShape,
    /// The fitted amplitude (cyclic) or play (backlash) of the joint angle,
    /// mrad.
    pub amplitude_mrad: f64,
    /// RMS of what it removes from the residual, mm.
    pub rms_mm: f64,
    /// Its F test beyond the static effects selected.
    pub test: Test,
    /// Gravity sag's F test beyond the calibration and this signature,
    /// where sag was selected: not significant, sag only stood in for it.
    pub sag_beyond: Option<Test>,
}

impl JointSignature {
    /// What the signature follows, in words.
    pub fn follows(&self) -> String {
        match self.shape {
            JointShape::Cyclic { cycles, .. } => format!(
                "the angle of axis {}, {cycles} cycle{} per turn",
                self.axis,
                if cycles == 1 { "" } else { "s" }
            ),
            JointShape::Backlash { .. } => {
                format!("the direction from which axis {} was approached", self.axis)
            }
        }
    }
}

/// The smallest joint signature of one shape these poses, times and noise
/// would have revealed beyond the calibration, at the level its test is
/// held to (shared among the signatures tried) with 90 % power.
#[derive(Debug, Clone, Serialize)]
pub struct JointLimit {
    /// 1-based axis.
    pub axis: usize,
    #[serde(flatten)]
    pub shape: LimitShape,
    /// Amplitude (cyclic, at its worst phase: the limit holds at any
    /// phase) or play (backlash) of the joint angle, mrad.
    pub amplitude_mrad: f64,
}

/// The shape a [`JointLimit`] is of: a signature's shape without what only
/// a fit gives (a phase, a sign).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum LimitShape {
    Cyclic { cycles: u32 },
    Backlash,
}

impl From<JointShape> for LimitShape {
    fn from(shape: JointShape) -> Self {
        match shape {
            JointShape::Cyclic { cycles, .. } => LimitShape::Cyclic { cycles },
            JointShape::Backlash { .. } => LimitShape::Backlash,
        }
    }
}

/// What the search for a joint signature found, and what it could have.
#[derive(Debug, Clone, Default)]
pub struct Searched {
    /// The largest significant signature.
    pub found: Option<JointSignature>,
    /// The detection limit of every signature tried.
    pub limits: Vec<JointLimit>,
}

/// The detection limit of one signature: `cols` (per mrad of the joint
/// angle) less what `base` takes up of them, against the noise. A cycle's
/// size depends on its phase; the limit is its worst phase's, the least
/// eigenvalue of the columns' Gram matrix beyond the calibration (what the
/// calibration cannot take up of any phase).
fn limit(base: Option<&LsqFactor>, cols: &[DVector<f64>], noise: &TestNoise, level: f64) -> f64 {
    let own = |v: &DVector<f64>| base.map_or_else(|| v.norm_squared(), |f| f.solve(v).1);
    let least = match cols {
        [c] => own(c),
        [s, c] => {
            let (a, d) = (own(s), own(c));
            let b = 0.5 * (own(&(s + c)) - a - d);
            // The smaller eigenvalue of [[a, b], [b, d]].
            0.5 * (a + d) - (0.25 * (a - d).powi(2) + b * b).sqrt()
        }
        _ => return f64::INFINITY,
    };
    let lambda = detectable_noncentrality(level, cols.len() as f64, POWER);
    if least <= 1e-300 {
        return f64::INFINITY;
    }
    (lambda * noise.sigma2 / least).sqrt()
}

/// Per joint, each row's direction of approach: +1 where it came from
/// below (its angle rose since the row measured before it), −1 from above,
/// 0 for the first row or a joint that did not move.
fn approach(problem: &Problem) -> [Vec<f64>; 6] {
    let mut order: Vec<usize> = (0..problem.rows.len()).collect();
    order.sort_by(|&a, &b| {
        problem.rows[a]
            .time_min
            .total_cmp(&problem.rows[b].time_min)
    });
    std::array::from_fn(|axis| {
        let mut out = vec![0.0; problem.rows.len()];
        for w in order.windows(2) {
            let d = problem.rows[w[1]].q[axis] - problem.rows[w[0]].q[axis];
            if d.abs() >= 1e-9 {
                out[w[1]] = d.signum();
            }
        }
        out
    })
}

/// Look for a joint signature in what the static effects `statics` leave
/// on `problem` (its fixed thermal effects taken out), beyond a full
/// kinematic calibration and the instrument's frame. The static effects
/// are small (tenths of a mm and of a mrad): linear at zero to well within
/// the noise, so every model here is fitted by linear least squares on the
/// Jacobians at zero, and the models tested are nested exactly. `None`
/// where none is significant at `level` (the family's, shared among the
/// signatures tried), or the problem keeps no Jacobians at zero.
pub fn find(problem: &Problem, statics: &[EffectKind], noise: &TestNoise, level: f64) -> Searched {
    search(problem, statics, noise, level).unwrap_or_default()
}

fn search(
    problem: &Problem,
    statics: &[EffectKind],
    noise: &TestNoise,
    level: f64,
) -> Option<Searched> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let w = problem.width();
    let mut kinds = vec![EffectKind::GeometryOffset, EffectKind::TrackerFrame];
    let sag = statics.contains(&EffectKind::GravitySag);
    if sag {
        kinds.push(EffectKind::GravitySag);
    }
    let base = problem.cached_jacobian(&kinds, &all)?;
    let geometry = problem.cached_jacobian(&[EffectKind::GeometryOffset], &all)?;
    let r = problem.residuals(&[], &all);
    let (_, rss_model) = lstsq(&base, &r);
    let dirs = approach(problem);
    // The zero column of every joint (mm of the residual per mrad).
    let params = EffectKind::GeometryOffset.params();
    let mut tried: Vec<(usize, JointShape, Vec<DVector<f64>>)> = Vec::new();
    for (axis, dir) in dirs.iter().enumerate() {
        let name = format!("dq{}_mrad", axis + 1);
        let Some(p) = params.iter().position(|info| info.name == name) else {
            continue;
        };
        let col = geometry.column(p).into_owned();
        let lever = col.norm() / (all.len().max(1) as f64).sqrt();
        if lever < MIN_LEVER_MM_PER_MRAD {
            continue;
        }
        let times =
            |f: &dyn Fn(usize) -> f64| DVector::from_fn(col.len(), |k, _| col[k] * f(all[k / w]));
        for n in 1..=MAX_CYCLES {
            let nf = f64::from(n);
            let q = |i: usize| problem.rows[i].q[axis];
            tried.push((
                axis,
                JointShape::Cyclic {
                    cycles: n,
                    phase_rad: 0.0,
                },
                vec![times(&|i| (nf * q(i)).sin()), times(&|i| (nf * q(i)).cos())],
            ));
        }
        tried.push((
            axis,
            JointShape::Backlash { lags: true },
            vec![times(&|i| dir[i])],
        ));
    }
    let level = level / tried.len().max(1) as f64;
    // Each signature's limit, in the size the report gives (a backlash's
    // play is twice the fitted coefficient).
    // The calibration's design factored once for all of them, and the
    // signatures taken on the cores at once (in order).
    use rayon::prelude::*;
    let factor = LsqFactor::new(&base);
    let limits = tried
        .par_iter()
        .map(|(axis, shape, cols)| JointLimit {
            axis: axis + 1,
            shape: LimitShape::from(*shape),
            amplitude_mrad: limit(factor.as_ref(), cols, noise, level)
                * if matches!(shape, JointShape::Backlash { .. }) {
                    2.0
                } else {
                    1.0
                },
        })
        .collect();
    let mut best: Option<(f64, JointSignature, Vec<DVector<f64>>)> = None;
    let solved: Vec<(DVector<f64>, f64)> = tried
        .par_iter()
        .map(|(_, _, cols)| lstsq(&hcat(&base, cols), &r))
        .collect();
    for ((axis, shape, cols), (coef, rss_full)) in tried.into_iter().zip(solved) {
        let test = Test::nested(
            rss_model,
            rss_full,
            cols.len(),
            noise.sigma2,
            noise.dof,
            level,
        );
        if !test.significant() {
            continue;
        }
        let c: Vec<f64> = (0..cols.len()).map(|k| coef[base.ncols() + k]).collect();
        // The sign of the zero column is the model's prediction's (see
        // `Problem::with_zero_jacobians_of`): the residual's coefficient is
        // the joint's own error.
        let (shape, amplitude_mrad) = match shape {
            JointShape::Cyclic { cycles, .. } => (
                JointShape::Cyclic {
                    cycles,
                    // A·sin(nq + φ) = A cos φ · sin nq + A sin φ · cos nq.
                    phase_rad: c[1].atan2(c[0]),
                },
                c[0].hypot(c[1]),
            ),
            // Δq = c·(direction): behind the motion where c < 0.
            JointShape::Backlash { .. } => {
                (JointShape::Backlash { lags: c[0] < 0.0 }, 2.0 * c[0].abs())
            }
        };
        let drop = rss_model - rss_full;
        if best.as_ref().is_some_and(|(d, ..)| *d >= drop) {
            continue;
        }
        best = Some((
            drop,
            JointSignature {
                axis: axis + 1,
                shape,
                amplitude_mrad,
                rms_mm: (drop.max(0.0) / all.len().max(1) as f64).sqrt(),
                test,
                sag_beyond: None,
            },
            cols,
        ));
    }
    let Some((_, mut sig, cols)) = best else {
        return Some(Searched {
            found: None,
            limits,
        });
    };
    if sag {
        let without = problem.cached_jacobian(
            &[EffectKind::GeometryOffset, EffectKind::TrackerFrame],
            &all,
        )?;
        let (_, rss_without) = lstsq(&hcat(&without, &cols), &r);
        let (_, rss_with) = lstsq(&hcat(&base, &cols), &r);
        let sag_params = EffectKind::GravitySag.params().len();
        sig.sag_beyond = Some(Test::nested(
            rss_without,
            rss_with,
            sag_params,
            noise.sigma2,
            noise.dof,
            LEVEL,
        ));
    }
    Some(Searched {
        found: Some(sig),
        limits,
    })
}
