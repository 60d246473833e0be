//! Reading a serial six-axis arm from a URDF (urdf-rs). Meshes, inertias
//! and collision geometry are ignored: no `package://` lookups, no ROS.
//! URDF lengths are metres; the chain is built in millimetres.

use super::chain::{Chain, ChainJoint, LinkMass};
use super::ik::Limits;
use super::urdf_scan::{self, UrdfIndex};
use crate::error::{Error, ErrorKind, Result};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use std::collections::HashMap;

/// The IRB 140 (`data/irb140/irb140.urdf`), written for this project from
/// `docs/model.md` and the ABB product specification.
pub const IRB140_URDF: &str = include_str!("../../data/irb140/irb140.urdf");

/// The bounds of a chain's length (`data/urdf_size.toml`).
pub const URDF_SIZE_TOML: &str = include_str!("../../data/urdf_size.toml");

#[derive(Debug, Clone, Copy, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Size {
    shortest_mm: f64,
    longest_mm: f64,
}

/// The embedded bounds, parsed once (a unit test parses the file, so the
/// `expect` cannot fire on a tested build).
fn size() -> Size {
    static SIZE: std::sync::OnceLock<Size> = std::sync::OnceLock::new();
    *SIZE.get_or_init(|| {
        toml::from_str(URDF_SIZE_TOML).expect("the embedded data/urdf_size.toml is valid")
    })
}

/// What a URDF gives the robot model.
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfArm {
    pub name: String,
    pub chain: Chain,
    pub limits: Limits,
    /// Joint velocity limits, °/s (0 where the URDF gives none).
    pub max_speed_deg_s: [f64; 6],
}

fn pose_of(origin: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = origin.xyz.0;
    let [r, p, yaw] = origin.rpy.0;
    Isometry3::from_parts(
        Translation3::new(x * 1000.0, y * 1000.0, z * 1000.0),
        UnitQuaternion::from_euler_angles(r, p, yaw),
    )
}

/// Read a URDF text with urdf-rs, after [`urdf_scan::scan`] has refused
/// what would overflow its stack or carry non-finite numbers.
fn read(file: &str, text: &str) -> Result<(urdf_rs::Robot, UrdfIndex)> {
    let index = urdf_scan::scan(file, text)?;
    let robot = urdf_rs::read_from_string(text)
        .map_err(|e| Error::input(format!("not a readable URDF: {e}")).at(index.link("")))?;
    Ok((robot, index))
}

/// The URDF's joints as a tree: which joint each link hangs from.
struct Tree<'r> {
    robot: &'r urdf_rs::Robot,
    parent_joint: HashMap<&'r str, usize>,
}

/// Whether a joint is one of the arm's axes.
fn movable(j: &urdf_rs::Joint) -> bool {
    matches!(
        j.joint_type,
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous
    )
}

impl<'r> Tree<'r> {
    /// The tree of `robot`'s joints, refused where a link has two parents.
    fn new(robot: &'r urdf_rs::Robot, index: &UrdfIndex) -> Result<Self> {
        let mut parent_joint: HashMap<&str, usize> = HashMap::new();
        for (i, j) in robot.joints.iter().enumerate() {
            if parent_joint.insert(j.child.link.as_str(), i).is_some() {
                return Err(bad_joint(
                    index,
                    &j.name,
                    format!(
                        "link `{}` is the child of more than one joint (not a tree)",
                        j.child.link
                    ),
                ));
            }
        }
        Ok(Tree {
            robot,
            parent_joint,
        })
    }

    /// Joints from the root down to `tip`, or None on a cycle.
    fn path_to(&self, tip: &str) -> Option<Vec<usize>> {
        let robot = self.robot;
        let mut path = Vec::new();
        let mut link = tip;
        while let Some(&i) = self.parent_joint.get(link) {
            if path.len() > robot.joints.len() {
                return None;
            }
            path.push(i);
            link = robot.joints[i].parent.link.as_str();
        }
        path.reverse();
        Some(path)
    }

    /// The flange link: `tool0`, or the one leaf reached through six
    /// revolute joints.
    fn tip_name(&self, file: &str) -> Result<String> {
        let robot = self.robot;
        if robot.links.iter().any(|l| l.name == "tool0") {
            return Ok("tool0".to_string());
        }
        let parents: Vec<&str> = robot
            .joints
            .iter()
            .map(|j| j.parent.link.as_str())
            .collect();
        let leaves: Vec<&str> = robot
            .links
            .iter()
            .map(|l| l.name.as_str())
            .filter(|l| !parents.contains(l))
            .filter(|l| {
                self.path_to(l)
                    .is_some_and(|p| p.iter().filter(|&&i| movable(&robot.joints[i])).count() == 6)
            })
            .collect();
        match leaves.as_slice() {
            [one] => Ok(one.to_string()),
            [] => Err(bad(
                file,
                "no link is reached through six revolute joints (a six-axis serial arm is needed)"
                    .into(),
            )),
            many => Err(bad(
                file,
                format!(
                    "several end links ({}); name the flange link `tool0`",
                    many.join(", ")
                ),
            )),
        }
    }

