//! What the controller module needs to know, taken from the arm and the
//! model: the arm's OPW lengths and joint convention, each link's growth
//! per degree and the motors that warm it, and the heating curves as
//! states that can be carried forward. Models the module cannot carry
//! are refused here, with the reason typed.

use crate::error::{Error, ErrorKind, Result};
use crate::model::Model;
use crate::robot::{Opw, Robot};
use crate::thermal::saturating::SatCurve;
use nalgebra::UnitQuaternion;
use std::fmt;

/// The most exponential terms per axis the module carries (the fitted
/// kinds have one or two).
pub const MAX_TERMS: usize = 2;

/// A gap between two corrections longer than this (minutes) counts as a
/// stop, over which the motors cool. A running program corrects a move
/// every few seconds; a cycle's longest wait (a part change, an operator)
/// is rarely longer than a minute or two. See docs/runtime.md.
pub const DEFAULT_STOP_GAP_MIN: f64 = 5.0;

/// Why a model cannot run on the controller.
#[derive(Debug, Clone, PartialEq)]
pub enum Refusal {
    /// The arm has no closed form (a URDF arm that is not an ABB-style
    /// six-axis arm with a spherical wrist).
    NoClosedForm(String),
    /// A parallel-arm robot: the controller's axis 3 is coupled to axis 2.
    ParallelArm,
    /// A heating curve with no state to carry (a polynomial, a recording).
    NotSaturating,
    /// More exponential terms on an axis than the module carries.
    TooManyTerms { axis: usize, terms: usize },
    /// Effects beyond link expansion (a diagnosed model).
    Effects(usize),
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::NoClosedForm(why) => write!(
                f,
                "the arm has no closed-form geometry the module can write ({why})"
            ),
            Refusal::ParallelArm => write!(
                f,
                "a parallel-arm robot (axis 3 driven through a parallelogram) is not carried yet"
            ),
            Refusal::NotSaturating => write!(
                f,
                "the heating model has no state to carry through running and stopped spans: fit a saturating one (heating fit --model two-tau)"
            ),
            Refusal::TooManyTerms { axis, terms } => write!(
                f,
                "axis {axis}'s heating curve has {terms} terms; the module carries at most {MAX_TERMS}"
            ),
            Refusal::Effects(n) => write!(
                f,
                "the model has {n} effect(s) beyond link expansion, which the module does not compute"
            ),
        }
    }
}

impl From<Refusal> for Error {
    fn from(r: Refusal) -> Error {
        Error::new(ErrorKind::Unsupported, format!("--runtime: {r}"))
    }
}

/// One link: how much it grows per degree above the reference, and which
/// motors' mean temperature is its own.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkGrowth {
    /// K0·α, 1/°C.
    pub per_degree: f64,
    /// Motors 1..6 whose mean is the link's temperature.
    pub motors: [bool; 6],
}

/// Everything the module is written from.
#[derive(Debug, Clone, PartialEq)]
pub struct RuntimeSpec {
    /// The arm's name, for the module's header.
    pub arm: String,
    pub geom: Opw,
    /// θ = sign·q + offset, per axis; offsets in degrees.
    pub signs: [f64; 6],
    pub offsets_deg: [f64; 6],
    /// Base, lower arm, upper arm, wrist.
    pub links: [LinkGrowth; 4],
    /// Temperature the targets were taught at, °C.
    pub t_ref: f64,
    pub curves: [SatCurve; 6],
    /// The robot's base frame in the world (rotation only: a drift is a
    /// direction).
    pub base_rotation: UnitQuaternion<f64>,
    pub stop_gap_min: f64,
}

impl RuntimeSpec {
    /// The spec of `robot` (the arm the controller drives) under `model`,
    /// its base frame rotated by `base_rotation` in the world.
    pub fn new(
        robot: &Robot,
        model: &Model,
        base_rotation: UnitQuaternion<f64>,
    ) -> Result<RuntimeSpec> {
        let arm = robot
            .opw
            .as_ref()
            .map_err(|why| Refusal::NoClosedForm(why.clone()))?;
        if arm.coupling != 0.0 {
            return Err(Refusal::ParallelArm.into());
        }
        let effects = model.effects()?;
        if !effects.is_empty() {
            return Err(Refusal::Effects(effects.len()).into());
        }
        let curves = model.profile()?.curves().ok_or(Refusal::NotSaturating)?;
        for (i, c) in curves.iter().enumerate() {
            if c.terms.len() > MAX_TERMS {
                return Err(Refusal::TooManyTerms {
                    axis: i + 1,
                    terms: c.terms.len(),
                }
                .into());
            }
        }
        let th = &model.thermal;
        let link = |l: &crate::model::expansion::LinkThermal| LinkGrowth {
            per_degree: th.k0 * l.alpha,
            motors: std::array::from_fn(|m| l.motors.contains(&(m + 1))),
        };
        Ok(RuntimeSpec {
            arm: robot.name.clone(),
            geom: arm.geom,
            signs: arm.signs,
            offsets_deg: arm.offsets.map(f64::to_degrees),
            links: [
                link(&th.base),
                link(&th.lower_arm),
                link(&th.upper_arm),
                link(&th.wrist),
            ],
            t_ref: th.t_ref,
            curves,
            base_rotation,
            stop_gap_min: DEFAULT_STOP_GAP_MIN,
        })
    }
}
