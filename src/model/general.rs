//! The perturbed chain of any serial arm read from a URDF
//! ([`crate::robot::chain::Chain`]): the same effects as the OPW arm's
//! chain ([`super::chain::fk_chain`]), placed on the joints of a chain that
//! need not have the OPW shape.
//!
//! - Thermal expansion scales every joint origin's translation by its
//!   link's factor ([`Segment::of_joint`]), the tool flange by the wrist's.
//! - Joint offsets are added to the chain's joint angles.
//! - An error of each joint's origin sits right after the joint's rotation,
//!   the measured point after the flange.
//! - Bending: the lower arm runs from axis 2 to axis 3's origin, the upper
//!   arm from axis 3 to the wrist point (axis 5's origin with axis 4 at
//!   zero). A uniform curvature κ about the link's own joint axis (its plane
//!   of motion) moves the link's end sideways by κL²/2 and turns everything
//!   beyond it by κL about that end, L being the link's length across the
//!   axis.
//! - Gravity sag, with gravity along −z of the base frame (a floor-mounted
//!   robot), in the nominal arm. Where the URDF gives the links' masses,
//!   axes 2 and 3 twist by a compliance times their gravity torque, the
//!   torque over that of all the masses beyond the axis held at the arm's
//!   length horizontally (so the parameter is the twist at that torque);
//!   the second parameter has no place then. Otherwise a proxy: the
//!   levers of the lower arm's end about axis 2 and of the wrist point
//!   about axes 2 and 3, each over its link's length, as on the OPW arm.
//!
//! On the IRB 140's chain this is exactly the OPW chain for every effect
//! but the geometric calibration's (whose joint-origin errors are written
//! in each chain's own joint frames), which `tests` below checks.

use super::chain::Perturbation;
use crate::robot::chain::{Chain, Segment};
use crate::robot::ik::serial_angles;
use crate::robot::{Joints, LinkScales};
use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

/// The link vector of the lower arm (in axis 2's frame) and of the upper
/// arm (in axis 3's frame) with each segment scaled, and the joint axis
/// each bends about.
fn links(chain: &Chain, scales: &LinkScales) -> [(Vector3<f64>, Unit<Vector3<f64>>); 2] {
    let j = &chain.joints;
    let lower = j[2].origin.translation.vector * scales[Segment::LowerArm.index()];
    let su = scales[Segment::UpperArm.index()];
    let upper = j[3].origin.translation.vector * su
        + j[3].origin.rotation * j[4].origin.translation.vector * su;
    [(lower, j[1].axis), (upper, j[2].axis)]
}

/// The part of `v` across the axis `a`.
fn across(v: &Vector3<f64>, a: &Unit<Vector3<f64>>) -> Vector3<f64> {
    v - a.into_inner() * v.dot(a)
}

/// Lengths of the lower and upper arm across their joint axes, mm (the L
/// of the bending and of the sag's levers).
pub fn link_lengths(chain: &Chain) -> [f64; 2] {
    links(chain, &[1.0; 4]).map(|(v, a)| across(&v, &a).norm())
}

/// A link from its joint's frame to `v`, bent by curvature `kappa` about
/// the joint axis `a`: everything beyond the link is turned by κL about
/// its end, and the end is moved by κL²/2 across the link.
fn bend(v: &Vector3<f64>, a: &Unit<Vector3<f64>>, kappa: f64) -> Isometry3<f64> {
    let w = across(v, a);
    let l = w.norm();
    if kappa == 0.0 || l <= 0.0 {
        return Isometry3::identity();
    }
    let side = a.cross(&(w / l)) * (kappa * l * l / 2.0);
    Isometry3::from_parts(
        Translation3::from(v + side),
        UnitQuaternion::from_axis_angle(a, kappa * l),
    ) * Translation3::from(-v)
}

fn scaled(iso: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::from(iso.translation.vector * s), iso.rotation)
}

/// Pose of the measured point (position) and of tool0 (orientation) of the
/// perturbed chain, in the measuring frame. `p.dlen` (the OPW lengths) has
/// no place on a general chain and is ignored: its joint origins take
/// that role.
pub fn fk_general(
    chain: &Chain,
    scales: &LinkScales,
    q: &Joints,
    p: &Perturbation,
) -> Isometry3<f64> {
    let qs = serial_angles(q, chain.coupling);
    let [(lower, a_lower), (upper, a_upper)] = links(chain, scales);
    let mut t = p.frame * p.base;
    for (i, j) in chain.joints.iter().enumerate() {
        let s = scales[Segment::of_joint(i).index()];
        t = t * scaled(&j.origin, s) * UnitQuaternion::from_axis_angle(&j.axis, qs[i] + p.dq[i]);
        if let Some(o) = &p.origin {
            t *= o[i];
        }
        match i {
            1 => t *= bend(&lower, &a_lower, p.kappa_lower),
            2 => t *= bend(&upper, &a_upper, p.kappa_upper),
            _ => {}
        }
    }
    t * scaled(&chain.tip, scales[Segment::Wrist.index()]) * Translation3::from(p.point)
}

