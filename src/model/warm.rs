//! The warm robot: what the simulation says a robot does at a time of its
//! warm-up. The controller moves with its nominal model; the warm arm is
//! the model file's (base link expansion and any effects a diagnosis
//! added), with motor temperatures from its heating profile.

use super::effects::{Effect, EffectKind};
use super::file::Model;
use super::perturb::{lag_taus, predict, Base, Geometry, LinkLags, RowState};
use crate::error::{Error, ErrorKind, Result};
use crate::robot::conf::RobConf;
use crate::robot::{Joints, LinkScales, Robot};
use crate::thermal::{HeatingProfile, MotorTemps, TempHistory};
use nalgebra::{Isometry3, Matrix6, Vector6};
use std::f64::consts::TAU;
use std::sync::Arc;

/// When the robot is at a target: a minute of the warm-up, or the
/// thermally stable state after it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Moment {
    Minute(f64),
    Steady,
}

impl std::fmt::Display for Moment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Moment::Minute(t) => write!(f, "minute {t}"),
            Moment::Steady => write!(f, "steady state"),
        }
    }
}

/// The thermal state of the arm at one moment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    pub temps: MotorTemps,
    /// Motor temperatures through each link's thermal lag (base, lower
    /// arm, upper arm, wrist), when the model has one.
    pub lagged: Option<[MotorTemps; 4]>,
    /// Each link's length over its cold length by the base model at
    /// `temps`: worked out once per moment, not twice per target.
    pub scales: LinkScales,
}

/// The nominal (controller) robot and the warm model.
pub struct WarmRobot {
    /// The controller's model: computes joints from targets.
    pub nominal: Robot,
    base: Base,
    effects: Vec<Effect>,
    profile: Box<dyn HeatingProfile>,
    history: Option<TempHistory>,
    instrument_left_out: bool,
}

/// Newton's tolerances for models whose warm arm changes shape: the
/// correction is exact to far below what a `num` can hold.
const NEWTON_POSITION_MM: f64 = 1e-8;
const NEWTON_ROTATION_RAD: f64 = 1e-12;
const NEWTON_MAX_STEPS: usize = 30;

impl WarmRobot {
    /// The warm robot of `model` on the arm `robot` (whose geometry the
    /// controller uses). `horizon_min`: the latest minute that will be
    /// asked for (the thermal lag integrates the history up to it).
    pub fn new(robot: Robot, model: &Model, horizon_min: f64) -> Result<WarmRobot> {
        WarmRobot::with_profile(robot, model, model.profile()?, horizon_min)
    }

    /// The warm robot of `model` with its motor temperatures from
    /// `profile` in place of the model's own (a day of running and
    /// stops, `thermal::duty`, made from the model's curves).
    pub fn with_profile(
        robot: Robot,
        model: &Model,
        profile: Box<dyn HeatingProfile>,
        horizon_min: f64,
    ) -> Result<WarmRobot> {
        // A tracker frame describes the instrument a diagnosis measured
        // with, not the robot: moving every target by it would be wrong.
        let (effects, instrument): (Vec<Effect>, Vec<Effect>) = model
            .effects()?
            .into_iter()
            .partition(|e| e.kind != EffectKind::TrackerFrame);
        let history = match lag_taus(&effects) {
            Some(_) => Some(TempHistory::from_profile(
                profile.as_ref(),
                horizon_min.max(0.0),
            )?),
            None => None,
        };
        Ok(WarmRobot {
            // The arm the controller drives is the one that warms: its
            // own geometry, in its own joint convention.
            base: Base {
                nominal: match &robot.opw {
                    Ok(a) => Geometry::Opw(a.geom),
                    Err(_) => Geometry::Chain(Arc::new(robot.chain.clone())),
                },
                thermal: model.thermal.clone(),
                // The instrument's point, not the robot's: `correct` moves
                // tool0 and the program's tools.
                point: nalgebra::Vector3::zeros(),
            },
            nominal: robot,
            effects,
            profile,
            history,
            instrument_left_out: !instrument.is_empty(),
        })
    }

