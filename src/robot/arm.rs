//! The robot with its model: a serial chain (forward kinematics for any
//! arm), the OPW form where the arm has that shape (closed-form IK), joint
//! limits, speeds and the thermal-expansion model.

use super::chain::{Chain, ChainJoint};
use super::conf::{CfxBits, RobConf};
use super::frames::{flange_of_target, target_of_flange, ToolData, WobjData};
use super::ik::{IkFailure, Limits, OpwArm, Solutions};
use super::urdf::{self, IRB140_URDF};
use super::{Joints, MotorTemps, ThermalExpansion, IRB140};
use crate::error::{Error, ErrorKind, Result};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use std::f64::consts::FRAC_PI_2;
use std::path::Path;
use std::sync::OnceLock;

#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    pub name: String,
    pub chain: Chain,
    /// The OPW form of the chain, or why it has none (then IK is refused).
    pub opw: std::result::Result<OpwArm, String>,
    /// rad, inclusive.
    pub limits: Limits,
    pub max_speed_deg_s: [f64; 6],
    pub thermal: ThermalExpansion,
}

impl Robot {
    /// The ABB IRB 140 from the embedded URDF (parsed once per process).
    pub fn irb140() -> Robot {
        static IRB140_ROBOT: OnceLock<Robot> = OnceLock::new();
        IRB140_ROBOT
            .get_or_init(|| {
                // The embedded file is tested to parse to exactly the
                // built-in model; the fallback only keeps this infallible.
                Robot::from_urdf_str("irb140.urdf", IRB140_URDF)
                    .unwrap_or_else(|_| Robot::irb140_builtin())
            })
            .clone()
    }

