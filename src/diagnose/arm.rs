//! Any OPW-shaped arm (from a URDF) in the diagnosis: its joints are mapped
//! to the angles of the perturbed chain ([`crate::model::chain::fk_chain`], written
//! in ABB's convention), so that the base model and every effect apply.
//!
//! The robot's joint `q` and the chain's `qc` relate through the arm's OPW
//! signs and offsets: θ = s·q + o (robot → OPW angle) and qc = θ − θ_abb
//! offset (θ3 = qc3 + 90°), so `qc = s·q + (o − o_abb)`, with q3 first
//! made serial on a parallel-arm robot (q3 + coupling·q2,
//! [`crate::robot::ik::serial_angles`]). The robot's tool0 is the chain's
//! flange turned by the constant rotation `tip`. On the IRB 140 the map is
//! exactly the identity.
//!
//! Joint-angle parameters of effects (joint offsets, their drift, gravity
//! sag) are in the chain's convention: on an axis whose sign is −1 the
//! robot's own joint value moves the opposite way.

use super::instrument::instrument;
use crate::error::{Error, ErrorKind, Result};
use crate::model::{Base, Geometry};
use crate::model::{JointConvention, Model, RobotSection};
use crate::robot::ik::{controller_angles, serial_angles};
use crate::robot::{Joints, Opw, Robot, OPW_OFFSET_Q3};
use nalgebra::{Isometry3, UnitQuaternion};
use std::sync::Arc;

/// Joint and flange-frame map from a robot to the diagnosis chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmMap {
    /// +1 or −1 per axis.
    pub signs: [f64; 6],
    /// rad, added after the sign: `qc = sign·q + offset`.
    pub offsets: Joints,
    /// Axis 3 read against the horizontal (−1) or the lower arm (0).
    pub coupling: f64,
    /// Robot tool0 = chain flange · tip.
    pub tip: UnitQuaternion<f64>,
}

impl Default for ArmMap {
    fn default() -> Self {
        ArmMap {
            signs: [1.0; 6],
            offsets: [0.0; 6],
            coupling: 0.0,
            tip: UnitQuaternion::identity(),
        }
    }
}

impl ArmMap {
    /// The map of `robot` and its nominal OPW geometry, or why the
    /// diagnosis cannot model it.
    pub fn of_robot(robot: &Robot) -> Result<(Opw, ArmMap)> {
        let arm = robot.opw.as_ref().map_err(|why| {
            Error::new(
                ErrorKind::Unsupported,
                format!(
                    "{}: the diagnosis models arms with an offset shoulder and a spherical wrist (OPW form); this one has none: {why}",
                    robot.name
                ),
            )
        })?;
        let abb = [0.0, 0.0, OPW_OFFSET_Q3, 0.0, 0.0, 0.0];
        Ok((
            arm.geom,
            ArmMap {
                signs: arm.signs,
                offsets: std::array::from_fn(|i| arm.offsets[i] - abb[i]),
                coupling: arm.coupling,
                tip: arm.tip,
            },
        ))
    }

    /// Chain angles of robot joints.
    pub fn to_chain(&self, q: &Joints) -> Joints {
        let s = serial_angles(q, self.coupling);
        std::array::from_fn(|i| self.signs[i] * s[i] + self.offsets[i])
    }

    /// Robot joints of chain angles (signs are ±1: their own inverse).
    pub fn from_chain(&self, qc: &Joints) -> Joints {
        let s: Joints = std::array::from_fn(|i| (qc[i] - self.offsets[i]) * self.signs[i]);
        controller_angles(&s, self.coupling)
    }

    /// The robot's tool0 pose of a chain flange pose.
    pub fn tool0(&self, flange: &Isometry3<f64>) -> Isometry3<f64> {
        let mut p = *flange;
        p.rotation *= self.tip;
        p
    }

    /// The chain flange orientation of a measured tool0 orientation.
    pub fn flange_rotation(&self, tool0: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
        tool0 * self.tip.inverse()
    }
}

