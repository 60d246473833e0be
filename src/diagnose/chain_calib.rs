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
//! column-normalised Jacobian at the start, in a fixed order of preference
//! (instrument frame, point, joint offsets, origin translations, origin
//! rotations): a parameter whose column is (nearly) a combination of those
//! already kept is dropped and held at zero, with the kept parameters it
//! duplicates named. Nothing is guessed from the robot's shape.

use super::prepare::kabsch;
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

/// A raw parameter: its name and unit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParamDef {
    pub name: String,
    pub unit: &'static str,
    pub group: Group,
}

/// Number of raw parameters: frame 6, point 3, offsets 6, origins 36.
pub const N_RAW: usize = 51;
const FRAME: usize = 0;
const POINT: usize = 6;
const OFFSET: usize = 9;
const ORIGIN: usize = 15;

/// The raw parameters of a six-joint chain, in the order of preference.
pub fn param_defs() -> Vec<ParamDef> {
    let mut out = Vec::with_capacity(N_RAW);
    let def = |name: String, unit, group| ParamDef { name, unit, group };
    for a in ["x", "y", "z"] {
        out.push(def(format!("frame.{a}"), "mm", Group::Frame));
    }
    for a in ["rx", "ry", "rz"] {
        out.push(def(format!("frame.{a}"), "mrad", Group::Frame));
    }
    for a in ["x", "y", "z"] {
        out.push(def(format!("point.{a}"), "mm", Group::Point));
    }
    for j in 1..=6 {
        out.push(def(format!("joint{j}.offset"), "mrad", Group::Offset));
    }
    for j in 1..=6 {
        for a in ["x", "y", "z"] {
            out.push(def(format!("joint{j}.{a}"), "mm", Group::Origin));
        }
    }
    for j in 1..=6 {
        for a in ["rx", "ry", "rz"] {
            out.push(def(format!("joint{j}.{a}"), "mrad", Group::Origin));
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
pub struct Geometry {
    chain: Chain,
    offsets: Joints,
    point: Vector3<f64>,
    frame: Isometry3<f64>,
}

impl Geometry {
    pub fn of(nominal: &Nominal, x: &[f64]) -> Geometry {
        let mut chain = nominal.chain.clone();
        for (j, joint) in chain.joints.iter_mut().enumerate() {
            let t = &x[ORIGIN + 3 * j..ORIGIN + 3 * j + 3];
            let r = &x[ORIGIN + 18 + 3 * j..ORIGIN + 18 + 3 * j + 3];
            joint.origin *= small(t, r);
        }
        Geometry {
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
    let g = Geometry::of(nominal, x);
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
        let (gu, gd) = (Geometry::of(nominal, &up), Geometry::of(nominal, &down));
        for (i, s) in samples.iter().enumerate() {
            let d = (gu.predict(&s.q) - gd.predict(&s.q)) / (2.0 * H);
            for a in 0..3 {
                jac[(3 * i + a, c)] = d[a];
            }
        }
    }
    jac
}

/// A parameter the rank test dropped, and the kept ones it duplicates.
#[derive(Debug, Clone, Serialize)]
pub struct Dropped {
    pub name: String,
    /// Share of its column's norm independent of the kept columns.
    pub independent: f64,
    /// Kept parameters that make up most of its effect.
    pub same_as: Vec<String>,
}

/// The outcome of the rank test.
#[derive(Debug, Clone)]
pub struct Identifiability {
    /// Indices of the kept raw parameters.
    pub kept: Vec<usize>,
    /// Share of each kept column independent of those kept before it.
    pub independent: Vec<f64>,
    pub dropped: Vec<Dropped>,
    /// Rank of the kept (normalised) columns by their singular values: a
    /// check on the greedy test, equal to `kept.len()`.
    pub rank: usize,
    /// Condition number of the kept normalised columns.
    pub condition: f64,
}

/// Below this share of its norm independent of the parameters kept before
/// it, a parameter counts as not identifiable: its standard error would be
/// over 100 times that of a parameter with a column of its own, and the
/// fit would trade it against the others (on the UR5 grid a joint 5 zero
/// of −43 ± 90 mrad against a wrist length of −5 ± 10 mm at 1e-4).
pub const INDEPENDENT_MIN: f64 = 1e-2;

/// Rank test (ordered Gram–Schmidt on the column-normalised Jacobian) over
/// the raw parameters allowed by `allow`.
pub fn identify(
    nominal: &Nominal,
    samples: &[Sample],
    allow: &dyn Fn(Group) -> bool,
) -> Identifiability {
    let defs = param_defs();
    let x0 = vec![0.0; N_RAW];
    let cols: Vec<usize> = (0..N_RAW).filter(|&k| allow(defs[k].group)).collect();
    let mut jac = jacobian(nominal, &x0, &cols, samples);
    for mut c in jac.column_iter_mut() {
        let n = c.norm();
        if n > 0.0 {
            c /= n;
        }
    }
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let mut kept_local: Vec<usize> = Vec::new();
    let mut kept = Vec::new();
    let mut kept_independent = Vec::new();
    let mut dropped = Vec::new();
    for (c, &k) in cols.iter().enumerate() {
        let col: DVector<f64> = jac.column(c).into();
        let mut r = col.clone();
        // Twice: classical Gram–Schmidt loses orthogonality once.
        for _ in 0..2 {
            for b in &basis {
                let d = b.dot(&r);
                r.axpy(-d, b, 1.0);
            }
        }
        let independent = r.norm();
        if independent > INDEPENDENT_MIN {
            basis.push(r / independent);
            kept_local.push(c);
            kept.push(k);
            kept_independent.push(independent);
        } else {
            dropped.push(Dropped {
                name: defs[k].name.clone(),
                independent,
                same_as: duplicates(&jac, &kept_local, &col)
                    .into_iter()
                    .map(|i| defs[cols[i]].name.clone())
                    .collect(),
            });
        }
    }
    // A check on the greedy test: the kept columns together have full rank.
    let kept_cols = DMatrix::from_fn(jac.nrows(), kept_local.len(), |i, c| {
        jac[(i, kept_local[c])]
    });
    let sv = kept_cols.singular_values();
    let smax = sv.max();
    let rank = sv.iter().filter(|&&s| s > 1e-6 * smax).count();
    let condition = smax / sv.min().max(1e-300);
    Identifiability {
        kept,
        independent: kept_independent,
        dropped,
        rank,
        condition,
    }
}

/// The kept columns (local indices) that make up most of `col`.
fn duplicates(jac: &DMatrix<f64>, kept: &[usize], col: &DVector<f64>) -> Vec<usize> {
    if kept.is_empty() {
        return Vec::new();
    }
    let a = DMatrix::from_fn(jac.nrows(), kept.len(), |i, c| jac[(i, kept[c])]);
    let Ok(coef) = a.svd(true, true).solve(col, 1e-10) else {
        return Vec::new();
    };
    // Columns are unit vectors: a coefficient is its share of the effect.
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
pub struct Param {
    pub name: String,
    pub unit: &'static str,
    pub value: f64,
    pub stderr: f64,
}

/// A fitted geometry.
#[derive(Debug, Clone)]
pub struct Fit {
    /// Raw parameter vector (dropped ones at zero).
    pub x: Vec<f64>,
    pub params: Vec<Param>,
    /// RMS of the 3-D gap on the fitted samples, mm.
    pub rms_mm: f64,
}

impl Fit {
    pub fn geometry(&self, nominal: &Nominal) -> Geometry {
        Geometry::of(nominal, &self.x)
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
        let g = Geometry::of(self.nominal, &self.x);
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

/// Fit the raw parameters `kept` (others at zero) to `samples`.
pub fn fit(nominal: &Nominal, samples: &[Sample], kept: &[usize]) -> Result<Fit> {
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
    let jtj = jac.transpose() * &jac;
    let cov = jtj
        .pseudo_inverse(1e-12)
        .map_err(|e| Error::new(ErrorKind::NoConvergence, e.to_string()))?
        * sigma2;
    let defs = param_defs();
    let params = kept
        .iter()
        .enumerate()
        .map(|(i, &k)| Param {
            name: defs[k].name.clone(),
            unit: defs[k].unit,
            value: x[k],
            stderr: cov[(i, i)].max(0.0).sqrt(),
        })
        .collect();
    Ok(Fit {
        x,
        params,
        rms_mm: (rss / samples.len() as f64).sqrt(),
    })
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
    let g = Geometry::of(&nominal, &[0.0; N_RAW]);
    let sim: Vec<Vector3<f64>> = samples.iter().map(|s| g.in_base(&s.q)).collect();
    let meas: Vec<Vector3<f64>> = samples.iter().map(|s| s.position).collect();
    kabsch(&sim, &meas).map_err(|f| {
        Error::input(format!(
            "the instrument frame: {}",
            f.reason().trim_start_matches(':').trim()
        ))
    })
}