    /// Whether the model's tracker frame (the instrument's, not the
    /// robot's) was left out.
    pub fn instrument_left_out(&self) -> bool {
        self.instrument_left_out
    }

    /// True when the warm arm is the nominal arm with longer links only:
    /// then the closed-form IK of the expanded arm is exact.
    pub fn is_pure_expansion(&self) -> bool {
        self.effects.is_empty()
    }

    /// The thermal state at a moment. For many moments, build
    /// [`WarmRobot::states`] once: it integrates the thermal lag once.
    pub fn state(&self, at: Moment) -> Result<State> {
        self.states().at(at)
    }

    /// The thermal states of this robot, with the thermal lag (if any)
    /// integrated over the whole history once.
    pub fn states(&self) -> States<'_> {
        States {
            warm: self,
            lags: self
                .history
                .as_ref()
                .and_then(|h| LinkLags::new(h, &self.effects)),
            known: None,
        }
    }

    /// Where the warm robot's flange is at joints `q`.
    pub fn flange(&self, q: &Joints, state: &State) -> Isometry3<f64> {
        if self.is_pure_expansion() {
            return self.nominal.fk_scaled(q, &state.scales);
        }
        predict(
            &self.base,
            &self.effects,
            &RowState {
                q: *q,
                temps: state.temps,
                lagged: state.lagged,
            },
        )
    }

    /// Joints that put the warm robot's flange at `flange` with robconf
    /// `conf`: closed form on the expanded arm, then Newton on the full
    /// model when effects change the arm's shape.
    pub fn joints_for(
        &self,
        flange: &Isometry3<f64>,
        conf: &RobConf,
        state: &State,
    ) -> Result<Joints> {
        let q = self.nominal.ik_conf_scaled(flange, conf, &state.scales)?;
        if self.is_pure_expansion() {
            return Ok(q);
        }
        match self.newton(flange, q, state, |j, r| j.lu().solve(r)) {
            Newton::Reached(q) => Ok(q),
            Newton::Stuck(_) => Err(Error::new(
                ErrorKind::NoConvergence,
                "the warm model's Jacobian is singular at this pose (a wrist or shoulder singularity)",
            )),
            Newton::NotReached(_) => Err(Error::new(
                ErrorKind::NoConvergence,
                format!(
                    "Newton did not reach the target within {NEWTON_MAX_STEPS} steps on the warm model"
                ),
            )),
        }
    }

    /// Newton's method on the warm model from `q` toward the flange pose
    /// `flange`, each step `step(J, r)` from the Jacobian and the pose
    /// error.
    fn newton(
        &self,
        flange: &Isometry3<f64>,
        mut q: Joints,
        state: &State,
        step: impl Fn(Matrix6<f64>, &Vector6<f64>) -> Option<Vector6<f64>>,
    ) -> Newton {
        for _ in 0..NEWTON_MAX_STEPS {
            let r = pose_error(flange, &self.flange(&q, state));
            if r.fixed_rows::<3>(0).norm() < NEWTON_POSITION_MM
                && r.fixed_rows::<3>(3).norm() < NEWTON_ROTATION_RAD
            {
                return Newton::Reached(q);
            }
            let Some(dq) = step(self.jacobian(&q, state), &r) else {
                return Newton::Stuck(q);
            };
            for (qi, d) in q.iter_mut().zip(dq.iter()) {
                *qi += d;
            }
        }
        Newton::NotReached(q)
    }

    /// The warm joints that put the flange at `flange`, nearest `near`:
    /// the branch whose joints lie nearest (axes 1, 2, 3 and 5 only where
    /// `free_wrist`, the wrist singularity, splits axes 4 and 6 freely),
    /// each axis taken within half a turn of its value in `near` (the
    /// controller moves the axes, it does not wrap them). The joint limits
    /// are not applied: the caller judges them on the joints it gets.
    pub fn joints_near(
        &self,
        flange: &Isometry3<f64>,
        near: &Joints,
        free_wrist: bool,
        state: &State,
    ) -> Result<Joints> {
        let branches = self.nominal.branches_scaled(flange, &state.scales)?;
        let axes: &[usize] = if free_wrist {
            &[0, 1, 2, 4]
        } else {
            &[0, 1, 2, 3, 4, 5]
        };
        let distance = |q: &Joints| axes.iter().map(|&j| (q[j] - near[j]).powi(2)).sum::<f64>();
        let q = branches
            .iter()
            .map(|b| std::array::from_fn(|j| wrap_near(b[j], near[j])))
            .min_by(|a: &Joints, b: &Joints| distance(a).total_cmp(&distance(b)))
            .ok_or_else(|| {
                Error::new(
                    ErrorKind::Unreachable,
                    "the warm arm has no branch at this pose",
                )
            })?;
        if self.is_pure_expansion() {
            return Ok(q);
        }
        // The effects beyond expansion move the solution by a little:
        // Newton from the expanded arm's branch, in the least-squares
        // sense so that a singular wrist does not stop it; what it cannot
        // reach the caller reports as the residual.
        let (Newton::Reached(q) | Newton::Stuck(q) | Newton::NotReached(q)) =
            self.newton(flange, q, state, |j, r| {
                j.svd(true, true).solve(r, 1e-9).ok()
            });
        Ok(q)
    }

    /// d(pose)/dq by central differences (the effects' kinematics are not
    /// differentiated by hand).
    fn jacobian(&self, q: &Joints, state: &State) -> Matrix6<f64> {
        const H: f64 = 1e-6;
        let mut j = Matrix6::zeros();
        for i in 0..6 {
            let mut qp = *q;
            let mut qm = *q;
            qp[i] += H;
            qm[i] -= H;
            let fm = self.flange(&qm, state);
            let d = pose_error(&self.flange(&qp, state), &fm) / (2.0 * H);
            j.set_column(i, &d);
        }
        j
    }
}

