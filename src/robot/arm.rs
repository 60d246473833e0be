//! The robot with its model: a serial chain (forward kinematics for any
//! arm), the OPW form where the arm has that shape (closed-form IK), joint
//! limits and speeds. A warm arm is the same arm with its segments scaled
//! ([`LinkScales`]); what scales them (temperatures) is the model's business.

use super::chain::{conf_of_axes, Chain};
use super::conf::{CfxBits, RobConf};
use super::frames::{flange_of_target, target_of_flange, ToolFrame, WobjFrames};
use super::ik::{IkFailure, Limits, OpwArm, Solutions, Violation, LIMIT_EPS};
use super::urdf::{self, IRB140_URDF};
use super::{Joints, LinkScales, Opw};
use crate::error::{Error, ErrorKind, Remedy, Result};
use nalgebra::Isometry3;
use std::f64::consts::PI;
use std::path::Path;
use std::sync::OnceLock;

#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    pub name: String,
    pub chain: Chain,
    /// The OPW form of the chain, or why it has none (then IK is numeric:
    /// `ik_chain`).
    pub opw: std::result::Result<OpwArm, String>,
    /// rad, inclusive.
    pub limits: Limits,
    pub max_speed_deg_s: [f64; 6],
}

/// The embedded IRB 140, parsed once per process. Tests parse the embedded
/// file and check it against docs/model.md (`tests/robot/kinematics.rs`), so the
/// `expect` cannot fire on a tested build.
fn irb140_ref() -> &'static Robot {
    static IRB140_ROBOT: OnceLock<Robot> = OnceLock::new();
    IRB140_ROBOT.get_or_init(|| {
        Robot::from_urdf_str("irb140.urdf", IRB140_URDF)
            .expect("the embedded data/irb140/irb140.urdf is a readable six-axis arm")
    })
}

/// The nominal OPW lengths of the IRB 140, mm: those of the embedded URDF
/// (`data/irb140/irb140.urdf`), extracted from its chain when it is parsed.
pub fn irb140_opw() -> Opw {
    match &irb140_ref().opw {
        Ok(arm) => arm.geom,
        Err(why) => panic!("the embedded data/irb140/irb140.urdf has no OPW form: {why}"),
    }
}

impl Robot {
    /// The ABB IRB 140 from the embedded URDF (`data/irb140/irb140.urdf`,
    /// parsed once per process).
    pub fn irb140() -> Robot {
        irb140_ref().clone()
    }

    /// Any serial six-axis arm from URDF text.
    pub fn from_urdf_str(file: &str, text: &str) -> Result<Robot> {
        let arm = urdf::parse(file, text)?;
        let opw = arm.chain.extract_opw();
        Ok(Robot {
            name: arm.name,
            chain: arm.chain,
            opw,
            limits: arm.limits,
            max_speed_deg_s: arm.max_speed_deg_s,
        })
    }

    /// An ABB arm from its OPW lengths (mm): the chain built from them
    /// ([`Chain::from_opw`]), ABB's joint conventions ([`OpwArm::abb`]),
    /// `coupling` as [`Chain::coupling`], limits in rad, speeds in °/s.
    pub fn from_opw(
        name: &str,
        geom: Opw,
        coupling: f64,
        limits: Limits,
        max_speed_deg_s: [f64; 6],
    ) -> Robot {
        Robot {
            name: name.to_string(),
            chain: Chain::from_opw(&geom, coupling),
            opw: Ok(OpwArm {
                coupling,
                ..OpwArm::abb(geom)
            }),
            limits,
            max_speed_deg_s,
        }
    }

