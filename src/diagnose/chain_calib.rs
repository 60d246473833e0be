//! Geometric calibration of any serial chain (a URDF's) from measured
//! positions of one point on it: the instrument frame, the measured point,
//! joint zero offsets and an error of every joint origin, fitted jointly by
//! Levenberg–Marquardt.
//!
//! Parameterisation: each joint origin of the chain is followed by a small
//! translation (x, y, z, mm) and rotation (rotation vector, mrad) in that
//! joint's own frame; each joint angle gets an offset (mrad); the measured
//! point is a vector in the flange (tool0) frame (mm); the instrument frame
//! is the starting rigid transform followed by a small translation and
//! rotation in the robot base frame. That is 51 raw parameters, many of
//! which position-only data cannot tell apart (a rotation of an origin
//! about its own joint axis is the joint offset; the first joint's origin
//! is the instrument frame; translations along parallel axes are one
//! another). Which ones are kept is decided by a rank test of the
//! Jacobian at the start, in a fixed order of preference (instrument frame,
//! point, joint offsets, origin translations, origin rotations), with an
//! absolute floor before any normalising: a parameter is kept only where
//! the part of its column independent of those kept before it moves the
//! data by more than the noise over the parameter's resolution (its lever
//! times the noise). A parameter that hardly moves the measured point at
//! all (a joint turning about an axis through it), one that is (nearly) a
//! combination of those already kept, and one whose standard error would
//! exceed its resolution are dropped and held at zero, each with its
//! reason. After the fit, the standard errors come from the covariance of
//! the kept parameters (a proper inverse: an unconstrained direction is
//! dropped, never reported with zero variance), and a parameter outside
//! its plausible range or less well determined than its resolution is
//! dropped and the fit repeated. Nothing is guessed from the robot's shape.

use super::prepare::kabsch;
pub use super::unidentified::Unidentified;
use crate::error::{Error, ErrorKind, Result};
use crate::robot::chain::Chain;
use crate::robot::Joints;
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Isometry3, Owned, Translation3, UnitQuaternion, Vector3};
use serde::Serialize;

/// One measured position of the point, in the instrument's frame, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Radians, the robot's own joint values.
    pub q: Joints,
    pub position: Vector3<f64>,
}

/// The kinds of parameter, in the order of preference of the rank test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Group {
    /// The instrument frame (`tracker-frame`).
    Frame,
    /// The measured point in the flange frame.
    Point,
    /// Joint zero offsets (`geometry-offset`).
    Offset,
    /// Joint origin translations and rotations (`geometry-offset`).
    Origin,
}

/// A raw parameter: its name and unit, the largest value a real arm's
/// error of its kind can take, and the largest standard error a
/// calibration may report for it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParamDef {
    pub name: String,
    pub unit: &'static str,
    pub group: Group,
    /// Largest plausible magnitude, in `unit`: a fitted value beyond it is
    /// the fit wandering along a direction the data hardly constrain, not
    /// an error of the arm.
    pub plausible: f64,
    /// Largest standard error worth reporting, in `unit` (a tenth of the
    /// plausible range): a parameter the data pin less well is not
    /// identifiable from them.
    pub resolution: f64,
}

/// Plausible magnitudes of each kind of parameter: the instrument frame
/// relative to its rigid (Kabsch) start, mm and mrad; the measured point
/// off its nominal place, mm (a reflector whose holder is not the one
/// assumed); joint zeros, mrad; joint origins, mm and mrad. An industrial
/// arm's geometric errors are tenths of a mm and of a mrad, a few mrad at
/// worst (a UR5's wrist tilt: 12 mrad); these bounds are several times
/// wider.
const PLAUSIBLE_FRAME: (f64, f64) = (100.0, 100.0);
const PLAUSIBLE_POINT_MM: f64 = 100.0;
const PLAUSIBLE_OFFSET_MRAD: f64 = 50.0;
const PLAUSIBLE_ORIGIN: (f64, f64) = (10.0, 50.0);

/// Number of raw parameters: frame 6, point 3, offsets 6, origins 36.
pub const N_RAW: usize = 51;
const FRAME: usize = 0;
const POINT: usize = 6;
const OFFSET: usize = 9;
const ORIGIN: usize = 15;

