//! Numeric IK for arms without the OPW form (`src/robot/ik_chain.rs`):
//! the UR5 (`tests/data/ur5/ur5.urdf`) and an arm with an offset wrist
//! round-trip random joints through FK and robconf IK to 1e-9 mm and
//! 1e-12 rad; the IRB 140 solved numerically (its OPW form withheld)
//! gives the closed form's answers; the warm arm; the errors.

use crate::rng::Rng;
use nalgebra::{Isometry3, Matrix6, Quaternion, Translation3, UnitQuaternion};
use proptest::prelude::*;
use rapidtherm::error::ErrorKind;
use rapidtherm::robot::{Joints, LinkScales, RobConf, Robot};
use std::f64::consts::{PI, TAU};
use std::path::Path;
use std::time::Instant;

const UR5: &str = "tests/data/ur5/ur5.urdf";
const WARM: LinkScales = [1.0002, 1.0003, 0.9998, 1.0004];

fn ur5() -> Robot {
    Robot::from_urdf_file(Path::new(UR5)).expect("the UR5 URDF of tests/data/ur5")
}

/// An IRB 140-sized arm whose wrist axes do not meet: axis 5 sits 60 mm
/// beside axis 4 and the flange 90 mm beside axis 6, as on a collaborative
/// arm (ABB's GoFa has such offsets).
fn offset_wrist() -> Robot {
    let joint = |n: u8, parent: &str, child: &str, xyz: &str, axis: &str, lim: f64| {
        format!(
            r#"<joint name="joint_{n}" type="revolute"><parent link="{parent}"/><child link="{child}"/><origin xyz="{xyz}" rpy="0 0 0"/><axis xyz="{axis}"/><limit lower="-{lim}" upper="{lim}" effort="0" velocity="3"/></joint>"#
        )
    };
    let links: String = ["base_link", "l1", "l2", "l3", "l4", "l5", "l6", "tool0"]
        .iter()
        .map(|l| format!(r#"<link name="{l}"/>"#))
        .collect();
    let text = format!(
        r#"<?xml version="1.0"?><robot name="offset_wrist">{links}{}{}{}{}{}{}<joint name="flange" type="fixed"><parent link="l6"/><child link="tool0"/><origin xyz="0.09 0 0" rpy="0 1.5707963267948966 0"/></joint></robot>"#,
        joint(1, "base_link", "l1", "0 0 0", "0 0 1", 3.05),
        joint(2, "l1", "l2", "0.05 0 0.265", "0 1 0", 2.0),
        joint(3, "l2", "l3", "0 0 0.444", "0 1 0", 3.5),
        joint(4, "l3", "l4", "0 0 0.11", "1 0 0", 3.5),
        joint(5, "l4", "l5", "0.47 0.06 0", "0 1 0", 2.3),
        joint(6, "l5", "l6", "0.03 -0.06 -0.08", "1 0 0", 6.9),
    );
    let robot = Robot::from_urdf_str("offset_wrist.urdf", &text).unwrap();
    assert!(robot.opw.is_err(), "the test arm must lack the OPW form");
    robot
}

/// The IRB 140 with its closed form withheld: the numeric IK runs on an
/// arm the closed form also solves.
fn irb140_numeric() -> Robot {
    Robot {
        opw: Err("withheld by the test".into()),
        ..Robot::irb140()
    }
}

/// Position (mm) and rotation (rad) between two poses; the angle from the
/// quaternion's vector part (acos of its scalar part, what nalgebra's
/// `angle_to` takes, cannot tell 1e-12 from 0).
fn gap(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let d = (a.translation.vector - b.translation.vector).norm();
    let r = a.rotation.inverse() * b.rotation;
    (d, 2.0 * r.imag().norm().atan2(r.w.abs()))
}

/// The Jacobian of the flange pose, position rows in metres (so that
/// both halves weigh alike).
fn jacobian(robot: &Robot, q: &Joints) -> Matrix6<f64> {
    let axes = robot.chain.axes(q);
    let tip = robot.chain.fk(q).translation.vector;
    let mut j = Matrix6::zeros();
    for (i, (p, d)) in axes.iter().enumerate() {
        let v = d.cross(&(tip - p)) / 1000.0;
        j.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
        j.fixed_view_mut::<3, 1>(3, i).copy_from(d);
    }
    j
}

/// The Jacobian's smallest singular value: small near any singularity.
fn conditioning(robot: &Robot, q: &Joints) -> f64 {
    jacobian(robot, q).singular_values().min()
}

/// Random joints within the limits, away from singularities.
fn regular_joints(rng: &mut Rng, robot: &Robot) -> Joints {
    loop {
        let q = rng.joints_within(robot);
        if conditioning(robot, &q) > 0.02 {
            return q;
        }
    }
}

fn assert_within_limits(robot: &Robot, q: &Joints) {
    assert!(robot.outside_limits(q).is_empty(), "{q:?}");
}

/// For each arm: `n` random joints; pose and robconf from them; the
/// robconf IK reaches the pose with that robconf, within the limits, and
/// gives the same answer twice. Returns how many answers were another
/// arm solution than the source's (one with the same robconf; other turns
/// of axes 2 and 3 do not count) and the mean time per call.
fn round_trip(robot: &Robot, n: usize, seed: u64, scales: Option<&LinkScales>) -> (usize, f64) {
    let mut rng = Rng(seed);
    let mut other = 0;
    let mut time = 0.0;
    for _ in 0..n {
        let q = regular_joints(&mut rng, robot);
        let conf = robot.conf_of(&q);
        let pose = match scales {
            Some(s) => robot.chain.fk_scaled(&q, s),
            None => robot.fk(&q),
        };
        let start = Instant::now();
        let got = match scales {
            Some(s) => robot.ik_conf_scaled(&pose, &conf, s),
            None => robot.ik_conf(&pose, &conf),
        };
        time += start.elapsed().as_secs_f64();
        let got = got.unwrap_or_else(|e| panic!("{}: {q:?} {conf}: {e}", robot.name));
        assert_eq!(
            robot.conf_of(&got),
            conf,
            "{}: {q:?} -> {got:?}",
            robot.name
        );
        assert_within_limits(robot, &got);
        let back = match scales {
            Some(s) => robot.chain.fk_scaled(&got, s),
            None => robot.fk(&got),
        };
        let (d, r) = gap(&back, &pose);
        assert!(
            d <= 1e-9 && r <= 1e-12,
            "{}: {q:?}: {d:e} mm {r:e} rad",
            robot.name
        );
        let again = match scales {
            Some(s) => robot.ik_conf_scaled(&pose, &conf, s),
            None => robot.ik_conf(&pose, &conf),
        };
        assert_eq!(again.unwrap(), got, "the same question, another answer");
        if !same_physical(&got, &q) {
            other += 1;
        }
    }
    (other, time / n as f64)
}

#[test]
fn ur5_robconf_ik_reaches_the_pose_with_the_robconf() {
    let robot = ur5();
    assert!(robot.opw.is_err());
    let (other, t) = round_trip(&robot, 300, 0x5EED_0005, None);
    eprintln!("UR5: {other} of 300 answers are another arm solution with the source's robconf; {:.1} µs per call (test build)", t * 1e6);
    let (_, t) = round_trip(&robot, 100, 0x5EED_0006, Some(&WARM));
    eprintln!("UR5 warm: {:.1} µs per call (test build)", t * 1e6);
}

#[test]
fn offset_wrist_robconf_ik_reaches_the_pose_with_the_robconf() {
    let robot = offset_wrist();
    let (other, t) = round_trip(&robot, 300, 0x5EED_0007, None);
    eprintln!("offset wrist: {other} of 300 answers are another arm solution with the source's robconf; {:.1} µs per call (test build)", t * 1e6);
    round_trip(&robot, 100, 0x5EED_0008, Some(&WARM));
}

/// On the UR5 (every axis ±360°) axis 2 at −300° is axis 2 at 60°, with
/// the same robconf: the answer takes the turn nearest 0.
#[test]
fn axes_2_and_3_take_the_turn_nearest_zero() {
    let robot = ur5();
    let q = [
        0.3,
        (-300.0f64).to_radians(),
        250.0f64.to_radians(),
        0.4,
        1.1,
        -0.5,
    ];
    let conf = robot.conf_of(&q);
    let got = robot.ik_conf(&robot.fk(&q), &conf).unwrap();
    let want = [q[0], q[1] + TAU, q[2] - TAU, q[3], q[4], q[5]];
    for (a, b) in got.iter().zip(&want) {
        assert!((a - b).abs() < 1e-9, "{got:?} vs {want:?}");
    }
}

/// At and near the wrist singularity (axis 5 at 0) the answer still
/// reaches the pose with axis 5 near 0 (not turned to 360° for its sign)
/// and the robconf, or a near match within the closed form's 0.5°.
#[test]
fn wrist_singularity() {
    let ur5 = ur5();
    let irb = irb140_numeric();
    let cases: [(&Robot, &[f64]); 2] = [
        (&ur5, &[0.0, 1e-12, 1e-6]),
        (&irb, &[0.0, 1e-12, 1e-9, -1e-9, 1e-6]),
    ];
    for (robot, q5s) in cases {
        for &q5 in q5s {
            let q = [0.3, -0.8, 0.6, 0.4, q5, 0.5];
            let conf = robot.conf_of(&q);
            let pose = robot.fk(&q);
            let got = robot
                .ik_conf(&pose, &conf)
                .unwrap_or_else(|e| panic!("{}: q5 {q5:e}: {e}", robot.name));
            let (d, r) = gap(&robot.fk(&got), &pose);
            assert!(
                d <= 1e-9 && r <= 1e-12,
                "{}: q5 {q5:e}: {d:e} {r:e}",
                robot.name
            );
            assert!(got[4].abs() < 1e-6, "{}: q5 {q5:e}: {got:?}", robot.name);
            let back = robot.conf_of(&got);
            assert_eq!(
                (back.cf1, back.cf4, back.cf6),
                (conf.cf1, conf.cf4, conf.cf6)
            );
        }
    }
}

/// The strongest check: where the closed form exists, the numeric IK
/// finds its answer (to 1e-9 rad), for the taught robconf and for
/// another one (the same answer or an error of the same kind), cold and
/// warm; and all solutions are the closed form's.
#[test]
fn irb140_numeric_ik_equals_the_closed_form() {
    let closed = Robot::irb140();
    let numeric = irb140_numeric();
    let mut rng = Rng(0x5EED_0140);
    let mut compared_other = 0;
    for i in 0..600 {
        let q = regular_joints(&mut rng, &closed);
        let scales = (i % 3 == 0).then_some(WARM);
        let solve = |robot: &Robot, pose: &Isometry3<f64>, conf: &RobConf| match &scales {
            Some(s) => robot.ik_conf_scaled(pose, conf, s),
            None => robot.ik_conf(pose, conf),
        };
        let pose = match &scales {
            Some(s) => closed.fk_scaled(&q, s),
            None => closed.fk(&q),
        };
        let taught = closed.conf_of(&q);
        assert_eq!(
            numeric.conf_of(&q),
            taught,
            "the chain's robconf is the OPW one"
        );
        // Another solution's robconf, and one at random (mostly none's).
        let sols = closed.ik(&closed.fk(&q)).unwrap();
        let other = sols.as_slice()[(rng.next() * sols.len() as f64) as usize].conf;
        let random = RobConf::new(
            (rng.next() * 4.0) as i32 - 2,
            (rng.next() * 4.0) as i32 - 2,
            (rng.next() * 8.0) as i32 - 4,
            (rng.next() * 8.0) as i32,
        );
        for conf in [taught, other, random] {
            let a = solve(&closed, &pose, &conf);
            let b = solve(&numeric, &pose, &conf);
            match (&a, &b) {
                (Ok(a), Ok(b)) => {
                    for k in 0..6 {
                        assert!((a[k] - b[k]).abs() <= 1e-9, "{conf}: {a:?} vs {b:?}");
                    }
                    compared_other += usize::from(conf == other);
                }
                (Err(ea), Err(eb)) => assert_eq!(ea.kind, eb.kind, "{ea} / {eb}"),
                (Ok(a), Err(e)) => panic!("{conf}: closed form {a:?}, numeric {e}"),
                (Err(e), Ok(b)) => panic!("{conf}: closed form {e}, numeric {b:?}"),
            }
        }
        if i % 10 == 0 {
            let all = |r: &Robot| {
                let mut v: Vec<Joints> = match &scales {
                    Some(s) => r.ik_scaled(&pose, s),
                    None => r.ik(&pose),
                }
                .unwrap()
                .iter()
                .map(|s| s.q)
                .collect();
                // Rounded for the order: the two agree to 1e-12, not to the bit.
                v.sort_by_key(|q| q.map(|x| (x * 1e6).round() as i64));
                v
            };
            let (a, b) = (all(&closed), all(&numeric));
            assert_eq!(a.len(), b.len(), "{q:?}");
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    x.iter().zip(y).all(|(u, v)| (u - v).abs() <= 1e-9),
                    "{x:?} vs {y:?}"
                );
            }
        }
    }
    assert!(compared_other > 400, "{compared_other}");
}

