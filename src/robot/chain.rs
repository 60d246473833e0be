//! Any serial six-axis chain: fixed transforms and revolute joint axes
//! (forward kinematics for every arm a URDF can describe), link lengths
//! scaled by link temperature, and extraction of the OPW parameters for
//! the arms that have that shape.
//!
//! Thermal mapping for a general chain: each joint's origin translation
//! belongs to the link it is fixed in (its parent). Origins of joints 1 and
//! 2 are in the base (c1, a1), joint 3's in the lower arm (c2), joints 4
//! and 5's in the upper arm (c3, a2), joint 6's and the flange's (tool0) in
//! the wrist (c4). For the IRB 140 this is exactly the OPW expansion.

use super::conf::{CfxBits, RobConf};
use super::ik::{serial_angles, wrap, OpwArm};
use super::{Joints, Opw};
use nalgebra::{Isometry3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};
use std::f64::consts::FRAC_PI_2;

/// Which link's temperature scales a joint origin's translation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Segment {
    Base,
    LowerArm,
    UpperArm,
    Wrist,
}

impl Segment {
    /// The segment of joint `i` (0-based) origin.
    pub fn of_joint(i: usize) -> Segment {
        match i {
            0 | 1 => Segment::Base,
            2 => Segment::LowerArm,
            3 | 4 => Segment::UpperArm,
            _ => Segment::Wrist,
        }
    }

    /// Position in the four link factors (base, lower arm, upper arm,
    /// wrist).
    pub fn index(self) -> usize {
        self as usize
    }
}

/// One revolute joint: its frame relative to the previous joint's frame at
/// q = 0 (mm), and its axis in its own frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainJoint {
    pub name: String,
    pub origin: Isometry3<f64>,
    pub axis: Unit<Vector3<f64>>,
}

/// A mass the arm carries (a URDF link's inertial): on which joint, and
/// where its centre of mass is in that joint's frame after its rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkMass {
    /// 0-based joint whose rotation moves it.
    pub joint: usize,
    pub mass_kg: f64,
    /// mm.
    pub com: Vector3<f64>,
}

/// A joint axis in the base frame: a point on it and its direction.
pub type Axis = (Vector3<f64>, Vector3<f64>);

/// A serial chain of six revolute joints from the base frame to the flange.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    pub joints: [ChainJoint; 6],
    /// Flange (tool0) in the last joint's frame.
    pub tip: Isometry3<f64>,
    /// How the controller reads axis 3 ([`super::ik::serial_angles`]): 0
    /// for a serial arm (every URDF), −1 for a parallel-arm robot whose
    /// axis 3 is measured against the horizontal. The joint angles this
    /// chain takes are the controller's.
    pub coupling: f64,
    /// The moving links' masses, where the URDF gives inertials (empty
    /// otherwise): what gravity twists the joints with.
    pub masses: Vec<LinkMass>,
}

fn scaled(iso: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::from(iso.translation.vector * s), iso.rotation)
}