/// The raw parameters of a six-joint chain, in the order of preference.
pub fn param_defs() -> Vec<ParamDef> {
    let mut out = Vec::with_capacity(N_RAW);
    let def = |name: String, unit, group, plausible: f64| ParamDef {
        name,
        unit,
        group,
        plausible,
        resolution: plausible / 10.0,
    };
    for a in ["x", "y", "z"] {
        out.push(def(
            format!("frame.{a}"),
            "mm",
            Group::Frame,
            PLAUSIBLE_FRAME.0,
        ));
    }
    for a in ["rx", "ry", "rz"] {
        out.push(def(
            format!("frame.{a}"),
            "mrad",
            Group::Frame,
            PLAUSIBLE_FRAME.1,
        ));
    }
    for a in ["x", "y", "z"] {
        out.push(def(
            format!("point.{a}"),
            "mm",
            Group::Point,
            PLAUSIBLE_POINT_MM,
        ));
    }
    for j in 1..=6 {
        out.push(def(
            format!("joint{j}.offset"),
            "mrad",
            Group::Offset,
            PLAUSIBLE_OFFSET_MRAD,
        ));
    }
    for j in 1..=6 {
        for a in ["x", "y", "z"] {
            out.push(def(
                format!("joint{j}.{a}"),
                "mm",
                Group::Origin,
                PLAUSIBLE_ORIGIN.0,
            ));
        }
    }
    for j in 1..=6 {
        for a in ["rx", "ry", "rz"] {
            out.push(def(
                format!("joint{j}.{a}"),
                "mrad",
                Group::Origin,
                PLAUSIBLE_ORIGIN.1,
            ));
        }
    }
    out
}

/// The nominal geometry and where the calibration starts from.
#[derive(Debug, Clone, PartialEq)]
pub struct Nominal {
    pub chain: Chain,
    /// The measured point in the flange (tool0) frame, mm.
    pub point: Vector3<f64>,
    /// Robot base → instrument frame at the start.
    pub frame: Isometry3<f64>,
}

fn small(t: &[f64], r_mrad: &[f64]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(t[0], t[1], t[2]),
        UnitQuaternion::from_scaled_axis(Vector3::new(r_mrad[0], r_mrad[1], r_mrad[2]) * 1e-3),
    )
}

/// The chain, point and frame of a raw parameter vector, ready to predict.
#[derive(Debug, Clone)]
pub struct ChainGeometry {
    chain: Chain,
    offsets: Joints,
    point: Vector3<f64>,
    frame: Isometry3<f64>,
}

impl ChainGeometry {
    pub fn of(nominal: &Nominal, x: &[f64]) -> ChainGeometry {
        let mut chain = nominal.chain.clone();
        for (j, joint) in chain.joints.iter_mut().enumerate() {
            let t = &x[ORIGIN + 3 * j..ORIGIN + 3 * j + 3];
            let r = &x[ORIGIN + 18 + 3 * j..ORIGIN + 18 + 3 * j + 3];
            joint.origin *= small(t, r);
        }
        ChainGeometry {
            chain,
            offsets: std::array::from_fn(|j| x[OFFSET + j] * 1e-3),
            point: nominal.point + Vector3::new(x[POINT], x[POINT + 1], x[POINT + 2]),
            frame: nominal.frame * small(&x[FRAME..FRAME + 3], &x[FRAME + 3..FRAME + 6]),
        }
    }

    /// The point in the robot base frame (before the instrument frame).
    pub fn in_base(&self, q: &Joints) -> Vector3<f64> {
        let q: Joints = std::array::from_fn(|j| q[j] + self.offsets[j]);
        (self.chain.fk(&q) * nalgebra::Point3::from(self.point)).coords
    }

    /// The point in the instrument's frame.
    pub fn predict(&self, q: &Joints) -> Vector3<f64> {
        self.frame.transform_point(&self.in_base(q).into()).coords
    }

    /// Robot base → instrument frame.
    pub fn frame(&self) -> &Isometry3<f64> {
        &self.frame
    }

    /// The calibrated chain (joint offsets not included: they are the
    /// robot's angle readings).
    pub fn chain(&self) -> &Chain {
        &self.chain
    }
}

/// Measured minus predicted, per sample.
pub fn gaps(nominal: &Nominal, x: &[f64], samples: &[Sample]) -> Vec<Vector3<f64>> {
    let g = ChainGeometry::of(nominal, x);
    samples
        .iter()
        .map(|s| s.position - g.predict(&s.q))
        .collect()
}