/// The robot the diagnosis works on: nominal geometry, joint map, limits.
#[derive(Debug, Clone, PartialEq)]
pub struct Arm {
    pub name: String,
    pub nominal: Geometry,
    pub map: ArmMap,
    /// Degrees, inclusive.
    pub limits_deg: [(f64, f64); 6],
    /// Where the nominal geometry comes from (for the report).
    pub source: String,
    /// How a saved model names this arm again; `None` where the arm was
    /// given as a robot alone (its URDF's text unknown), and a saved model
    /// can keep only its OPW lengths.
    pub written: Option<Written>,
}

/// How a model file names an arm, so that the file stands alone.
#[derive(Debug, Clone, PartialEq)]
pub enum Written {
    /// The model's own `[robot]` (OPW lengths, or what it names).
    Model,
    /// A catalogue arm, by its name.
    Catalogue(String),
    /// A URDF's content.
    UrdfText(String),
}

impl Arm {
    /// The arm of a robot (from a URDF): its OPW lengths are the nominal
    /// geometry.
    /// An arm without that shape is its URDF chain, in the URDF's own
    /// joint convention (the map is the identity).
    pub fn of_robot(robot: &Robot, source: &str) -> Result<Arm> {
        let (nominal, map) = match robot.opw {
            Ok(_) => {
                let (geom, map) = ArmMap::of_robot(robot)?;
                (Geometry::Opw(geom), map)
            }
            Err(_) => (
                Geometry::Chain(Arc::new(robot.chain.clone())),
                ArmMap::default(),
            ),
        };
        Ok(Arm {
            name: robot.name.clone(),
            nominal,
            map,
            limits_deg: robot
                .limits
                .map(|(lo, hi)| (lo.to_degrees(), hi.to_degrees())),
            source: source.to_string(),
            written: None,
        })
    }

    /// The arm of a URDF's text (`name` names it in messages), which a
    /// saved model embeds.
    pub fn of_urdf_text(name: &str, text: &str) -> Result<Arm> {
        let robot = Robot::from_urdf_str(name, text)?;
        Ok(Arm {
            written: Some(Written::UrdfText(text.to_string())),
            ..Arm::of_robot(&robot, name)?
        })
    }

    /// A catalogue arm, which a saved model names.
    pub fn of_catalogue(arm: &crate::robot::abb::AbbArm) -> Result<Arm> {
        Ok(Arm {
            written: Some(Written::Catalogue(arm.name.clone())),
            ..Arm::of_robot(&arm.robot(), arm.file)?
        })
    }

    /// The arm of a model file: its `[robot]` OPW geometry, in ABB's
    /// convention with the IRB 140's limits, or the arm it names (a URDF,
    /// its text, a catalogue arm) with that arm's convention and limits.
    pub fn of_model(model: &Model) -> Result<Arm> {
        if let Some(named) = model.arm()? {
            let written = match (named.urdf_text, named.catalogue) {
                (Some(text), _) => Written::UrdfText(text),
                (None, Some(name)) => Written::Catalogue(name),
                (None, None) => Written::Model,
            };
            return Ok(Arm {
                written: Some(written),
                ..Arm::of_robot(&named.robot, &named.source)?
            });
        }
        let nominal = model
            .robot
            .opw
            .ok_or_else(|| Error::input("model: [robot] has no geometry"))?;
        Ok(Arm {
            name: model.robot.name.clone(),
            nominal: Geometry::Opw(nominal),
            map: ArmMap::default(),
            limits_deg: *super::measurements::IRB140_LIMITS_DEG,
            source: "model".into(),
            written: Some(Written::Model),
        })
    }