/// An angle difference wrapped into [−π, π].
fn wrapped(v: f64) -> f64 {
    v - TAU * (v / TAU).round()
}

fn same_physical(a: &Joints, b: &Joints) -> bool {
    a.iter().zip(b).all(|(x, y)| wrapped(x - y).abs() < 1e-6)
}

/// The reference for the full search: plain damped Newton from 400 random
/// starts anywhere in (−2π, 2π)⁶, every distinct solution it reaches
/// (modulo 2π). Slow and simple.
fn brute_force(robot: &Robot, pose: &Isometry3<f64>, rng: &mut Rng) -> Vec<Joints> {
    let mut found: Vec<Joints> = Vec::new();
    for _ in 0..400 {
        let mut q = rng.any_joints();
        for _ in 0..100 {
            let f = robot.chain.fk(&q);
            let dp = (pose.translation.vector - f.translation.vector) / 1000.0;
            let (d, r) = gap(&f, pose);
            if d < 1e-9 && r < 1e-12 {
                if !found.iter().any(|g| same_physical(g, &q)) {
                    found.push(q);
                }
                break;
            }
            let dr = (pose.rotation * f.rotation.inverse()).scaled_axis();
            let e = nalgebra::Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z);
            let j = jacobian(robot, &q);
            let a = j.tr_mul(&j) + Matrix6::identity() * 1e-9;
            let Some(dq) = a.cholesky().map(|c| c.solve(&j.tr_mul(&e))) else {
                break;
            };
            let s = (0.3 / dq.amax()).min(1.0);
            for k in 0..6 {
                q[k] += dq[k] * s;
            }
        }
    }
    found
}