/// Central-difference Jacobian of the predictions (3 rows per sample) with
/// respect to the raw parameters `cols` at `x`.
fn jacobian(nominal: &Nominal, x: &[f64], cols: &[usize], samples: &[Sample]) -> DMatrix<f64> {
    let mut jac = DMatrix::zeros(3 * samples.len(), cols.len());
    // mm and mrad: the model is smooth at this scale, and far from rounding.
    const H: f64 = 1e-3;
    for (c, &k) in cols.iter().enumerate() {
        let mut up = x.to_vec();
        let mut down = x.to_vec();
        up[k] += H;
        down[k] -= H;
        let (gu, gd) = (
            ChainGeometry::of(nominal, &up),
            ChainGeometry::of(nominal, &down),
        );
        for (i, s) in samples.iter().enumerate() {
            let d = (gu.predict(&s.q) - gd.predict(&s.q)) / (2.0 * H);
            for a in 0..3 {
                jac[(3 * i + a, c)] = d[a];
            }
        }
    }
    jac
}

/// A parameter held at zero, and why.
#[derive(Debug, Clone, Serialize)]
pub struct Dropped {
    pub name: String,
    pub unit: &'static str,
    #[serde(flatten)]
    pub why: Unidentified,
}

/// The outcome of the rank test.
#[derive(Debug, Clone)]
pub struct Identifiability {
    /// Indices of the kept raw parameters.
    pub kept: Vec<usize>,
    /// Share of each kept column independent of those kept before it.
    pub independent: Vec<f64>,
    pub dropped: Vec<Dropped>,
}

/// Below this share of its norm independent of the parameters kept before
/// it, a parameter counts as a combination of them whatever the noise: its
/// standard error would be over 100 times that of a parameter with a
/// column of its own, and the fit would trade it against the others (on
/// the UR5 grid a joint 5 zero of −43 ± 90 mrad against a wrist length of
/// −5 ± 10 mm at 1e-4).
pub const INDEPENDENT_MIN: f64 = 1e-2;

/// Largest displacement of the measured point, over the poses, per unit of
/// the parameter whose column `col` is (3 rows per pose).
fn lever(col: &DVector<f64>) -> f64 {
    col.as_slice()
        .chunks(3)
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max)
}

/// Rank test over the raw parameters allowed by `allow`, against the
/// measurement noise `noise_mm` (per axis): ordered Gram–Schmidt on the
/// Jacobian's columns as they are (mm per unit), each parameter kept only
/// where the part of its column independent of those kept before it is
/// at least 1 % of its norm (not a rounding-level combination) and large
/// enough that the noise leaves its standard error within its resolution
/// (noise over that independent norm). The floor is absolute: a column of
/// rounding noise, normalised, would look independent.
pub fn identify(
    nominal: &Nominal,
    samples: &[Sample],
    allow: &dyn Fn(Group) -> bool,
    noise_mm: f64,
) -> Identifiability {
    let defs = param_defs();
    let x0 = vec![0.0; N_RAW];
    let cols: Vec<usize> = (0..N_RAW).filter(|&k| allow(defs[k].group)).collect();
    let jac = jacobian(nominal, &x0, &cols, samples);
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let mut kept_local: Vec<usize> = Vec::new();
    let mut kept = Vec::new();
    let mut kept_independent = Vec::new();
    let mut dropped = Vec::new();
    for (c, &k) in cols.iter().enumerate() {
        let def = &defs[k];
        let col: DVector<f64> = jac.column(c).into();
        let lev = lever(&col);
        // Changed by its resolution, it moves no pose by the noise.
        if lev * def.resolution < noise_mm {
            dropped.push(Dropped {
                name: def.name.clone(),
                unit: def.unit,
                why: Unidentified::NoLever { lever_mm: lev },
            });
            continue;
        }
        let mut r = col.clone();
        // Twice: classical Gram–Schmidt loses orthogonality once.
        for _ in 0..2 {
            for b in &basis {
                let d = b.dot(&r);
                r.axpy(-d, b, 1.0);
            }
        }
        let own = r.norm();
        let independent = own / col.norm().max(1e-300);
        let stderr = noise_mm / own.max(1e-300);
        if independent <= INDEPENDENT_MIN {
            dropped.push(Dropped {
                name: def.name.clone(),
                unit: def.unit,
                why: Unidentified::SameAs {
                    independent,
                    same_as: duplicates(&jac, &kept_local, &col)
                        .into_iter()
                        .map(|i| defs[cols[i]].name.clone())
                        .collect(),
                },
            });
        } else if stderr > def.resolution {
            dropped.push(Dropped {
                name: def.name.clone(),
                unit: def.unit,
                why: Unidentified::Unresolved {
                    stderr,
                    limit: def.resolution,
                },
            });
        } else {
            basis.push(r / own);
            kept_local.push(c);
            kept.push(k);
            kept_independent.push(independent);
        }
    }
    Identifiability {
        kept,
        independent: kept_independent,
        dropped,
    }
}

