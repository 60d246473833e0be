//! Measurements and a model turned into the fit problem: each row's
//! temperatures (measured, else the model's heating profile), its pose
//! identity (label, else identical joints), and, when asked, the rigid
//! frame of the instrument registered onto the robot base.

use super::arm::Arm;
use super::fit::{Problem, Row};
use super::instrument::instrument;
use super::measurements::Measurements;
use super::temps::TempOrigin;
use crate::error::{Error, Result};
use crate::model::effects::FULL_GEOMETRY_POSES;
use crate::model::Model;
use crate::thermal::TempHistory;
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use serde::Serialize;
use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

/// Data ready for the diagnosis.
#[derive(Debug, Clone)]
pub struct Prepared {
    pub problem: Problem,
    /// Pose names by pose id.
    pub pose_names: Vec<String>,
    /// The instrument frame the measured points were brought from: fitted
    /// when registration was asked for, or the model's own.
    pub registration: Option<Registration>,
    /// What the data were prepared from, where they were prepared from
    /// measurements: a diagnosis builds the model it saves from them and
    /// scores that model on them as `gap --model` does.
    pub source: Option<Arc<PreparedFrom>>,
    /// Where the rows' temperatures came from: the data, or the model's
    /// heating (a record, or a profile from a cold start the data do not
    /// say; the diagnosis uses a profile only where the caller assumes it,
    /// [`super::temps`]).
    pub temps: TempOrigin,
}

/// The measurements, the model and the arm a [`Prepared`] was made of.
#[derive(Debug, Clone)]
pub struct PreparedFrom {
    pub meas: Measurements,
    pub model: Model,
    pub arm: Arm,
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
    /// more poses, else all); 0 where the frame is the model's.
    pub rows_used: usize,
    /// The frame is the model file's `[instrument]`, not fitted here.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub from_model: bool,
    #[serde(skip)]
    pub transform: Isometry3<f64>,
}

/// Why the instrument frame cannot be registered. Typed, so that a caller
/// can name its own way of asking for the registration (a command-line
/// flag) in front of the reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegisterFailure {
    /// Fewer than 3 measured poses.
    TooFewPoses,
    /// The rigid fit has no solution (degenerate decomposition).
    NoFrame,
    /// The poses lie on a line or a plane.
    NotSpread,
}

impl RegisterFailure {
    /// What is missing, as the rest of a sentence that starts with what
    /// asked for the registration.
    pub fn reason(self) -> &'static str {
        match self {
            RegisterFailure::TooFewPoses => " needs at least 3 measured poses",
            RegisterFailure::NoFrame => ": the measured points do not fix a frame",
            RegisterFailure::NotSpread => {
                " needs poses spread in 3-D (these lie on a line or a plane)"
            }
        }
    }
}

impl fmt::Display for RegisterFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "registering the instrument frame{}", self.reason())
    }
}

impl From<RegisterFailure> for Error {
    fn from(f: RegisterFailure) -> Error {
        Error::input(f.to_string())
    }
}

/// Resolve every row's temperatures (measured or from the model's heating
/// profile), pose identity (label, else identical joints) and, with
/// `register`, bring measured points from the instrument's frame into the
/// robot base frame.
pub fn prepare(meas: &Measurements, model: &Model, register: bool) -> Result<Prepared> {
    prepare_arm(meas, model, &Arm::of_model(model)?, register)
}

/// [`prepare`] for any arm: its nominal geometry (OPW lengths or its URDF
/// chain) replaces the model's, and on an OPW arm the rows' joints and
/// orientations are mapped to the diagnosis chain's convention
/// ([`super::arm::ArmMap`]; the identity on a URDF chain).
pub fn prepare_arm(
    meas: &Measurements,
    model: &Model,
    arm: &Arm,
    register: bool,
) -> Result<Prepared> {
    let mut prepared = problem_of(meas, model, arm)?;
    place_in_base(&mut prepared, model, register)?;
    Ok(prepared)
}

/// The fit problem of the measurements, in the frame they were measured in.
pub fn problem_of(meas: &Measurements, model: &Model, arm: &Arm) -> Result<Prepared> {
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
    let noise = instrument()?;
    let problem = Problem {
        base: arm.base(model),
        fixed: model.effects()?,
        rows,
        history,
        w_ori: noise.position.noise_mm / noise.orientation.noise_mrad,
        noise_mm: noise.position.noise_mm,
        zero_jacobians: None,
        centre_poses: false,
        // A full kinematic calibration from as many poses as it has
        // parameters; the diagnosis decides by the rank it finds.
        origins: pose_names.len() >= FULL_GEOMETRY_POSES,
        memo: Default::default(),
    };
    let temps = if meas.has_temps() {
        TempOrigin::Measured
    } else if let Some(r) = &model.heating.recording {
        TempOrigin::Recording(r.clone())
    } else {
        TempOrigin::Profile(model.heating.profile.clone())
    };
    let prepared = Prepared {
        problem,
        pose_names,
        registration: None,
        source: Some(Arc::new(PreparedFrom {
            meas: meas.clone(),
            model: model.clone(),
            arm: arm.clone(),
        })),
        temps,
    };
    super::sanity::check_spread(&prepared.problem, &meas.file)?;
    Ok(prepared)
}