/// Gravity levers of the nominal arm at `q`, multiplying the three
/// parameters of `gravity-sag` (axis 2, axis 2, axis 3). Without masses:
/// the lower arm's end about axis 2, the wrist point about axis 2 and
/// about axis 3, over the link lengths (on an OPW arm in ABB's convention:
/// sin q2, and cos(q2 + q3) twice). With masses: the gravity torques of
/// axes 2 and 3 over their reference torques, and zero for the second.
pub fn gravity_levers(chain: &Chain, q: &Joints) -> [f64; 3] {
    let f = chain.joint_frames(q);
    let [l_lower, l_upper] = link_lengths(chain);
    let qs = serial_angles(q, chain.coupling);
    let axis = |k: usize| f[k].rotation * chain.joints[k].axis.into_inner();
    // Torque of a unit weight at p about axis k: a · ((p − o) × −z).
    let lever = |p: &Vector3<f64>, k: usize| {
        axis(k).dot(&(p - f[k].translation.vector).cross(&-Vector3::z()))
    };
    if !chain.masses.is_empty() {
        let turned: [Isometry3<f64>; 6] = std::array::from_fn(|k| {
            f[k] * UnitQuaternion::from_axis_angle(&chain.joints[k].axis, qs[k])
        });
        let torque = |k: usize, reach: f64| {
            let (mut tau, mut mass) = (0.0, 0.0);
            for m in chain.masses.iter().filter(|m| m.joint >= k) {
                tau +=
                    m.mass_kg * lever(&(turned[m.joint] * nalgebra::Point3::from(m.com)).coords, k);
                mass += m.mass_kg;
            }
            if mass > 0.0 && reach > 0.0 {
                tau / (mass * reach)
            } else {
                0.0
            }
        };
        return [torque(1, l_lower + l_upper), 0.0, torque(2, l_upper)];
    }
    // The wrist point with axis 4 at zero, as the upper arm's length is
    // taken: axis 4 turns about the upper arm and does not move it.
    let frame3 = f[2] * UnitQuaternion::from_axis_angle(&chain.joints[2].axis, qs[2]);
    let wrist = frame3 * chain.joints[3].origin * chain.joints[4].origin;
    let (elbow, wrist) = (f[2].translation.vector, wrist.translation.vector);
    let per = |v: f64, l: f64| if l > 0.0 { v / l } else { 0.0 };
    [
        per(lever(&elbow, 1), l_lower),
        per(lever(&wrist, 1) - lever(&elbow, 1), l_upper),
        per(lever(&wrist, 2), l_upper),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::chain::fk_chain;
    use crate::robot::{irb140_opw, Robot};

    #[test]
    fn irb140_levers_are_the_opw_ones() {
        let chain = Robot::irb140().chain;
        for q in [
            [0.3, 0.4, -0.2, 1.0, 0.5, 0.1],
            [-1.2, -0.7, 0.9, -2.0, 1.1, 3.0],
        ] {
            let l = gravity_levers(&chain, &q);
            assert!((l[0] - q[1].sin()).abs() < 1e-12, "{l:?}");
            assert!((l[1] - (q[1] + q[2]).cos()).abs() < 1e-12, "{l:?}");
            assert!((l[2] - (q[1] + q[2]).cos()).abs() < 1e-12, "{l:?}");
        }
        let o = irb140_opw();
        assert_eq!(link_lengths(&chain), [o.c2, o.c3]);
    }

    #[test]
    fn irb140_general_chain_is_the_opw_chain() {
        let chain = Robot::irb140().chain;
        let opw = irb140_opw();
        let scales = [1.0003, 1.0002, 0.9999, 1.0004];
        let p = Perturbation {
            dq: [1e-4, -2e-4, 3e-4, 1e-3, -5e-4, 2e-4],
            kappa_lower: 3e-7,
            kappa_upper: -5e-7,
            base: Isometry3::from_parts(
                Translation3::new(0.1, -0.05, 0.2),
                UnitQuaternion::from_scaled_axis(Vector3::new(1e-4, -2e-4, 0.0)),
            ),
            frame: Isometry3::from_parts(
                Translation3::new(3.0, 1.0, -2.0),
                UnitQuaternion::from_scaled_axis(Vector3::new(1e-3, 2e-3, -1e-3)),
            ),
            ..Default::default()
        };
        for q in [
            [0.3, 0.4, -0.2, 1.0, 0.5, 0.1],
            [-1.2, -0.7, 0.9, -2.0, 1.1, 3.0],
        ] {
            let a = fk_chain(&opw.scaled(&scales), &q, &p);
            let b = fk_general(&chain, &scales, &q, &p);
            assert!((a.translation.vector - b.translation.vector).norm() < 1e-9);
            assert!(a.rotation.angle_to(&b.rotation) < 1e-12);
        }
    }
}