/// The kept columns (local indices) that make up most of `col`.
fn duplicates(jac: &DMatrix<f64>, kept: &[usize], col: &DVector<f64>) -> Vec<usize> {
    if kept.is_empty() {
        return Vec::new();
    }
    // Columns normalised: a coefficient is then its share of the effect.
    let norms: Vec<f64> = kept
        .iter()
        .map(|&c| jac.column(c).norm().max(1e-300))
        .collect();
    let a = DMatrix::from_fn(jac.nrows(), kept.len(), |i, c| jac[(i, kept[c])] / norms[c]);
    let unit = col / col.norm().max(1e-300);
    let Ok(coef) = a.svd(true, true).solve(&unit, 1e-10) else {
        return Vec::new();
    };
    let mut big: Vec<(usize, f64)> = coef
        .iter()
        .enumerate()
        .filter(|(_, v)| v.abs() > 0.2)
        .map(|(i, v)| (kept[i], v.abs()))
        .collect();
    big.sort_by(|a, b| b.1.total_cmp(&a.1));
    big.into_iter().take(3).map(|(i, _)| i).collect()
}

/// A fitted parameter.
#[derive(Debug, Clone, Serialize)]
pub struct ChainParam {
    pub name: String,
    pub unit: &'static str,
    pub value: f64,
    pub stderr: f64,
}

/// A fitted geometry.
#[derive(Debug, Clone)]
pub struct ChainFit {
    /// Raw parameter vector (dropped ones at zero).
    pub x: Vec<f64>,
    pub params: Vec<ChainParam>,
    /// RMS of the 3-D gap on the fitted samples, mm.
    pub rms_mm: f64,
    /// Residual standard deviation per axis, mm (the residual sum of
    /// squares over its degrees of freedom).
    pub sigma_mm: f64,
}

impl ChainFit {
    pub fn geometry(&self, nominal: &Nominal) -> ChainGeometry {
        ChainGeometry::of(nominal, &self.x)
    }
}

struct Lm<'a> {
    nominal: &'a Nominal,
    samples: &'a [Sample],
    kept: &'a [usize],
    x: Vec<f64>,
}

impl Lm<'_> {
    fn full(&self, p: &DVector<f64>) -> Vec<f64> {
        let mut x = self.x.clone();
        for (i, &k) in self.kept.iter().enumerate() {
            x[k] = p[i];
        }
        x
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Lm<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, p: &DVector<f64>) {
        self.x = self.full(p);
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_iterator(self.kept.len(), self.kept.iter().map(|&k| self.x[k]))
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let g = ChainGeometry::of(self.nominal, &self.x);
        let mut r = DVector::zeros(3 * self.samples.len());
        for (i, s) in self.samples.iter().enumerate() {
            let d = g.predict(&s.q) - s.position;
            for a in 0..3 {
                r[3 * i + a] = d[a];
            }
        }
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        Some(jacobian(self.nominal, &self.x, self.kept, self.samples))
    }
}

/// ChainFit the raw parameters `kept` (others at zero) to `samples`, as they
/// are: standard errors from the covariance σ²(JᵀJ)⁻¹ where JᵀJ is
/// positive definite, infinite where it is not (a direction the data leave
/// free).
pub fn fit(nominal: &Nominal, samples: &[Sample], kept: &[usize]) -> Result<ChainFit> {
    let m = 3 * samples.len();
    if m <= kept.len() {
        return Err(Error::input(format!(
            "{} measured points cannot fix {} parameters",
            samples.len(),
            kept.len()
        )));
    }
    let lm = Lm {
        nominal,
        samples,
        kept,
        x: vec![0.0; N_RAW],
    };
    let (lm, report) = LevenbergMarquardt::new().with_patience(100).minimize(lm);
    if !report.termination.was_successful() || !report.objective_function.is_finite() {
        return Err(Error::new(
            ErrorKind::NoConvergence,
            format!(
                "the geometric calibration did not converge ({:?})",
                report.termination
            ),
        ));
    }
    let x = lm.x.clone();
    let g = gaps(nominal, &x, samples);
    let rss: f64 = g.iter().map(|v| v.norm_squared()).sum();
    let jac = jacobian(nominal, &x, kept, samples);
    let sigma2 = rss / (m - kept.len()) as f64;
    // A proper inverse: a direction the data leave free has no finite
    // variance, and is not given a zero one (as a pseudo-inverse would).
    let cov = (jac.transpose() * &jac).cholesky().map(|c| c.inverse());
    let defs = param_defs();
    let params = kept
        .iter()
        .enumerate()
        .map(|(i, &k)| ChainParam {
            name: defs[k].name.clone(),
            unit: defs[k].unit,
            value: x[k],
            stderr: cov
                .as_ref()
                .map_or(f64::INFINITY, |c| (c[(i, i)] * sigma2).max(0.0).sqrt()),
        })
        .collect();
    Ok(ChainFit {
        x,
        params,
        rms_mm: (rss / samples.len() as f64).sqrt(),
        sigma_mm: sigma2.sqrt(),
    })
}