/// Every solution of the UR5's full search reaches the pose with its
/// robconf; its arm solutions (modulo 2π) are exactly those a brute-force
/// search finds, each first with the turns nearest 0, and the source
/// joints are one of them.
#[test]
fn ur5_all_solutions_are_the_brute_force_ones() {
    let robot = ur5();
    let mut rng = Rng(0x5EED_0A11);
    let mut starts = Rng(0x5EED_0B12);
    let mut counts = Vec::new();
    for _ in 0..12 {
        let q = regular_joints(&mut rng, &robot);
        let pose = robot.fk(&q);
        let sols = robot.ik(&pose).unwrap();
        for s in &sols {
            let (d, r) = gap(&robot.fk(&s.q), &pose);
            assert!(d <= 1e-9 && r <= 1e-12);
            assert_eq!(robot.conf_of(&s.q), s.conf);
            assert_within_limits(&robot, &s.q);
        }
        let mut physical: Vec<Joints> = Vec::new();
        for s in &sols {
            if !physical.iter().any(|p| same_physical(p, &s.q)) {
                physical.push(s.q);
            }
        }
        let reference = brute_force(&robot, &pose, &mut starts);
        assert_eq!(physical.len(), reference.len(), "{q:?}");
        for p in &reference {
            assert!(
                physical.iter().any(|s| same_physical(s, p)),
                "{p:?} missing"
            );
        }
        for (i, s) in sols.iter().take(physical.len()).enumerate() {
            assert!(same_physical(&s.q, &physical[i]));
            assert!(s.q.iter().all(|v| v.abs() <= PI + 1e-9), "{:?}", s.q);
        }
        assert!(physical.iter().any(|s| same_physical(s, &q)));
        counts.push(physical.len());
    }
    eprintln!("UR5 arm solutions per pose: {counts:?}");
}