    pub fn from_urdf_file(path: &Path) -> Result<Robot> {
        let bytes = crate::input::read_path(path)?;
        // A URDF saved as UTF-16 (Windows editors do) is named, not called
        // invalid UTF-8.
        crate::input::refuse_unread_encoding(&path.display().to_string(), &bytes, "UTF-8")?;
        let text = String::from_utf8(bytes).map_err(|e| {
            Error::io(
                path,
                &std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()),
            )
        })?;
        Robot::from_urdf_str(&path.display().to_string(), &text)
    }

    /// The OPW arm, with its segments scaled when `scales` are given.
    pub fn opw_arm(&self, scales: Option<&LinkScales>) -> Result<OpwArm> {
        let arm = self.opw_ref()?;
        Ok(match scales {
            Some(s) => OpwArm {
                geom: arm.geom.scaled(s),
                ..*arm
            },
            None => *arm,
        })
    }

    /// Flange (tool0) pose in the base frame.
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        match &self.opw {
            Ok(arm) => arm.fk(q),
            Err(_) => self.chain.fk(q),
        }
    }

    /// Flange pose of the arm with its segments scaled (base, lower arm,
    /// upper arm, wrist): a warm arm's.
    pub fn fk_scaled(&self, q: &Joints, scales: &LinkScales) -> Isometry3<f64> {
        match &self.opw {
            Ok(arm) => OpwArm {
                geom: arm.geom.scaled(scales),
                ..*arm
            }
            .fk(q),
            Err(_) => self.chain.fk_scaled(q, scales),
        }
    }

    /// The axes of `q` outside the joint limits, each with its angle and
    /// limits (rad), in axis order. Joint values are taken as the
    /// controller takes them, literally (200° on a ±180° axis is outside,
    /// though -160° is the same angle); within [`LIMIT_EPS`] of a limit is
    /// on it; a value that is not a number is outside.
    pub fn outside_limits(&self, q: &Joints) -> Vec<Violation> {
        (0..6)
            .filter_map(|j| {
                let (lo, hi) = self.limits[j];
                let inside = q[j] >= lo - LIMIT_EPS && q[j] <= hi + LIMIT_EPS;
                (!inside).then_some((j, q[j], (lo, hi)))
            })
            .collect()
    }

    /// All joint solutions (within limits, with every allowed turn of the
    /// axes) for a flange pose, each with its robconf; the arm branches
    /// outside the limits are in [`Solutions::dropped`].
    pub fn ik(&self, pose: &Isometry3<f64>) -> Result<Solutions> {
        self.solve(pose, None)
    }

    /// [`Robot::ik`] on the arm with its segments scaled.
    pub fn ik_scaled(&self, pose: &Isometry3<f64>, scales: &LinkScales) -> Result<Solutions> {
        self.solve(pose, Some(scales))
    }

    fn solve(&self, pose: &Isometry3<f64>, scales: Option<&LinkScales>) -> Result<Solutions> {
        if self.opw.is_err() {
            return self.chain_solve(pose, scales);
        }
        // Filled where it is returned from (a 4 kB buffer; see OpwArm::solve).
        let mut out = Ok(Solutions::default());
        if let Ok(sols) = &mut out {
            let failed = self.on_arm(pose, scales, |arm| {
                arm.solve_in(pose, &self.limits, None, sols).err()
            })?;
            if let Some(f) = failed {
                out = Err(self.failure(f));
            }
        }
        out
    }

    /// Every arm branch of a flange pose on the arm with its segments
    /// scaled, whatever the joint limits say: the joints (each axis within
    /// [-180°, 180°] on the OPW form) from which a caller picks the branch
    /// nearest given joints and judges the limits itself. A jointtarget
    /// needs this: its written joints name the branch, and a limit is a
    /// reason to refuse only for that branch.
    pub fn branches_scaled(
        &self,
        pose: &Isometry3<f64>,
        scales: &LinkScales,
    ) -> Result<Vec<Joints>> {
        if self.opw.is_err() {
            let sols = self.chain_solve(pose, Some(scales))?;
            return Ok(sols
                .iter()
                .map(|s| s.q)
                .chain(sols.dropped().map(|d| d.q))
                .collect());
        }
        // One turn each way: every branch's wrapped joints lie inside.
        let open = [(-PI - LIMIT_EPS, PI + LIMIT_EPS); 6];
        let sols = self
            .on_arm(pose, Some(scales), |arm| arm.solve(pose, &open, None))?
            .map_err(|f| self.failure(f))?;
        Ok(sols.iter().map(|s| s.q).collect())
    }

    /// The solution with robconf `conf` (exactly, or within
    /// [`super::ik::CONF_TOLERANCE`] of its quadrants; exactly on an arm
    /// without the OPW form, whose IK is numeric).
    pub fn ik_conf(&self, pose: &Isometry3<f64>, conf: &RobConf) -> Result<Joints> {
        self.solve_conf(pose, conf, None)
    }

    /// Whether [`Robot::ik_conf`] of the flange pose of `q` with robconf
    /// `conf` certainly gives `q` back, told without solving
    /// ([`OpwArm::picks_back`]); `false` on an arm without the OPW form,
    /// and wherever it is not certain: solve to know.
    pub fn picks_back(&self, q: &Joints, conf: &RobConf) -> bool {
        self.opw
            .as_ref()
            .is_ok_and(|arm| arm.picks_back(q, &self.limits, conf))
    }

    /// Whether `pose` is reached with robconf `conf`, told by the closed
    /// form's direct path alone (a third of [`Robot::ik`]'s cost): `true`
    /// means [`Robot::ik`] has a solution; `false` means only that this
    /// did not find one (an arm without the OPW form, the shoulder
    /// singularity, another robconf): ask [`Robot::ik`].
    pub fn reaches_with(&self, pose: &Isometry3<f64>, conf: &RobConf) -> bool {
        self.joints_with(pose, conf).is_some()
    }

    /// The joints [`Robot::reaches_with`] found: where `Some`, exactly
    /// what [`Robot::ik_conf`] gives (it takes the same direct path
    /// first).
    pub fn joints_with(&self, pose: &Isometry3<f64>, conf: &RobConf) -> Option<Joints> {
        // A cfx this family does not have: no solution has it.
        CfxBits::from_cfx(conf.cfx)?;
        self.on_arm(pose, None, |arm| {
            arm.solve_conf_direct(pose, &self.limits, conf).map(|s| s.q)
        })
        .ok()
        .flatten()
    }

    /// [`Robot::ik_conf`] on the arm with its segments scaled.
    pub fn ik_conf_scaled(
        &self,
        pose: &Isometry3<f64>,
        conf: &RobConf,
        scales: &LinkScales,
    ) -> Result<Joints> {
        self.solve_conf(pose, conf, Some(scales))
    }

    fn solve_conf(
        &self,
        pose: &Isometry3<f64>,
        conf: &RobConf,
        scales: Option<&LinkScales>,
    ) -> Result<Joints> {
        if CfxBits::from_cfx(conf.cfx).is_none() {
            return Err(Error::input(format!(
                "robconf {conf}: cfx must be 0..7 for this robot family"
            )));
        }
        if self.opw.is_err() {
            return self.chain_solve_conf(pose, conf, scales);
        }
        let direct = self.on_arm(pose, scales, |arm| {
            arm.solve_conf_direct(pose, &self.limits, conf)
        })?;
        if let Some(s) = direct {
            return Ok(s.q);
        }
        // Everything else (the shoulder singularity, errors and their list
        // of configurations) as the enumeration decides it.
        let (found, sols) = self
            .on_arm(pose, scales, |arm| {
                arm.solve_conf_by_enumeration(pose, &self.limits, conf)
            })?
            .map_err(|f| self.failure(f))?;
        match found {
            Some(s) => Ok(s.q),
            None => {
                let mut have: Vec<String> = sols.iter().map(|s| s.conf.to_string()).collect();
                have.dedup();
                Err(Error::new(
                    ErrorKind::Unreachable,
                    format!(
                        "no solution with robconf {conf} within the joint limits of the arm {}",
                        self.name
                    ),
                )
                .with_note(format!("reachable configurations: {}", have.join(" ")))
                .with_remedy(Remedy::AnotherArm))
            }
        }
    }

    /// The OPW arm as the robot holds it.
    fn opw_ref(&self) -> Result<&OpwArm> {
        self.opw.as_ref().map_err(|why| {
            Error::new(
                ErrorKind::Unsupported,
                format!(
                    "{}: closed-form IK needs an arm with an offset shoulder and a spherical wrist: {why}",
                    self.name
                ),
            )
        })
    }

    /// `f` of the OPW arm (its segments scaled by `scales`), after
    /// refusing non-finite input: the arm lent, not copied (a million
    /// targets' solves copied its 192 bytes twice each), a scaled one
    /// made where it is used.
    fn on_arm<T>(
        &self,
        pose: &Isometry3<f64>,
        scales: Option<&LinkScales>,
        f: impl FnOnce(&OpwArm) -> T,
    ) -> Result<T> {
        let finite = pose.translation.vector.iter().all(|v| v.is_finite())
            && pose.rotation.coords.iter().all(|v| v.is_finite());
        if !finite {
            return Err(Error::input("pose is not finite"));
        }
        if let Some(s) = scales {
            if !s.iter().all(|v| v.is_finite()) {
                return Err(Error::input("motor temperatures are not finite"));
            }
        }
        let arm = self.opw_ref()?;
        Ok(match scales {
            Some(s) => f(&OpwArm {
                geom: arm.geom.scaled(s),
                ..*arm
            }),
            None => f(arm),
        })
    }

    /// Out of reach, `how` said (`the arm reaches …` naming this arm),
    /// with the remedy of another arm's program.
    pub(super) fn out_of_reach(&self, how: &str) -> Error {
        let how = how.replacen(
            "the arm reaches",
            &format!("the arm {} reaches", self.name),
            1,
        );
        Error::new(ErrorKind::Unreachable, format!("out of reach: {how}"))
            .with_remedy(Remedy::AnotherArm)
    }

    pub(super) fn failure(&self, f: IkFailure) -> Error {
        match f {
            IkFailure::OutOfReach(r) if !(r.front.is_finite() && r.back.is_finite()) => self
                .out_of_reach(&format!(
                    "the wrist centre is too far to measure (a coordinate of astronomic size?); the arm reaches {:.3} to {:.3} mm",
                    r.min, r.max
                )),
            IkFailure::OutOfReach(r) => self.out_of_reach(&format!(
                "the wrist centre is {:.3} mm from axis 2 facing it, {:.3} mm over the back; the arm reaches {:.3} to {:.3} mm",
                r.front, r.back, r.min, r.max
            )),
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
                    format!("every solution violates a joint limit of the arm {}", self.name),
                )
                .with_note(list.join("; "))
                .with_remedy(Remedy::AnotherArm)
            }
        }
    }

    /// Joint angles that put `tool` at the robtarget pose `target` in
    /// `wobj`, with robconf `conf`.
    pub fn target_joints(
        &self,
        target: &Isometry3<f64>,
        conf: &RobConf,
        tool: &ToolFrame,
        wobj: &WobjFrames,
    ) -> Result<Joints> {
        let flange = flange_of_target(target, tool, wobj)?;
        self.ik_conf(&flange, conf)
    }

    /// The robtarget pose (in `wobj`, for `tool`) that joint angles reach.
    pub fn target_of_joints(
        &self,
        q: &Joints,
        tool: &ToolFrame,
        wobj: &WobjFrames,
    ) -> Result<Isometry3<f64>> {
        target_of_flange(&self.fk(q), tool, wobj)
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
        conf_of_axes(q, &self.chain.axes(q))
    }
}

/// A joint outside its limits in words: `axis 1 at 200° is outside its
/// limits [-180°, 180°]` (degrees to 0.001°, trailing zeros dropped).
pub fn describe_violation(v: &Violation) -> String {
    let (axis, q, (lo, hi)) = *v;
    format!(
        "axis {} at {}° is outside its limits [{}°, {}°]",
        axis + 1,
        degrees_text(q),
        degrees_text(lo),
        degrees_text(hi)
    )
}

/// An angle (rad) in degrees to 0.001°, without trailing zeros: the
/// way the messages about joints write an angle.
pub fn degrees_text(rad: f64) -> String {
    let s = format!("{:.3}", rad.to_degrees());
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}