    /// The `[robot]` section of a model of this arm, fitted from `model`:
    /// the arm named so that the file needs nothing else (a URDF's text,
    /// a catalogue name, or the model's own), with its joint convention
    /// and the model's measured point.
    pub fn robot_section(&self, model: &Model) -> RobotSection {
        let convention = match self.nominal {
            Geometry::Opw(_) => JointConvention::AbbOpw,
            Geometry::Chain(_) => JointConvention::Urdf,
        };
        let empty = RobotSection {
            name: self.name.clone(),
            opw: None,
            urdf: None,
            urdf_text: None,
            catalogue: None,
            joints: Some(convention),
            point_mm: model.robot.point_mm,
        };
        match &self.written {
            Some(Written::Model) => RobotSection {
                joints: Some(convention),
                ..model.robot.clone()
            },
            Some(Written::Catalogue(name)) => RobotSection {
                catalogue: Some(name.clone()),
                ..empty
            },
            Some(Written::UrdfText(text)) => RobotSection {
                urdf_text: Some(text.clone()),
                ..empty
            },
            // Only the lengths are known: ABB's convention, the IRB 140's
            // limits on reading (a format-1 file's arm).
            None => RobotSection {
                opw: self.nominal.opw().copied(),
                joints: self.nominal.opw().map(|_| JointConvention::AbbOpw),
                ..empty
            },
        }
    }

    /// The base model: this arm's nominal geometry with the model's
    /// thermal expansion and measured point (given in tool0, turned into
    /// the chain's flange frame).
    pub fn base(&self, model: &Model) -> Base {
        Base {
            nominal: self.nominal.clone(),
            thermal: model.thermal.clone(),
            point: self.map.tip * nalgebra::Vector3::from(model.point()),
        }
    }

    /// Wrist-centre reach from axis 1, mm (a1 + c2 + the forearm), and the
    /// height of axis 2 (c1).
    fn reach_and_shoulder(&self) -> (f64, f64) {
        match &self.nominal {
            Geometry::Opw(o) => (o.a1 + o.c2 + o.a2.hypot(o.c3), o.c1),
            Geometry::Chain(c) => {
                let shoulder = c.joint_frames(&[0.0; 6])[1].translation.vector;
                let [lower, upper] = self.nominal.arm_lengths();
                (shoulder.xy().norm() + lower + upper, shoulder.z)
            }
        }
    }

    /// Wrist-centre reach from axis 1, mm.
    pub fn reach(&self) -> f64 {
        self.reach_and_shoulder().0
    }

    /// The ISO 9283 cube for this arm, scaled to its reach R by the
    /// fractions of `data/instrument.toml`: centre 0.6·R in front of axis 1
    /// and 0.12·R above the shoulder (c1), side 0.35·R. On the IRB 140
    /// (R = 810 mm) that is (486, 0, 449.2) mm and 283.5 mm.
    pub fn iso_cube(&self) -> Result<IsoCube> {
        let shape = &instrument()?.iso_cube;
        let (r, shoulder) = self.reach_and_shoulder();
        Ok(IsoCube {
            centre: [shape.forward * r, 0.0, shoulder + shape.above_shoulder * r],
            side: shape.side * r,
        })
    }
}

/// A cube in the robot base frame, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsoCube {
    pub centre: [f64; 3],
    pub side: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::chain::{fk_chain, Perturbation};

    #[test]
    fn irb140_map_is_exactly_the_identity() {
        let (geom, map) = ArmMap::of_robot(&Robot::irb140()).unwrap();
        assert_eq!(map, ArmMap::default());
        let q = [0.3, -0.2, 0.5, 1.0, -0.7, 2.0];
        assert_eq!(map.to_chain(&q), q);
        let r = Robot::irb140();
        let a = fk_chain(&geom, &q, &Perturbation::default());
        let b = r.fk(&q);
        assert!((a.translation.vector - b.translation.vector).norm() < 1e-9);
        assert!(a.rotation.angle_to(&b.rotation) < 1e-12);
    }

    #[test]
    fn non_opw_robot_is_refused_with_the_reason() {
        let mut r = Robot::irb140();
        r.opw = Err("axes 4, 5 and 6 do not meet".into());
        let e = ArmMap::of_robot(&r).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Unsupported);
        assert!(e.message.contains("do not meet"), "{}", e.message);
    }

    #[test]
    fn irb140_iso_cube_is_the_scaled_one() {
        let cube = Arm::of_model(&Model::default())
            .unwrap()
            .iso_cube()
            .unwrap();
        let expect = [486.0, 0.0, 449.2];
        for (a, b) in cube.centre.iter().zip(expect) {
            assert!((a - b).abs() < 1e-9, "{:?}", cube.centre);
        }
        assert!((cube.side - 283.5).abs() < 1e-9, "{}", cube.side);
    }
}