impl Chain {
    /// The chain of an ABB arm given by its OPW lengths, joint by joint as
    /// the IRB 140's URDF writes it: axis 1 up through the base origin,
    /// axis 2 at (a1, b, c1), axis 3 c2 above it, axis 4 along the upper
    /// arm −a2 above axis 3, axis 5 c3 along it, the flange c4 beyond on
    /// axis 6, tool0 with z out of the flange. Each offset sits in the
    /// link whose temperature scales it ([`Segment`]), so the warm chain
    /// is [`Opw::scaled`]'s arm. `coupling` as [`Chain::coupling`].
    pub fn from_opw(geom: &Opw, coupling: f64) -> Chain {
        let joint = |name: &str, x: f64, y: f64, z: f64, axis: Unit<Vector3<f64>>| ChainJoint {
            name: name.to_string(),
            origin: Isometry3::translation(x, y, z),
            axis,
        };
        let (ex, ey, ez) = (Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis());
        Chain {
            joints: [
                joint("joint_1", 0.0, 0.0, 0.0, ez),
                joint("joint_2", geom.a1, geom.b, geom.c1, ey),
                joint("joint_3", 0.0, 0.0, geom.c2, ey),
                joint("joint_4", 0.0, 0.0, -geom.a2, ex),
                joint("joint_5", geom.c3, 0.0, 0.0, ey),
                joint("joint_6", geom.c4, 0.0, 0.0, ex),
            ],
            tip: Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&ey, FRAC_PI_2),
            ),
            coupling,
            masses: Vec::new(),
        }
    }

    /// Flange pose in the base frame.
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        self.fk_scaled(q, &[1.0; 4])
    }

    /// Flange pose with each segment's translations scaled (base, lower
    /// arm, upper arm, wrist).
    pub fn fk_scaled(&self, q: &Joints, scale: &[f64; 4]) -> Isometry3<f64> {
        self.walk(q, scale, |_, _| {})
    }

    /// Frames of the six joints (before their own rotation) and of the
    /// flange at `q`, each segment's translations scaled: one pass for
    /// the pose and its Jacobian (the numeric IK's step).
    pub fn frames_scaled(
        &self,
        q: &Joints,
        scale: &[f64; 4],
    ) -> ([Isometry3<f64>; 6], Isometry3<f64>) {
        let mut out = [Isometry3::identity(); 6];
        let flange = self.walk(q, scale, |i, t| out[i] = *t);
        (out, flange)
    }

    /// The flange pose, showing `frame` each joint's frame on the way
    /// (FK, which shows nothing, pays nothing for it).
    #[inline]
    fn walk(
        &self,
        q: &Joints,
        scale: &[f64; 4],
        mut frame: impl FnMut(usize, &Isometry3<f64>),
    ) -> Isometry3<f64> {
        let q = serial_angles(q, self.coupling);
        let mut t = Isometry3::identity();
        for (i, j) in self.joints.iter().enumerate() {
            t *= scaled(&j.origin, scale[Segment::of_joint(i).index()]);
            frame(i, &t);
            t *= UnitQuaternion::from_axis_angle(&j.axis, q[i]);
        }
        t * scaled(&self.tip, scale[Segment::Wrist.index()])
    }

    /// Frames of the six joints (before their own rotation) at `q`.
    pub fn joint_frames(&self, q: &Joints) -> [Isometry3<f64>; 6] {
        self.frames_scaled(q, &[1.0; 4]).0
    }

    /// Point on and direction of each joint axis in the base frame at `q`.
    pub fn axes(&self, q: &Joints) -> [Axis; 6] {
        self.axes_scaled(q, &[1.0; 4]).0
    }

    /// [`Chain::axes`] of the chain with its segments scaled, and its
    /// flange pose.
    pub fn axes_scaled(&self, q: &Joints, scale: &[f64; 4]) -> ([Axis; 6], Isometry3<f64>) {
        let (f, flange) = self.frames_scaled(q, scale);
        let axes = std::array::from_fn(|i| {
            (
                f[i].translation.vector,
                f[i].rotation * self.joints[i].axis.into_inner(),
            )
        });
        (axes, flange)
    }

    /// The OPW parameters, joint signs and offsets of this chain, or what
    /// keeps it from having that shape (axis 1 vertical through the base
    /// origin; axes 2 and 3 parallel and horizontal; axes 4, 5, 6 meeting
    /// in one point; tool0 on axis 6). The result is verified against this
    /// chain's own forward kinematics.
    pub fn extract_opw(&self) -> Result<OpwArm, String> {
        const ANG: f64 = 1e-9;
        const POS: f64 = 1e-6;
        let ez = Vector3::z();
        let ax = self.axes(&[0.0; 6]);
        let (p1, d1) = ax[0];
        let (p2, d2) = ax[1];
        let (p3, d3) = ax[2];
        let (p4, d4) = ax[3];
        let (p5, d5) = ax[4];
        let (p6, d6) = ax[5];
        if d1.cross(&ez).norm() > ANG || p1.xy().norm() > POS {
            return Err("axis 1 is not the vertical (z) axis through the base origin".into());
        }
        let s1 = d1.z.signum();
        if d2.z.abs() > ANG {
            return Err("axis 2 is not perpendicular to axis 1".into());
        }
        if d3.cross(&d2).norm() > ANG {
            return Err("axes 2 and 3 are not parallel".into());
        }
        let w = intersect(p4, d4, p5, d5)
            .filter(|w| dist_to_line(w, p6, d6) < POS)
            .ok_or("axes 4, 5 and 6 do not meet in one point (no spherical wrist)")?;
        // Forward direction: axis 2 is OPW's +y after axis 1 turned.
        let mut y = d2;
        let a1_plus = p2.dot(&y.cross(&ez));
        let w_plus = w.dot(&y.cross(&ez));
        if a1_plus < -POS || (a1_plus.abs() <= POS && w_plus < -POS) {
            y = -y;
        }
        let f = y.cross(&ez);
        let s2 = d2.dot(&y).signum();
        let s3 = d3.dot(&y).signum();
        let o1 = f.y.atan2(f.x);
        let c1 = p2.z;
        let a1 = p2.dot(&f);
        let b = w.dot(&y);
        let v = p3 - p2;
        let (vx, vz) = (v.dot(&f), v.z);
        let c2 = vx.hypot(vz);
        let o2 = vx.atan2(vz);
        let u = w - p3;
        if d4.dot(&y).abs() > ANG {
            return Err("axis 4 is not perpendicular to axes 2 and 3".into());
        }
        let e4 = if d4.dot(&u) >= 0.0 { d4 } else { -d4 };
        let s4 = d4.dot(&e4).signum();
        let (ex, ez4) = (e4.dot(&f), e4.z);
        let phi = ex.atan2(ez4);
        let o3 = phi - o2;
        let (ux, uz) = (u.dot(&f), u.z);
        let c3 = ux * ex + uz * ez4;
        let a2 = ux * ez4 - uz * ex;
        let r03 = Rotation3::from_axis_angle(&Vector3::z_axis(), o1)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), phi);
        let d5l = r03.inverse() * d5;
        if d5l.z.abs() > ANG {
            return Err("axis 5 is not perpendicular to axis 4".into());
        }
        let (mut s5, mut o4) = (1.0, (-d5l.x).atan2(d5l.y));
        if o4.abs() > FRAC_PI_2 + ANG {
            s5 = -1.0;
            o4 = d5l.x.atan2(-d5l.y);
        }
        let r04 = r03 * Rotation3::from_axis_angle(&Vector3::z_axis(), o4);
        let d6l = r04.inverse() * d6;
        if d6l.y.abs() > ANG {
            return Err("axis 6 is not perpendicular to axis 5".into());
        }
        let (mut s6, mut o5) = (1.0, d6l.x.atan2(d6l.z));
        if o5.abs() > FRAC_PI_2 + ANG {
            s6 = -1.0;
            o5 = (-d6l.x).atan2(-d6l.z);
        }
        let r06 = r04 * Rotation3::from_axis_angle(&Vector3::y_axis(), o5);
        let e6 = r06 * Vector3::z();
        let tool = self.fk(&[0.0; 6]);
        let vt = tool.translation.vector - w;
        let c4 = vt.dot(&e6);
        if (vt - c4 * e6).norm() > POS {
            return Err("the flange (tool0) is not on axis 6".into());
        }
        let tip = UnitQuaternion::from_rotation_matrix(&r06).inverse() * tool.rotation;
        let arm = OpwArm {
            geom: Opw {
                c1,
                a1,
                c2,
                c3,
                c4,
                a2,
                b,
            },
            signs: [s1, s2, s3, s4, s5, s6],
            offsets: [o1, o2, o3, o4, o5, 0.0].map(clean_angle),
            coupling: self.coupling,
            tip,
        };
        // Whatever the shape tests missed shows up here.
        for q in VERIFY_POSES {
            let q = q.map(f64::to_radians);
            let (a, b) = (self.fk(&q), arm.fk(&q));
            let dp = (a.translation.vector - b.translation.vector).norm();
            let dr = a.rotation.angle_to(&b.rotation);
            if dp > POS || dr > ANG * 10.0 {
                return Err(format!(
                    "the chain has the OPW features but its kinematics differ from the OPW model by {dp:.3e} mm / {dr:.3e} rad"
                ));
            }
        }
        Ok(arm)
    }
}