    /// Every link with a mass that one of the arm's joints moves (a branch
    /// off the arm, or the base, is not the arm's load).
    fn masses(&self, joints: &[ChainJoint; 6]) -> Vec<LinkMass> {
        let robot = self.robot;
        let mut masses = Vec::new();
        for link in &robot.links {
            let m = link.inertial.mass.value;
            if !(m.is_finite() && m > 0.0) {
                continue;
            }
            let Some(p) = self.path_to(&link.name) else {
                continue;
            };
            let Some(last) = p.iter().rposition(|&i| movable(&robot.joints[i])) else {
                continue;
            };
            let name = &robot.joints[p[last]].name;
            let Some(k) = joints.iter().position(|j| &j.name == name) else {
                continue;
            };
            let com = p[last + 1..].iter().fold(Isometry3::identity(), |t, &i| {
                t * pose_of(&robot.joints[i].origin)
            }) * pose_of(&link.inertial.origin);
            let com = com.translation.vector;
            if com.iter().all(|v| v.is_finite()) {
                masses.push(LinkMass {
                    joint: k,
                    mass_kg: m,
                    com,
                });
            }
        }
        masses
    }
}

/// An error of the file as a whole.
fn bad(file: &str, msg: String) -> Error {
    Error::input(format!("{file}: {msg}"))
}

/// An error at a joint's element.
fn bad_joint(index: &UrdfIndex, name: &str, msg: String) -> Error {
    Error::input(msg).at(index.joint(name))
}

/// The axes met on the way from the root to the flange, with the fixed
/// transforms not yet folded into an axis's origin.
struct Axes {
    joints: Vec<ChainJoint>,
    limits: Vec<(f64, f64)>,
    speeds: Vec<f64>,
    pending: Isometry3<f64>,
}

impl Axes {
    /// The axes of the joints of `path`, refused where a joint is not one
    /// the model has.
    fn along(robot: &urdf_rs::Robot, path: &[usize], index: &UrdfIndex) -> Result<Self> {
        let mut axes = Axes {
            joints: Vec::with_capacity(6),
            limits: Vec::with_capacity(6),
            speeds: Vec::with_capacity(6),
            pending: Isometry3::identity(),
        };
        for &i in path {
            axes.joint(&robot.joints[i], index)?;
        }
        Ok(axes)
    }

    /// One joint of the path: a fixed one folded into what follows, a
    /// revolute one an axis.
    fn joint(&mut self, j: &urdf_rs::Joint, index: &UrdfIndex) -> Result<()> {
        if let Some(m) = &j.mimic {
            // A joint that follows another is no axis of its own: taken
            // as one, the arm would move it freely.
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "joint `{}` mimics joint `{}` (`<mimic>`): rapidtherm models an arm of six independent axes, and a coupled joint on the arm's chain is not one",
                    j.name, m.joint
                ),
            )
            .at(index.joint(&j.name)));
        }
        match &j.joint_type {
            urdf_rs::JointType::Fixed => self.pending *= pose_of(&j.origin),
            urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                let axis = Vector3::from(j.axis.xyz.0);
                let axis = Unit::try_new(axis, 1e-12)
                    .filter(|_| axis.iter().all(|v| v.is_finite()))
                    .ok_or_else(|| {
                        bad_joint(
                            index,
                            &j.name,
                            format!("joint `{}` has a zero or invalid axis", j.name),
                        )
                    })?;
                let lim = if j.joint_type == urdf_rs::JointType::Continuous {
                    // A continuous joint turns freely; one turn each way is
                    // what the IK enumerates.
                    (-std::f64::consts::PI, std::f64::consts::PI)
                } else {
                    let (lo, hi) = (j.limit.lower, j.limit.upper);
                    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                        return Err(bad_joint(
                            index,
                            &j.name,
                            format!(
                                "revolute joint `{}` needs limits with lower < upper (got {lo} .. {hi})",
                                j.name
                            ),
                        ));
                    }
                    (lo, hi)
                };
                self.joints.push(ChainJoint {
                    name: j.name.clone(),
                    origin: self.pending * pose_of(&j.origin),
                    axis,
                });
                self.pending = Isometry3::identity();
                self.limits.push(lim);
                let v = j.limit.velocity;
                self.speeds.push(if v.is_finite() && v > 0.0 {
                    v.to_degrees()
                } else {
                    0.0
                });
            }
            other => {
                return Err(Error::new(
                    ErrorKind::Unsupported,
                    format!(
                        "joint `{}` is {}; only revolute and fixed joints are modelled",
                        j.name,
                        joint_type_name(other)
                    ),
                )
                .at(index.joint(&j.name)))
            }
        }
        Ok(())
    }
}

