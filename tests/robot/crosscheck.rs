//! Independent cross-check: rs-opw-kinematics (not written here) with the
//! IRB 140's OPW parameters in its own conventions (θ = q·sign − offset,
//! so offset3 = −90°), and property tests of robconf.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use proptest::prelude::*;
use rapidtherm::robot::ik::wrap;
use rapidtherm::robot::{irb140_opw, Joints, Robot};
use rs_opw_kinematics::glam::{DQuat, DVec3};
use rs_opw_kinematics::kinematic_traits::{Kinematics, Pose};
use rs_opw_kinematics::kinematics_impl::OPWKinematics;
use rs_opw_kinematics::parameters::opw_kinematics::Parameters;

fn reference() -> OPWKinematics {
    let irb140 = irb140_opw();
    OPWKinematics::new(Parameters {
        a1: irb140.a1,
        a2: irb140.a2,
        b: irb140.b,
        c1: irb140.c1,
        c2: irb140.c2,
        c3: irb140.c3,
        c4: irb140.c4,
        offsets: [0.0, 0.0, -std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0],
        sign_corrections: [1; 6],
        dof: 6,
    })
}

fn to_ref(p: &Isometry3<f64>) -> Pose {
    let t = p.translation.vector;
    let q = p.rotation.quaternion();
    Pose::from_parts(
        DVec3::new(t.x, t.y, t.z),
        DQuat::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

fn from_ref(p: &Pose) -> Isometry3<f64> {
    let (t, r) = (p.translation, p.rotation);
    Isometry3::from_parts(
        Translation3::new(t.x, t.y, t.z),
        UnitQuaternion::from_quaternion(Quaternion::new(r.w, r.x, r.y, r.z)),
    )
}

use crate::rng::Rng;

#[test]
fn forward_kinematics_agrees_with_rs_opw_kinematics() {
    let robot = Robot::irb140();
    let reference = reference();
    let mut rng = Rng(11);
    let mut worst: (f64, f64) = (0.0, 0.0);
    for _ in 0..10_000 {
        let q: Joints =
            std::array::from_fn(|_| (rng.next() * 2.0 - 1.0) * 2.0 * std::f64::consts::PI);
        let ours = robot.fk(&q);
        let theirs = from_ref(&reference.forward(&q));
        let dp = (ours.translation.vector - theirs.translation.vector).norm();
        let dr = ours.rotation.angle_to(&theirs.rotation);
        worst = (worst.0.max(dp), worst.1.max(dr));
    }
    assert!(worst.0 < 1e-9, "position {} mm", worst.0);
    assert!(worst.1 < 1e-12, "rotation {} rad", worst.1);
}

#[test]
fn ik_solution_sets_agree_with_rs_opw_kinematics() {
    let mut robot = Robot::irb140();
    // One turn of every axis: the eight OPW branches, no ±360° variants.
    robot.limits = [(-std::f64::consts::PI, std::f64::consts::PI); 6];
    let arm = robot.opw.clone().unwrap();
    let reference = reference();
    let mut rng = Rng(2024);
    let mut compared = 0;
    let mut solutions = 0;
    while compared < 10_000 {
        let q: Joints = std::array::from_fn(|_| (rng.next() * 2.0 - 1.0) * std::f64::consts::PI);
        // Keep away from the singularities, where each library makes its
        // own (documented) choice of the free angle.
        if q[4].abs() < 1e-3 || (q[4].abs() - std::f64::consts::PI).abs() < 1e-3 {
            continue;
        }
        let pose = robot.fk(&q);
        let ours = arm.solve(&pose, &robot.limits, None).unwrap();
        let theirs = reference.inverse(&to_ref(&pose));
        let same = |a: &Joints, b: &Joints| (0..6).all(|i| wrap(a[i] - b[i]).abs() < 1e-7);
        for t in &theirs {
            assert!(
                ours.iter().any(|s| same(&s.q, t)),
                "theirs {t:?} not in ours {ours:?}"
            );
        }
        for s in &ours {
            assert!(
                theirs.iter().any(|t| same(&s.q, t)),
                "ours {:?} not in theirs {theirs:?}",
                s.q
            );
        }
        solutions += ours.len();
        compared += 1;
    }
    // Reachable random poses of this arm have 4 or 8 solutions.
    assert!(solutions >= 4 * compared);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The robconf of taught joints picks those joints back from the pose.
    #[test]
    fn robconf_of_fk_picks_back_q(
        q1 in -179.0f64..179.0, q2 in -89.0f64..109.0, q3 in -229.0f64..49.0,
        q4 in -199.0f64..199.0, q5 in -114.0f64..114.0, q6 in -399.0f64..399.0,
    ) {
        let q = [q1, q2, q3, q4, q5, q6].map(f64::to_radians);
        // Away from singularities and quadrant boundaries (where the
        // robconf itself is ambiguous within rounding).
        let near = |a: f64| { let r = a / 90.0; (r - r.round()).abs() < 1e-6 };
        prop_assume!(q5.abs() > 0.1 && !near(q1) && !near(q4) && !near(q6));
        let robot = Robot::irb140();
        let pose = robot.fk(&q);
        let w = pose * nalgebra::Point3::new(0.0, 0.0, -65.0);
        prop_assume!(w.x.hypot(w.y) > 1.0);
        let conf = robot.conf_of(&q);
        let back = robot.ik_conf(&pose, &conf).unwrap();
        for i in 0..6 {
            prop_assert!((back[i] - q[i]).abs() < 1e-8, "{:?} -> {:?}", q, back);
        }
    }
}