const VERIFY_POSES: [[f64; 6]; 4] = [
    [10.0, 20.0, 30.0, 40.0, 50.0, 60.0],
    [-100.0, -35.0, 70.0, -150.0, -80.0, 200.0],
    [170.0, 80.0, -120.0, 10.0, 5.0, -300.0],
    [-45.0, 5.0, -200.0, 95.0, -110.0, 15.0],
];

/// Snap angles within rounding of a multiple of 90° onto it (offsets read
/// from a URDF's rpy and atan2 carry 1e-16 noise).
fn clean_angle(a: f64) -> f64 {
    let q = (a / FRAC_PI_2).round();
    if (a - q * FRAC_PI_2).abs() < 1e-12 {
        wrap(q * FRAC_PI_2)
    } else {
        a
    }
}

fn dist_to_line(x: &Vector3<f64>, p: Vector3<f64>, d: Vector3<f64>) -> f64 {
    (x - p).cross(&d).norm() / d.norm()
}

/// The common point of two lines, if they meet (within 1e-6 mm).
fn intersect(
    p: Vector3<f64>,
    d: Vector3<f64>,
    q: Vector3<f64>,
    e: Vector3<f64>,
) -> Option<Vector3<f64>> {
    let n = d.cross(&e);
    let nn = n.norm_squared();
    if nn < 1e-18 {
        return None;
    }
    let r = q - p;
    let t = r.cross(&e).dot(&n) / nn;
    let s = r.cross(&d).dot(&n) / nn;
    let a = p + d * t;
    let b = q + e * s;
    ((a - b).norm() < 1e-6).then_some(0.5 * (a + b))
}

/// robconf of an arm without the OPW form from joint angles and its axes
/// there ([`Chain::axes`]): the wrist centre is the joint-5 origin, the
/// arm faces axis 2 × axis 1 (as on the IRB 140), the lower arm runs from
/// axis 2 to axis 3.
pub(super) fn conf_of_axes(q: &Joints, ax: &[Axis; 6]) -> RobConf {
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
