//! The arm's kinematic chain written out joint by joint, so that every
//! departure the diagnosis considers (length errors, joint offsets, bent
//! links, a moved base, a tilted measuring frame) has a place in it.
//!
//! With no perturbation it is exactly [`Opw::fk`] (tested below):
//! `B · Rz(q1) · T(a1, b, c1) · Ry(q2) · T(0,0,c2) · [bend lower] ·
//! Ry(q3 + π/2) · T(a2, 0, c3) · [bend upper] · Rz(q4) · Ry(q5) · Rz(q6) ·
//! T(0,0,c4)`.

use crate::robot::{Joints, Opw, OPW_OFFSET_Q3};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// A departure from the nominal chain. Lengths in mm, angles in radians,
/// curvatures in 1/mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Perturbation {
    /// Added to c1, a1, c2, c3, c4, a2, b.
    pub dlen: [f64; 7],
    /// Added to the joint angles.
    pub dq: Joints,
    /// Uniform curvature of the lower arm in its plane of motion.
    pub kappa_lower: f64,
    /// Uniform curvature of the upper arm in its plane of motion.
    pub kappa_upper: f64,
    /// Where the robot's base really is, in the nominal base frame.
    pub base: Isometry3<f64>,
    /// Transform from the robot base frame to the frame the positions are
    /// measured in (a tracker not exactly aligned).
    pub frame: Isometry3<f64>,
    /// A small error of each joint's origin, right after its rotation
    /// (`None`: none, the common case, which skips six products per pose).
    pub origin: Option<[Isometry3<f64>; 6]>,
    /// The measured point in the flange frame, mm.
    pub point: Vector3<f64>,
}

impl Default for Perturbation {
    fn default() -> Self {
        Perturbation {
            dlen: [0.0; 7],
            dq: [0.0; 6],
            kappa_lower: 0.0,
            kappa_upper: 0.0,
            base: Isometry3::identity(),
            frame: Isometry3::identity(),
            origin: None,
            point: Vector3::zeros(),
        }
    }
}

fn rz(a: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), a)
}

fn ry(a: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), a)
}

/// A link of length `len` along local z, bent by curvature `kappa` about
/// local y: the tip moves κL²/2 along x and turns by κL.
fn link(len: f64, kappa: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(kappa * len * len / 2.0, 0.0, len),
        ry(kappa * len),
    )
}

/// Flange pose of the perturbed chain, in the measuring frame.
pub fn fk_chain(opw: &Opw, q: &Joints, p: &Perturbation) -> Isometry3<f64> {
    let c1 = opw.c1 + p.dlen[0];
    let a1 = opw.a1 + p.dlen[1];
    let c2 = opw.c2 + p.dlen[2];
    let c3 = opw.c3 + p.dlen[3];
    let c4 = opw.c4 + p.dlen[4];
    let iso = |r: UnitQuaternion<f64>| Isometry3::from_parts(Translation3::identity(), r);
    let flange = Isometry3::translation(p.point.x, p.point.y, c4 + p.point.z);
    let (shoulder, lower, upper, wrist) = match &p.origin {
        None => (
            iso(rz(q[0] + p.dq[0])) * Isometry3::translation(a1, opw.b + p.dlen[6], c1),
            iso(ry(q[1] + p.dq[1])) * link(c2, p.kappa_lower),
            iso(ry(q[2] + OPW_OFFSET_Q3 + p.dq[2]))
                * Isometry3::translation(opw.a2 + p.dlen[5], 0.0, 0.0)
                * link(c3, p.kappa_upper),
            iso(rz(q[3] + p.dq[3]) * ry(q[4] + p.dq[4]) * rz(q[5] + p.dq[5])) * flange,
        ),
        Some(o) => (
            iso(rz(q[0] + p.dq[0])) * o[0] * Isometry3::translation(a1, opw.b + p.dlen[6], c1),
            iso(ry(q[1] + p.dq[1])) * o[1] * link(c2, p.kappa_lower),
            iso(ry(q[2] + OPW_OFFSET_Q3 + p.dq[2]))
                * o[2]
                * Isometry3::translation(opw.a2 + p.dlen[5], 0.0, 0.0)
                * link(c3, p.kappa_upper),
            iso(rz(q[3] + p.dq[3]))
                * o[3]
                * iso(ry(q[4] + p.dq[4]))
                * o[4]
                * iso(rz(q[5] + p.dq[5]))
                * o[5]
                * flange,
        ),
    };
    p.frame * p.base * shoulder * lower * upper * wrist
}

/// Rotation vector (axis × angle, radians) of `a⁻¹·b`: the small rotation
/// that takes orientation `a` to `b`, expressed in `a`'s frame.
pub fn rotation_gap(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> Vector3<f64> {
    (a.inverse() * b).scaled_axis()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::irb140_opw;
    use approx::assert_relative_eq;

    #[test]
    fn unperturbed_chain_is_opw_fk() {
        let qs = [
            [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [0.5, -0.3, 0.7, 1.1, -0.9, 2.0],
            [-2.5, 1.2, -3.0, -2.0, 1.5, -5.0],
            [30f64, 20.0, -40.0, 50.0, 60.0, 70.0].map(f64::to_radians),
        ];
        let opw = Opw {
            a2: 12.0,
            b: 5.0,
            ..irb140_opw()
        };
        for robot in [irb140_opw(), opw] {
            for q in &qs {
                let a = robot.fk(q);
                let b = fk_chain(&robot, q, &Perturbation::default());
                assert_relative_eq!(a.translation.vector, b.translation.vector, epsilon = 1e-9);
                assert!(a.rotation.angle_to(&b.rotation) < 1e-12);
            }
        }
    }

    #[test]
    fn bending_moves_tip_by_half_kappa_l_squared() {
        // Calibration pose: lower arm vertical, bending about y pushes the
        // elbow forward (+x) by κ·c2²/2 and turns everything after by κ·c2.
        let kappa = 1e-6;
        let p = Perturbation {
            kappa_lower: kappa,
            ..Default::default()
        };
        let q = [0.0; 6];
        let bent = fk_chain(&irb140_opw(), &q, &p);
        let nominal = irb140_opw().fk(&q);
        let turn = kappa * 360.0;
        // Everything beyond the elbow (380 + 65 along x) rotates by κL.
        let expect_x = kappa * 360.0 * 360.0 / 2.0;
        let expect_z = -turn * 445.0;
        let d = bent.translation.vector - nominal.translation.vector;
        // Second-order terms (445·(1 − cos κL) ≈ 3e-5 mm) aside.
        assert_relative_eq!(d.x, expect_x, epsilon = 1e-4);
        assert_relative_eq!(d.z, expect_z, epsilon = 1e-4);
        assert_relative_eq!(
            bent.rotation.angle_to(&nominal.rotation),
            turn,
            epsilon = 1e-12
        );
    }
}