/// A calibration: the fit of the identifiable parameters and those held
/// at zero, with why.
#[derive(Debug, Clone)]
pub struct Calibration {
    pub fit: ChainFit,
    pub kept: Vec<usize>,
    pub dropped: Vec<Dropped>,
    /// Number of singular values of the kept columns, each scaled by its
    /// parameter's resolution, that move the data by more than the
    /// residual noise: equal to the number kept (checked), counted, not
    /// assumed.
    pub rank: usize,
    /// Condition number of the kept columns scaled by their resolutions.
    pub condition: f64,
}

/// ChainFit the parameters `id` keeps, then drop, one at a time and refitting,
/// the parameter furthest outside what a metrologist signs: a value beyond
/// its plausible range, or a standard error (from the fit's own residual)
/// above its resolution. What is left is reported with honest standard
/// errors.
pub fn calibrate(
    nominal: &Nominal,
    samples: &[Sample],
    id: Identifiability,
) -> Result<Calibration> {
    let defs = param_defs();
    let mut kept = id.kept;
    let mut dropped = id.dropped;
    loop {
        let fit = fit(nominal, samples, &kept)?;
        // The worst offender, by how far it is beyond its bound.
        let worst = fit
            .params
            .iter()
            .zip(&kept)
            .filter_map(|(p, &k)| {
                let d = &defs[k];
                let over_value = p.value.abs() / d.plausible;
                let over_se = p.stderr / d.resolution;
                let why = if over_value > 1.0 && over_value >= over_se {
                    Unidentified::Implausible {
                        value: p.value,
                        limit: d.plausible,
                    }
                } else if over_se > 1.0 {
                    Unidentified::Unresolved {
                        stderr: p.stderr,
                        limit: d.resolution,
                    }
                } else {
                    return None;
                };
                Some((over_value.max(over_se), k, why))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        match worst {
            Some((_, k, why)) => {
                kept.retain(|&x| x != k);
                dropped.push(Dropped {
                    name: defs[k].name.clone(),
                    unit: defs[k].unit,
                    why,
                });
            }
            None => {
                let (rank, condition) = scaled_rank(nominal, samples, &fit, &kept);
                dropped.sort_by_key(|d| defs.iter().position(|x| x.name == d.name));
                return Ok(Calibration {
                    fit,
                    kept,
                    dropped,
                    rank,
                    condition,
                });
            }
        }
    }
}

/// Rank and condition of the kept columns at the solution, each scaled by
/// its parameter's resolution: a singular value counts when moving the
/// parameters one resolution along its direction moves the data by more
/// than the fit's residual noise.
fn scaled_rank(
    nominal: &Nominal,
    samples: &[Sample],
    fit: &ChainFit,
    kept: &[usize],
) -> (usize, f64) {
    if kept.is_empty() {
        return (0, 1.0);
    }
    let defs = param_defs();
    let jac = jacobian(nominal, &fit.x, kept, samples);
    let scaled = DMatrix::from_fn(jac.nrows(), kept.len(), |i, c| {
        jac[(i, c)] * defs[kept[c]].resolution
    });
    let sv = scaled.singular_values();
    let rank = sv.iter().filter(|&&s| s > fit.sigma_mm).count();
    (rank, sv.max() / sv.min().max(1e-300))
}

/// The instrument frame that best maps the nominal chain's points onto the
/// measured ones (rigid, Kabsch), so that the calibration starts close.
pub fn start_frame(
    chain: &Chain,
    point: Vector3<f64>,
    samples: &[Sample],
) -> Result<Isometry3<f64>> {
    let nominal = Nominal {
        chain: chain.clone(),
        point,
        frame: Isometry3::identity(),
    };
    let g = ChainGeometry::of(&nominal, &[0.0; N_RAW]);
    let sim: Vec<Vector3<f64>> = samples.iter().map(|s| g.in_base(&s.q)).collect();
    let meas: Vec<Vector3<f64>> = samples.iter().map(|s| s.position).collect();
    kabsch(&sim, &meas).map_err(|f| {
        Error::input(format!(
            "the instrument frame: {}",
            f.reason().trim_start_matches(':').trim()
        ))
    })
}