/// Parse a URDF text (`file` names it in messages).
pub fn parse(file: &str, text: &str) -> Result<UrdfArm> {
    let (robot, index) = read(file, text)?;
    let tree = Tree::new(&robot, &index)?;
    let tip_name = tree.tip_name(file)?;
    let path = tree
        .path_to(&tip_name)
        .ok_or_else(|| bad(file, "the joints form a cycle".into()))?;
    let Axes {
        joints,
        limits,
        speeds,
        pending,
    } = Axes::along(&robot, &path, &index)?;
    let n = joints.len();
    let joints: [ChainJoint; 6] = joints.try_into().map_err(|_| {
        bad(
            file,
            format!(
                "{n} revolute joints between the root and `{tip_name}`; a six-axis serial arm is needed"
            ),
        )
    })?;
    let finite = joints.iter().all(|j| {
        j.origin.translation.vector.iter().all(|v| v.is_finite())
            && j.origin.rotation.coords.iter().all(|v| v.is_finite())
    });
    if !finite {
        return Err(bad(file, "a joint origin is not finite".into()));
    }
    check_size(file, &joints, &pending, &index)?;
    let masses = tree.masses(&joints);
    Ok(UrdfArm {
        name: robot.name.clone(),
        chain: Chain {
            joints,
            tip: pending,
            coupling: 0.0,
            masses,
        },
        limits: std::array::from_fn(|i| limits[i]),
        max_speed_deg_s: std::array::from_fn(|i| speeds[i]),
    })
}

/// A chain as long as a six-axis arm's (`data/urdf_size.toml`): not
/// written in millimetres, not every joint at the origin.
fn check_size(
    file: &str,
    joints: &[ChainJoint; 6],
    tip: &Isometry3<f64>,
    index: &UrdfIndex,
) -> Result<()> {
    let b = size();
    let length: f64 = joints
        .iter()
        .map(|j| j.origin.translation.vector.norm())
        .sum::<f64>()
        + tip.translation.vector.norm();
    if length > b.longest_mm {
        return Err(Error::input(format!(
            "{file}: the arm's chain is {:.0} m long (its joint origins summed, base to flange): no six-axis arm is longer than {} m. Is the URDF in millimetres? URDF lengths are metres",
            length / 1000.0,
            b.longest_mm / 1000.0
        ))
        .at(index.joint(&joints[0].name)));
    }
    if length < b.shortest_mm {
        return Err(Error::input(format!(
            "{file}: the arm's chain is {length:.1} mm long (its joint origins summed, base to flange): the joints sit at or next to one point, and no six-axis arm is shorter than {} mm. Are the joints' `<origin>`s missing?",
            b.shortest_mm
        ))
        .at(index.joint(&joints[0].name)));
    }
    Ok(())
}

/// The pose of link `link` in the flange (tool0) frame of `arm`, the chain
/// `parse` read from the same `text`: the link must hang on the arm's six
/// revolute joints through fixed joints only (a reflector, a tool point).
pub fn link_in_tip(file: &str, text: &str, arm: &UrdfArm, link: &str) -> Result<Isometry3<f64>> {
    let (robot, _) = read(file, text)?;
    if !robot.links.iter().any(|l| l.name == link) {
        let names: Vec<&str> = robot.links.iter().map(|l| l.name.as_str()).collect();
        return Err(Error::input(format!(
            "{file}: no link `{link}` (links: {})",
            names.join(", ")
        )));
    }
    // Fixed joints from the link up to the last revolute joint.
    let mut after = Isometry3::identity();
    let mut at = link;
    for _ in 0..=robot.joints.len() {
        let Some(j) = robot.joints.iter().find(|j| j.child.link == at) else {
            return Err(Error::input(format!(
                "{file}: link `{link}` is not carried by the arm's last joint"
            )));
        };
        if j.name == arm.chain.joints[5].name {
            return Ok(arm.chain.tip.inverse() * after);
        }
        if j.joint_type != urdf_rs::JointType::Fixed {
            return Err(Error::input(format!(
                "{file}: link `{link}` hangs on the movable joint `{}`, not on the flange through fixed joints",
                j.name
            )));
        }
        after = pose_of(&j.origin) * after;
        at = j.parent.link.as_str();
    }
    Err(Error::input(format!("{file}: the joints form a cycle")))
}

/// A joint type as URDF writes it (never `Debug` text in a message).
fn joint_type_name(t: &urdf_rs::JointType) -> &'static str {
    match t {
        urdf_rs::JointType::Revolute => "revolute",
        urdf_rs::JointType::Continuous => "continuous",
        urdf_rs::JointType::Prismatic => "prismatic",
        urdf_rs::JointType::Fixed => "fixed",
        urdf_rs::JointType::Floating => "floating",
        urdf_rs::JointType::Planar => "planar",
        urdf_rs::JointType::Spherical => "spherical",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_size_bounds_parse_and_hold_the_irb140() {
        let b = size();
        assert_eq!((b.shortest_mm, b.longest_mm), (50.0, 20_000.0));
        // sqrt(70² + 352²) + 360 + 380 + 65 = 1163.89 mm.
        assert!(parse("irb140.urdf", IRB140_URDF).is_ok());
    }
}