#[test]
fn a_robconf_no_solution_has_is_unreachable_with_the_list() {
    let robot = ur5();
    let q = [0.3, -1.2, 1.4, -0.6, 1.1, 0.5];
    let pose = robot.fk(&q);
    // Axis 1 in its fifth quadrant (450°..540°): beyond its ±360°.
    let e = robot.ik_conf(&pose, &RobConf::new(5, 0, 0, 0)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert_eq!(
        e.message,
        "no solution with robconf [5,0,0,0] within the joint limits"
    );
    let note = e.notes.join("\n");
    assert!(note.starts_with("reachable configurations: "), "{note}");
    assert!(note.contains(&robot.conf_of(&q).to_string()), "{note}");
    // 8 arm solutions, each with 2 turns of axes 1, 4, 5 and 6.
    assert_eq!(note.matches('[').count(), 8 * 16, "{note}");
}

#[test]
fn out_of_reach_and_non_finite_input() {
    let robot = ur5();
    // Beyond the summed offsets: refused at once. Within them but beyond
    // the arm's reach: the search finds nothing.
    for (pose, why) in [
        (
            (3000.0, 0.0, 0.0),
            "out of reach: the flange is 3000.000 mm",
        ),
        (
            (1100.0, 0.0, 100.0),
            "out of reach: no joint values put the flange",
        ),
    ] {
        let pose = Isometry3::translation(pose.0, pose.1, pose.2);
        for e in [
            robot.ik_conf(&pose, &RobConf::default()).unwrap_err(),
            robot.ik(&pose).unwrap_err(),
        ] {
            assert_eq!(e.kind, ErrorKind::Unreachable);
            assert!(e.message.starts_with(why), "{}", e.message);
        }
    }
    let nan = Isometry3::translation(f64::NAN, 0.0, 0.0);
    let e = robot.ik_conf(&nan, &RobConf::default()).unwrap_err();
    assert_eq!(
        (e.kind, e.message.as_str()),
        (ErrorKind::Input, "pose is not finite")
    );
    let e = robot.ik(&nan).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    let pose = robot.fk(&[0.3, -1.2, 1.4, -0.6, 1.1, 0.5]);
    let e = robot
        .ik_conf_scaled(&pose, &RobConf::default(), &[1.0, f64::NAN, 1.0, 1.0])
        .unwrap_err();
    assert_eq!(
        (e.kind, e.message.as_str()),
        (ErrorKind::Input, "motor temperatures are not finite")
    );
    let e = robot.ik_conf(&pose, &RobConf::new(0, 0, 0, 9)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
}

/// Solutions that exist but are all outside the limits: the closed form's
/// error, naming an axis of each.
#[test]
fn every_solution_outside_the_limits() {
    let mut robot = ur5();
    let pose = robot.fk(&[0.3, -1.2, 1.4, -0.6, 1.1, 0.5]);
    robot.limits[3] = (2.0, 2.1);
    robot.limits[4] = (2.0, 2.1);
    for e in [
        robot.ik(&pose).unwrap_err(),
        robot.ik_conf(&pose, &RobConf::default()).unwrap_err(),
    ] {
        assert_eq!(e.kind, ErrorKind::Unreachable);
        assert_eq!(
            e.message,
            "every solution violates a joint limit of the arm ur5"
        );
        assert!(e.notes.join("").contains("axis 4 at"), "{:?}", e.notes);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(60))]

    /// Nothing panics on any pose, robconf or scales; what is returned
    /// reaches the pose.
    #[test]
    fn never_panics(
        x in prop_oneof![-1500.0f64..1500.0, Just(f64::INFINITY), Just(1e300), Just(1e-300)],
        y in -1500.0f64..1500.0,
        z in -1500.0f64..1500.0,
        w in -1.0f64..1.0, i in -1.0f64..1.0, j in -1.0f64..1.0, k in -1.0f64..1.0,
        conf in proptest::array::uniform4(-6i32..9),
        scale in prop_oneof![Just(1.0), 0.999f64..1.001, Just(f64::NAN)],
    ) {
        let q = Quaternion::new(w, i, j, k);
        prop_assume!(q.norm() > 1e-6);
        let pose = Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_quaternion(q));
        let robot = offset_wrist();
        let scales = [scale; 4];
        if let Ok(got) = robot.ik_conf_scaled(&pose, &RobConf::new(conf[0], conf[1], conf[2], conf[3]), &scales) {
            let (d, r) = gap(&robot.chain.fk_scaled(&got, &scales), &pose);
            prop_assert!(d <= 1e-9 && r <= 1e-12, "{d:e} {r:e}");
        }
        let _ = robot.ik_scaled(&pose, &scales);
    }
}