    /// The IRB 140 built from the spec's numbers in code (the reference the
    /// embedded URDF is tested against).
    pub fn irb140_builtin() -> Robot {
        let d = f64::to_radians;
        let joint = |name: &str, xyz: [f64; 3], axis: Vector3<f64>| ChainJoint {
            name: name.to_string(),
            origin: Isometry3::translation(xyz[0], xyz[1], xyz[2]),
            axis: Unit::new_normalize(axis),
        };
        let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
        let o = IRB140;
        Robot {
            name: "abb_irb140".into(),
            chain: Chain {
                joints: [
                    joint("joint_1", [0.0, 0.0, 0.0], z),
                    joint("joint_2", [o.a1, 0.0, o.c1], y),
                    joint("joint_3", [0.0, 0.0, o.c2], y),
                    joint("joint_4", [0.0, 0.0, 0.0], x),
                    joint("joint_5", [o.c3, 0.0, 0.0], y),
                    joint("joint_6", [o.c4, 0.0, 0.0], x),
                ],
                tip: Isometry3::from_parts(
                    Translation3::identity(),
                    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_2),
                ),
            },
            opw: Ok(OpwArm::abb(IRB140)),
            limits: [
                (d(-180.0), d(180.0)),
                (d(-90.0), d(110.0)),
                (d(-230.0), d(50.0)),
                (d(-200.0), d(200.0)),
                (d(-115.0), d(115.0)),
                (d(-400.0), d(400.0)),
            ],
            max_speed_deg_s: [200.0, 200.0, 260.0, 360.0, 360.0, 450.0],
            thermal: ThermalExpansion::default(),
        }
    }

    /// Any serial six-axis arm from URDF text; the thermal model is the
    /// default one (replace `thermal` to change it).
    pub fn from_urdf_str(file: &str, text: &str) -> Result<Robot> {
        let arm = urdf::parse(file, text)?;
        let opw = arm.chain.extract_opw();
        Ok(Robot {
            name: arm.name,
            chain: arm.chain,
            opw,
            limits: arm.limits,
            max_speed_deg_s: arm.max_speed_deg_s,
            thermal: ThermalExpansion::default(),
        })
    }

    pub fn from_urdf_file(path: &Path) -> Result<Robot> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, &e))?;
        Robot::from_urdf_str(&path.display().to_string(), &text)
    }

    /// The OPW arm, warm when motor temperatures are given.
    pub fn opw_at(&self, temps: Option<&MotorTemps>) -> Result<OpwArm> {
        let arm = self.opw.as_ref().map_err(|why| {
            Error::new(
                ErrorKind::Unsupported,
                format!(
                    "{}: closed-form IK needs an arm with an offset shoulder and a spherical wrist: {why}",
                    self.name
                ),
            )
        })?;
        Ok(match temps {
            Some(t) => OpwArm {
                geom: self.thermal.expand(&arm.geom, t),
                ..*arm
            },
            None => *arm,
        })
    }

    /// Flange (tool0) pose in the base frame; with motor temperatures, on
    /// the warm (expanded) arm.
    pub fn fk(&self, q: &Joints, temps: Option<&MotorTemps>) -> Isometry3<f64> {
        match (&self.opw, temps) {
            (Ok(arm), None) => arm.fk(q),
            (Ok(arm), Some(t)) => OpwArm {
                geom: self.thermal.expand(&arm.geom, t),
                ..*arm
            }
            .fk(q),
            (Err(_), None) => self.chain.fk(q),
            (Err(_), Some(t)) => self.chain.fk_scaled(q, &self.thermal.scales(t)),
        }
    }

    /// All joint solutions (within limits, with every allowed turn of the
    /// axes) for a flange pose, each with its robconf.
    pub fn ik(&self, pose: &Isometry3<f64>, temps: Option<&MotorTemps>) -> Result<Solutions> {
        self.solve(pose, temps, None)
    }

    /// The solution with robconf `conf` (exactly, or within
    /// [`super::ik::CONF_TOLERANCE`] of its quadrants).
    pub fn ik_conf(
        &self,
        pose: &Isometry3<f64>,
        conf: &RobConf,
        temps: Option<&MotorTemps>,
    ) -> Result<Joints> {
        if CfxBits::from_cfx(conf.cfx).is_none() {
            return Err(Error::input(format!(
                "robconf {conf}: cfx must be 0..7 for this robot family"
            )));
        }
        let (found, sols) = self
            .checked_arm(pose, temps)?
            .solve_conf(pose, &self.limits, conf)
            .map_err(|f| self.failure(f))?;
        match found {
            Some(s) => Ok(s.q),
            None => {
                let mut have: Vec<String> = sols.iter().map(|s| s.conf.to_string()).collect();
                have.dedup();
                Err(Error::new(
                    ErrorKind::Unreachable,
                    format!("no solution with robconf {conf} within the joint limits"),
                )
                .with_note(format!("reachable configurations: {}", have.join(" "))))
            }
        }
    }

    fn solve(
        &self,
        pose: &Isometry3<f64>,
        temps: Option<&MotorTemps>,
        want: Option<&RobConf>,
    ) -> Result<Solutions> {
        self.checked_arm(pose, temps)?
            .solve(pose, &self.limits, want)
            .map_err(|f| self.failure(f))
    }

    /// The (warm) OPW arm, after refusing non-finite input.
    fn checked_arm(&self, pose: &Isometry3<f64>, temps: Option<&MotorTemps>) -> Result<OpwArm> {
        let finite = pose.translation.vector.iter().all(|v| v.is_finite())
            && pose.rotation.coords.iter().all(|v| v.is_finite());
        if !finite {
            return Err(Error::input("pose is not finite"));
        }
        if let Some(t) = temps {
            if !t.iter().all(|v| v.is_finite()) {
                return Err(Error::input("motor temperatures are not finite"));
            }
        }
        self.opw_at(temps)
    }

    fn failure(&self, f: IkFailure) -> Error {
        match f {
            IkFailure::OutOfReach(r) => Error::new(
                ErrorKind::Unreachable,
                format!(
                    "out of reach: the wrist centre is {:.3} mm from axis 2 facing it, {:.3} mm over the back; the arm reaches {:.3} to {:.3} mm",
                    r.front, r.back, r.min, r.max
                ),
            ),
            IkFailure::JointLimits(v) => {
                let list: Vec<String> = v
                    .iter()
                    .flatten()
                    .map(|(j, q, (lo, hi))| {
                        format!(
                            "axis {} at {:.3}° (limits {:.1}..{:.1})",
                            j + 1,
                            q.to_degrees(),
                            lo.to_degrees(),
                            hi.to_degrees()
                        )
                    })
                    .collect();
                Error::new(
                    ErrorKind::Unreachable,
                    "every solution violates a joint limit".to_string(),
                )
                .with_note(list.join("; "))
            }
        }
    }

    /// Joint angles that put `tool` at the robtarget pose `target` in
    /// `wobj`, with robconf `conf` (on the warm arm when temperatures are
    /// given).
    pub fn target_joints(
        &self,
        target: &Isometry3<f64>,
        conf: &RobConf,
        tool: &ToolData,
        wobj: &WobjData,
        temps: Option<&MotorTemps>,
    ) -> Result<Joints> {
        let flange = flange_of_target(target, tool, wobj)?;
        self.ik_conf(&flange, conf, temps)
    }

    /// The robtarget pose (in `wobj`, for `tool`) that joint angles reach.
    pub fn target_of_joints(
        &self,
        q: &Joints,
        tool: &ToolData,
        wobj: &WobjData,
        temps: Option<&MotorTemps>,
    ) -> Result<Isometry3<f64>> {
        target_of_flange(&self.fk(q, temps), tool, wobj)
    }

    /// robconf of joint angles (on the nominal arm).
    pub fn conf_of(&self, q: &Joints) -> RobConf {
        match &self.opw {
            Ok(arm) => arm.conf_of(q),
            Err(_) => self.chain_conf_of(q),
        }
    }

    /// robconf of an arm without OPW form, from its chain: wrist centre =
    /// the joint-5 origin, forward = axis 2 × axis 1 (as on the IRB 140).
    fn chain_conf_of(&self, q: &Joints) -> RobConf {
        let ax = self.chain.axes(q);
        let (p1, d1) = ax[0];
        let (p2, d2) = ax[1];
        let (p3, _) = ax[2];
        let w = ax[4].0;
        let forward = d2.cross(&d1);
        let lower = p3 - p2;
        let normal = d2.cross(&lower);
        RobConf::from_parts(
            q,
            CfxBits {
                behind_axis1: (w - p1).dot(&forward) < 0.0,
                behind_lower_arm: (w - p2).dot(&normal) < 0.0,
                axis5_negative: q[4] < 0.0,
            },
        )
    }
}