/// Fit the instrument's frame and bring the measured points and
/// orientations into the robot base frame.
pub fn register_instrument(
    prepared: &mut Prepared,
) -> std::result::Result<&Registration, RegisterFailure> {
    let reg = register_frame(&prepared.problem)?;
    Ok(into_frame(prepared, reg))
}

/// Bring the measured points into the robot base frame: by a frame
/// registered anew (`register`), else by the model's `[instrument]` frame
/// where it has one (a saved diagnosis's), else as they are. `gap`, the
/// diagnosis and the score of a saved model all place the data so.
pub fn place_in_base(
    prepared: &mut Prepared,
    model: &Model,
    register: bool,
) -> std::result::Result<(), RegisterFailure> {
    if register {
        register_instrument(prepared)?;
        return Ok(());
    }
    let Some(frame) = &model.instrument else {
        return Ok(());
    };
    let transform = frame.transform();
    let all: Vec<usize> = (0..prepared.problem.rows.len()).collect();
    let sim = prepared.problem.predict_rows(&[], &all);
    let n = all.len().max(1) as f64;
    let rms = (sim
        .iter()
        .zip(&prepared.problem.rows)
        .map(|(s, r)| {
            (transform
                .transform_point(&s.translation.vector.into())
                .coords
                - r.position)
                .norm_squared()
        })
        .sum::<f64>()
        / n)
        .sqrt();
    into_frame(
        prepared,
        Registration {
            translation_mm: frame.translation_mm,
            rotation_deg: frame.rotation_deg,
            rms_mm: rms,
            rows_used: 0,
            from_model: true,
            transform,
        },
    );
    Ok(())
}

/// The rows brought from the frame `reg` into the robot base frame.
fn into_frame(prepared: &mut Prepared, reg: Registration) -> &Registration {
    let inv = reg.transform.inverse();
    for r in &mut prepared.problem.rows {
        r.position = inv.transform_point(&r.position.into()).coords;
        r.orientation = r.orientation.map(|o| inv.rotation * o);
    }
    prepared.registration.insert(reg)
}

/// Rigid fit (Kabsch) of the model's positions onto the measured ones.
fn register_frame(problem: &Problem) -> std::result::Result<Registration, RegisterFailure> {
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
fn rigid_fit(
    problem: &Problem,
    rows: &[usize],
) -> std::result::Result<Registration, RegisterFailure> {
    if rows.len() < 3 {
        return Err(RegisterFailure::TooFewPoses);
    }
    let all = rows;
    let sim: Vec<Vector3<f64>> = problem
        .predict_rows(&[], all)
        .iter()
        .map(|p| p.translation.vector)
        .collect();
    let meas: Vec<Vector3<f64>> = all.iter().map(|&i| problem.rows[i].position).collect();
    let n = sim.len() as f64;
    let transform = kabsch(&sim, &meas)?;
    let (t, rot) = (transform.translation.vector, transform.rotation);
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
        from_model: false,
        transform,
    })
}

/// The rigid transform T that best maps the points `sim` onto `meas`
/// (least squares, Kabsch): meas ≈ T · sim.
pub fn kabsch(
    sim: &[Vector3<f64>],
    meas: &[Vector3<f64>],
) -> std::result::Result<Isometry3<f64>, RegisterFailure> {
    if sim.len() < 3 || sim.len() != meas.len() {
        return Err(RegisterFailure::TooFewPoses);
    }
    let n = sim.len() as f64;
    let cs = sim.iter().sum::<Vector3<f64>>() / n;
    let cm = meas.iter().sum::<Vector3<f64>>() / n;
    let mut h = Matrix3::zeros();
    for (s, m) in sim.iter().zip(meas) {
        h += (s - cs) * (m - cm).transpose();
    }
    let svd = h.svd(true, true);
    let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
        return Err(RegisterFailure::NoFrame);
    };
    let s = svd.singular_values;
    if s.min() < 1e-9 * s.max().max(1e-300) {
        return Err(RegisterFailure::NotSpread);
    }
    let v = vt.transpose();
    let d = (v * u.transpose()).determinant().signum();
    let r = v * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * u.transpose();
    let rot = UnitQuaternion::from_matrix(&r);
    let t = cm - rot * cs;
    Ok(Isometry3::from_parts(Translation3::from(t), rot))
}