/// Thermal states at any moment, the lag integrated once.
pub struct States<'a> {
    warm: &'a WarmRobot,
    lags: Option<LinkLags<'a>>,
    /// One moment's state worked out ahead: a run at one moment asks for
    /// it a million times, and working it out each time (the heating
    /// curves' exponentials) was a twentieth of correcting a target.
    known: Option<(Moment, State)>,
}

impl States<'_> {
    /// Work out the state at `at` once, for every later [`States::at`] of
    /// it (the same state, kept).
    pub fn remember(&mut self, at: Moment) -> Result<()> {
        self.known = None;
        let state = self.at(at)?;
        self.known = Some((at, state));
        Ok(())
    }

    /// The thermal state at a moment.
    pub fn at(&self, at: Moment) -> Result<State> {
        if let Some((m, state)) = &self.known {
            if *m == at {
                return Ok(*state);
            }
        }
        match at {
            Moment::Steady => {
                let temps = self.warm.profile.steady()?;
                Ok(State {
                    temps,
                    lagged: self.lags.as_ref().map(|_| [temps; 4]),
                    scales: self.warm.base.thermal.scales(&temps),
                })
            }
            Moment::Minute(t) => {
                let temps = self.warm.profile.temps_at(t)?;
                Ok(State {
                    temps,
                    lagged: self.lags.as_ref().map(|lags| lags.at(t)),
                    scales: self.warm.base.thermal.scales(&temps),
                })
            }
        }
    }
}

/// Where Newton's method ended: at the pose, where no step could be
/// taken (a singular Jacobian), or after its last step.
enum Newton {
    Reached(Joints),
    Stuck(Joints),
    NotReached(Joints),
}

/// `a` plus whole turns, within half a turn of `near`.
pub fn wrap_near(a: f64, near: f64) -> f64 {
    a + TAU * ((near - a) / TAU).round()
}

/// `goal ⊖ at`: position difference (mm) and rotation vector (rad) taking
/// `at` to `goal`, in the base frame.
pub fn pose_error(goal: &Isometry3<f64>, at: &Isometry3<f64>) -> Vector6<f64> {
    let dp = goal.translation.vector - at.translation.vector;
    let dr = (goal.rotation * at.rotation.inverse()).scaled_axis();
    Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z)
}
