//! The catalogue of ABB arms (`data/arms/*.toml`, `Robot::abb`): every arm
//! against numbers published apart from the file it was written from
//! (RobotComponents' presets, the OPW parameter sets, the designations),
//! the chain built from OPW lengths against the OPW model, IK and robconf
//! round trips on every arm, rs-opw-kinematics' presets, the parallel-arm
//! axis 3 of the IRB 2400, and the name lookup.

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rapidtherm::diagnose::arm::Arm;
use rapidtherm::error::ErrorKind;
use rapidtherm::model::chain::{fk_chain, Perturbation};
use rapidtherm::robot::abb::{self, AbbArm, Axis3};
use rapidtherm::robot::chain::Chain;
use rapidtherm::robot::ik::{serial_angles, wrap, OpwArm};
use rapidtherm::robot::{Joints, Opw, Robot};
use rs_opw_kinematics::kinematic_traits::{Kinematics, Pose};
use rs_opw_kinematics::kinematics_impl::OPWKinematics;
use rs_opw_kinematics::parameters::opw_kinematics::Parameters;
use std::f64::consts::{FRAC_PI_2, PI};

use crate::rng::Rng;

fn pose_dist(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

fn arm(name: &str) -> &'static AbbArm {
    abb::find(name).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The OPW lengths of each arm as published apart from the data file's
/// first source: RobotComponents' presets (8eaaf1a,
/// `RobotComponents.ABB.Presets/Robots/*.cs`: a1, a2, c1, c2, c3, c4), and
/// for the arms it lacks, the ROS-Industrial joint origins (IRB 120T,
/// IRB 1600-8/1.45) or opw_kinematics' `makeIrb2400_10` (IRB 2400).
/// (name, a1, a2, c1, c2, c3, c4) in mm; b is 0 on all of them.
const PUBLISHED: &[(&str, f64, f64, f64, f64, f64, f64)] = &[
    ("IRB 120-3/0.58", 0.0, -70.0, 290.0, 270.0, 302.0, 72.0),
    ("IRB 120T-3/0.58", 0.0, -70.0, 290.0, 270.0, 302.0, 72.0),
    ("IRB 140", 70.0, 0.0, 352.0, 360.0, 380.0, 65.0),
    ("IRB 1200-5/0.9", 0.0, -42.0, 399.1, 448.0, 451.0, 82.0),
    ("IRB 1200-7/0.7", 0.0, -42.0, 399.1, 350.0, 351.0, 82.0),
    ("IRB 1600-6/1.2", 150.0, 0.0, 486.5, 475.0, 600.0, 65.0),
    ("IRB 1600-8/1.45", 150.0, 0.0, 486.5, 700.0, 600.0, 65.0),
    ("IRB 1600-10/1.45", 150.0, 0.0, 486.5, 700.0, 600.0, 65.0),
    ("IRB 2400-10", 100.0, -135.0, 615.0, 705.0, 755.0, 85.0),
    ("IRB 2400-16", 100.0, -135.0, 615.0, 705.0, 755.0, 85.0),
    ("IRB 2600-12/1.65", 150.0, -115.0, 445.0, 700.0, 795.0, 85.0),
    ("IRB 2600-20/1.65", 150.0, -115.0, 445.0, 700.0, 795.0, 85.0),
    ("IRB 2600-12/1.85", 150.0, -115.0, 445.0, 900.0, 795.0, 85.0),
    (
        "IRB 4600-20/2.50",
        175.0,
        -175.0,
        495.0,
        1095.0,
        1230.5,
        85.0,
    ),
    (
        "IRB 4600-40/2.55",
        175.0,
        -175.0,
        495.0,
        1095.0,
        1270.0,
        135.0,
    ),
    (
        "IRB 4600-45/2.05",
        175.0,
        -175.0,
        495.0,
        900.0,
        960.0,
        135.0,
    ),
    (
        "IRB 4600-60/2.05",
        175.0,
        -175.0,
        495.0,
        900.0,
        960.0,
        135.0,
    ),
    (
        "IRB 6640-185/2.8",
        320.0,
        -200.0,
        780.0,
        1075.0,
        1392.5,
        200.0,
    ),
    (
        "IRB 6640-235/2.55",
        320.0,
        -200.0,
        780.0,
        1075.0,
        1142.5,
        200.0,
    ),
    (
        "IRB 6650S-125/3.5",
        600.0,
        -200.0,
        630.0,
        1280.0,
        1592.0,
        200.0,
    ),
    (
        "IRB 6650S-90/3.9",
        600.0,
        -200.0,
        630.0,
        1280.0,
        2042.0,
        200.0,
    ),
    (
        "IRB 6700-200/2.60",
        320.0,
        -200.0,
        780.0,
        1125.0,
        1142.5,
        200.0,
    ),
    (
        "IRB 6700-235/2.65",
        320.0,
        -200.0,
        780.0,
        1135.0,
        1182.5,
        200.0,
    ),
    (
        "IRB 7600-150/3.50",
        410.0,
        -165.0,
        780.0,
        1075.0,
        2012.0,
        250.0,
    ),
];

#[test]
fn the_catalogue_has_the_arms_people_own_each_with_its_sources() {
    let names = abb::names();
    for (name, ..) in PUBLISHED {
        assert!(names.contains(name), "{name} missing from {names:?}");
    }
    assert_eq!(names.len(), PUBLISHED.len(), "{names:?}");
    for a in abb::catalogue() {
        let s = &a.sources;
        for (what, list) in [
            ("geometry", &s.geometry),
            ("limits", &s.limits),
            ("rating", &s.rating),
            ("axis3", &s.axis3),
        ] {
            assert!(!list.is_empty(), "{}: no {what} source", a.name);
            assert!(list
                .iter()
                .all(|c| !c.cite.is_empty() && !c.label.is_empty()));
        }
        assert_eq!(
            a.max_speed_deg_s.is_some(),
            !s.speeds.is_empty(),
            "{}",
            a.name
        );
        assert!(a.file.starts_with("data/arms/"), "{}", a.file);
        assert_eq!(a.robot().name, a.name);
    }
    // The loader's checks pass on the embedded files (what `catalogue`
    // relies on).
    assert_eq!(abb::load().unwrap(), abb::catalogue());
}

/// The zero pose (lower arm up, upper arm level): wrist centre at (a1 +
/// c3, 0, c1 + c2 − a2), tool0 c4 further out, z forward and x down, as on
/// ABB's dimension drawings. And the reach to the wrist centre, arm
/// stretched out level: a1 + c2 + √(c3² + a2²) against the designation
/// (rounded there: within 2.5 %, the IRB 1600-6/1.2's 1225 mm the farthest).
#[test]
fn every_arm_has_the_published_zero_pose_and_reach() {
    let down_z_forward = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_2);
    for &(name, a1, a2, c1, c2, c3, c4) in PUBLISHED {
        let a = arm(name);
        let robot = a.robot();
        let tool0 = robot.fk(&[0.0; 6]);
        let wrist = tool0 * Point3::new(0.0, 0.0, -c4);
        let expect = Vector3::new(a1 + c3, 0.0, c1 + c2 - a2);
        assert!((wrist.coords - expect).norm() < 1e-9, "{name}: {wrist}");
        let flange = expect + Vector3::new(c4, 0.0, 0.0);
        assert!((tool0.translation.vector - flange).norm() < 1e-9, "{name}");
        assert!(tool0.rotation.angle_to(&down_z_forward) < 1e-12, "{name}");

        // Stretched level: lower arm at 90°, the upper arm in line with
        // the triangle's long side (serial θ3 = −atan2(a2, c3)), axis 3 in
        // the controller's angle.
        let serial3 = -FRAC_PI_2 - a2.atan2(c3);
        let q3 = match a.axis3 {
            Axis3::Serial => serial3,
            Axis3::Parallel => serial3 + FRAC_PI_2,
        };
        let q = [0.0, FRAC_PI_2, q3, 0.0, 0.0, 0.0];
        let w = robot.fk(&q) * Point3::new(0.0, 0.0, -c4);
        let reach = a1 + c2 + c3.hypot(a2);
        assert!((w.x - reach).abs() < 1e-9 && w.z.abs() > 0.0, "{name}: {w}");
        let published = a.reach_m * 1000.0;
        assert!(
            (reach - published).abs() <= 0.025 * published,
            "{name}: reach {reach} mm against {published} mm"
        );
    }
}

#[test]
fn the_chain_of_opw_lengths_is_the_opw_model() {
    let mut rng = Rng(5);
    for a in abb::catalogue() {
        let robot = a.robot();
        // The chain read back as an OPW arm: the same lengths, ABB's
        // conventions, the same axis-3 coupling.
        let back = robot.chain.extract_opw().unwrap();
        let want = robot.opw.clone().unwrap();
        let g = [back.geom.c1 - want.geom.c1, back.geom.a1 - want.geom.a1]
            .into_iter()
            .chain([
                back.geom.c2 - want.geom.c2,
                back.geom.c3 - want.geom.c3,
                back.geom.c4 - want.geom.c4,
                back.geom.a2 - want.geom.a2,
                back.geom.b - want.geom.b,
            ]);
        for d in g {
            assert!(d.abs() < 1e-9, "{}: {:?}", a.name, back.geom);
        }
        assert_eq!(back.signs, want.signs, "{}", a.name);
        assert_eq!(back.offsets, want.offsets, "{}", a.name);
        assert_eq!(back.coupling, want.coupling, "{}", a.name);
        // Cold and warm, for any joint values.
        let scales = [1.0004, 1.0007, 0.9995, 1.0011];
        for _ in 0..300 {
            let q = rng.any_joints();
            let (dp, dr) = pose_dist(&robot.chain.fk(&q), &robot.fk(&q));
            assert!(dp < 1e-9 && dr < 1e-12, "{}: {dp} {dr}", a.name);
            let (dp, dr) = pose_dist(
                &robot.chain.fk_scaled(&q, &scales),
                &robot.fk_scaled(&q, &scales),
            );
            assert!(dp < 1e-9 && dr < 1e-12, "{} warm: {dp} {dr}", a.name);
        }
    }
    // On a serial arm the chain is `Opw::fk` itself.
    let opw = arm("IRB 2600-12/1.65").opw;
    let chain = Chain::from_opw(&opw, 0.0);
    for _ in 0..300 {
        let q = rng.any_joints();
        let (dp, dr) = pose_dist(&chain.fk(&q), &opw.fk(&q));
        assert!(dp < 1e-9 && dr < 1e-12, "{dp} {dr}");
    }
}

/// No singular pose among the samples: axis 5 away from 0 and ±180° (the
/// split of q4 and q6 is chosen there) and the wrist centre off axis 1.
fn regular(robot: &Robot, q: &Joints) -> bool {
    let arm = robot.opw.as_ref().unwrap();
    let w = robot.fk(q) * Point3::new(0.0, 0.0, -arm.geom.c4);
    q[4].sin().abs() > 1e-3 && w.x.hypot(w.y) > 1.0
}

/// 10,000 random joint sets within the limits per arm: every IK solution
/// reaches the pose, and the joints it came from are among them.
#[test]
fn ik_round_trips_on_every_arm() {
    let mut rng = Rng(2026);
    for a in abb::catalogue() {
        let robot = a.robot();
        let (mut worst_p, mut worst_r) = (0.0f64, 0.0f64);
        let mut done = 0;
        while done < 10_000 {
            let q = rng.joints_within(&robot);
            if !regular(&robot, &q) {
                continue;
            }
            let pose = robot.fk(&q);
            let sols = robot
                .ik(&pose)
                .unwrap_or_else(|e| panic!("{}: {q:?}: {e}", a.name));
            assert!(
                sols.iter()
                    .any(|s| (0..6).all(|i| (s.q[i] - q[i]).abs() < 1e-7)),
                "{}: {q:?} not among {sols:?}",
                a.name
            );
            for s in &sols {
                let (dp, dr) = pose_dist(&robot.fk(&s.q), &pose);
                worst_p = worst_p.max(dp);
                worst_r = worst_r.max(dr);
            }
            done += 1;
        }
        assert!(worst_p < 1e-9, "{}: {worst_p} mm", a.name);
        assert!(worst_r < 1e-11, "{}: {worst_r} rad", a.name);
    }
}

/// robconf of taught joints picks those joints back from the pose, on
/// every arm (1,000 joint sets each, away from quadrant boundaries).
#[test]
fn robconf_round_trips_on_every_arm() {
    let mut rng = Rng(77);
    let near_boundary = |v: f64| {
        let r = v / FRAC_PI_2;
        (r - r.round()).abs() < 1e-6
    };
    for a in abb::catalogue() {
        let robot = a.robot();
        let mut done = 0;
        while done < 1000 {
            let q = rng.joints_within(&robot);
            if !regular(&robot, &q) || [q[0], q[3], q[5]].into_iter().any(near_boundary) {
                continue;
            }
            let pose = robot.fk(&q);
            let conf = robot.conf_of(&q);
            let back = robot
                .ik_conf(&pose, &conf)
                .unwrap_or_else(|e| panic!("{}: {q:?} {conf}: {e}", a.name));
            for i in 0..6 {
                assert!(
                    (back[i] - q[i]).abs() < 1e-8,
                    "{}: {q:?} -> {back:?}",
                    a.name
                );
            }
            done += 1;
        }
    }
}

/// The lower-arm bit of cfx turns where the wrist centre crosses the line
/// through axes 2 and 3, the elbow singularity, which on an arm with an
/// elbow offset is not q3 = −90°: on the IRB 2600 (a2 −115, c3 795 mm) at
/// q3 = −90° + atan(115/795) ≈ −81.77°, and on the parallel-arm IRB 2400
/// at the same serial angle, i.e. q2 further in the controller's q3.
#[test]
fn the_lower_arm_bit_turns_on_the_line_through_axes_2_and_3() {
    for (name, q2) in [("IRB 2600-12/1.65", 0.3), ("IRB 2400-10", 0.3)] {
        let a = arm(name);
        let robot = a.robot();
        let g = a.opw;
        let serial3 = -FRAC_PI_2 + (-g.a2).atan2(g.c3);
        let crossing = serial3 - a.axis3.coupling() * q2;
        for (dq, cfx) in [(-1e-6, 2), (1e-6, 0)] {
            let q = [0.1, q2, crossing + dq, 0.2, 0.4, 0.3];
            assert_eq!(robot.conf_of(&q).cfx, cfx, "{name} at {dq}");
            // The wrist centre's side of the lower arm, from the chain.
            let ax = robot.chain.axes(&q);
            let (p2, d2) = ax[1];
            let lower = ax[2].0 - p2;
            let w = robot.fk(&q) * Point3::new(0.0, 0.0, -g.c4);
            let side = (w.coords - p2).dot(&d2.cross(&lower));
            assert_eq!(side < 0.0, cfx == 2, "{name}: side {side}");
        }
    }
}

/// The IRB 2400's controller reads axis 3 against the horizontal: tilting
/// axis 2 alone leaves the upper arm (and the flange) level.
#[test]
fn parallel_arm_axis_3_keeps_the_upper_arm_level() {
    let robot = Robot::abb("irb2400-10").unwrap();
    let level = robot.fk(&[0.0; 6]).rotation;
    for q2 in [-0.8, -0.2, 0.4, 1.1] {
        let pose = robot.fk(&[0.0, q2, 0.0, 0.0, 0.0, 0.0]);
        assert!(pose.rotation.angle_to(&level) < 1e-12, "q2 {q2}");
        // The serial angle is q3 − q2: the same pose as a serial arm of
        // the same lengths at (q2, −q2).
        let serial = Robot::from_opw(
            "serial",
            robot.opw.as_ref().unwrap().geom,
            0.0,
            robot.limits,
            [0.0; 6],
        );
        let (dp, dr) = pose_dist(&pose, &serial.fk(&[0.0, q2, -q2, 0.0, 0.0, 0.0]));
        assert!(dp < 1e-9 && dr < 1e-12);
    }
    // The diagnosis's perturbed chain (ABB's serial convention) agrees
    // through the arm's joint map.
    let diag = Arm::of_robot(&robot, "test").unwrap();
    let mut rng = Rng(9);
    for _ in 0..200 {
        let q = rng.joints_within(&robot);
        let chain = fk_chain(
            diag.nominal.opw().unwrap(),
            &diag.map.to_chain(&q),
            &Perturbation::default(),
        );
        let (dp, dr) = pose_dist(&diag.map.tool0(&chain), &robot.fk(&q));
        assert!(dp < 1e-9 && dr < 1e-12, "{dp} {dr}");
        let back = diag.map.from_chain(&diag.map.to_chain(&q));
        assert!((0..6).all(|i| (back[i] - q[i]).abs() < 1e-12));
    }
}

fn to_ref(p: &Isometry3<f64>) -> Pose {
    let t = p.translation.vector / 1000.0;
    let q = p.rotation.quaternion();
    Pose::from_parts(
        rs_opw_kinematics::glam::DVec3::new(t.x, t.y, t.z),
        rs_opw_kinematics::glam::DQuat::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

fn from_ref(p: &Pose) -> Isometry3<f64> {
    let (t, r) = (p.translation, p.rotation);
    Isometry3::from_parts(
        Translation3::new(t.x * 1000.0, t.y * 1000.0, t.z * 1000.0),
        UnitQuaternion::from_quaternion(Quaternion::new(r.w, r.x, r.y, r.z)),
    )
}

/// rs-opw-kinematics' own ABB presets (metres, ROS-Industrial joint
/// coordinates: serial, so the IRB 2400's axis 3 is q3 − q2 there).
#[test]
fn forward_kinematics_agrees_with_rs_opw_kinematics_presets() {
    let presets: [(&str, Parameters); 9] = [
        ("IRB 120-3/0.58", Parameters::irb120_3_58()),
        ("IRB 1200-5/0.9", Parameters::irb1200_5_90()),
        ("IRB 1200-7/0.7", Parameters::irb1200_7_70()),
        ("IRB 1600-6/1.2", Parameters::irb1600_6_120()),
        ("IRB 1600-10/1.45", Parameters::abb_1600()),
        ("IRB 2400-10", Parameters::irb2400_10()),
        ("IRB 2600-12/1.65", Parameters::irb2600_12_165()),
        ("IRB 4600-40/2.55", Parameters::irb4600_40_255()),
        ("IRB 4600-60/2.05", Parameters::irb4600_60_205()),
    ];
    let mut rng = Rng(31);
    for (name, p) in presets {
        let a = arm(name);
        let ours = [
            a.opw.a1, a.opw.a2, a.opw.b, a.opw.c1, a.opw.c2, a.opw.c3, a.opw.c4,
        ];
        let theirs = [p.a1, p.a2, p.b, p.c1, p.c2, p.c3, p.c4].map(|v| v * 1000.0);
        for (o, t) in ours.iter().zip(theirs) {
            assert!((o - t).abs() < 1e-9, "{name}: {ours:?} against {theirs:?}");
        }
        let robot = a.robot();
        let reference = OPWKinematics::new(p);
        for _ in 0..2000 {
            let q = rng.any_joints();
            let ros = serial_angles(&q, a.axis3.coupling());
            let (dp, dr) = pose_dist(&robot.fk(&q), &from_ref(&reference.forward(&ros)));
            assert!(dp < 1e-9 && dr < 1e-12, "{name}: {dp} {dr}");
        }
    }
}

/// The eight OPW branches of an arm with a shoulder and an elbow offset
/// (IRB 2600) and of the parallel-arm IRB 2400 are rs-opw-kinematics'.
#[test]
fn ik_solution_sets_agree_with_rs_opw_kinematics() {
    for (name, p) in [
        ("IRB 2600-12/1.65", Parameters::irb2600_12_165()),
        ("IRB 2400-10", Parameters::irb2400_10()),
    ] {
        let a = arm(name);
        let mut robot = a.robot();
        // One turn of every axis: no ±360° variants.
        robot.limits = [(-PI, PI); 6];
        let opw: OpwArm = robot.opw.clone().unwrap();
        let reference = OPWKinematics::new(p);
        let mut rng = Rng(4);
        let mut compared = 0;
        while compared < 2000 {
            let q: Joints = std::array::from_fn(|_| (rng.next() * 2.0 - 1.0) * PI);
            if !regular(&robot, &q) || (q[4].abs() - PI).abs() < 1e-3 {
                continue;
            }
            let pose = robot.fk(&q);
            let ours = opw.solve(&pose, &robot.limits, None).unwrap();
            let theirs = reference.inverse(&to_ref(&pose));
            let same = |ros: &Joints, t: &Joints| (0..6).all(|i| wrap(ros[i] - t[i]).abs() < 1e-7);
            let ours_ros: Vec<Joints> = ours
                .iter()
                .map(|s| serial_angles(&s.q, a.axis3.coupling()))
                .collect();
            for t in &theirs {
                assert!(
                    ours_ros.iter().any(|o| same(o, t)),
                    "{name}: {t:?} not in ours"
                );
            }
            for o in &ours_ros {
                assert!(
                    theirs.iter().any(|t| same(o, t)),
                    "{name}: {o:?} not in theirs"
                );
            }
            compared += 1;
        }
    }
}

#[test]
fn the_irb_140_entry_is_the_embedded_arm() {
    let by_name = Robot::abb("irb140").unwrap();
    let embedded = Robot::irb140();
    assert_eq!(by_name.name, "IRB 140");
    assert_eq!(
        Robot {
            name: embedded.name.clone(),
            ..by_name
        },
        embedded
    );
    assert!(arm("IRB 140").is_embedded_irb140());
    assert_eq!(arm("IRB 140-6/0.81").name, "IRB 140");
}

#[test]
fn names_are_forgiving_of_case_spaces_and_trailing_zeros() {
    for (given, meant) in [
        ("irb2600-12/1.65", "IRB 2600-12/1.65"),
        ("IRB 2600-12/1.65", "IRB 2600-12/1.65"),
        ("  Irb 2600 - 12 / 1.65 ", "IRB 2600-12/1.65"),
        ("ABB IRB 2600-12/1.85", "IRB 2600-12/1.85"),
        ("irb6700-200/2.6", "IRB 6700-200/2.60"),
        ("irb4600-20/2.5", "IRB 4600-20/2.50"),
        ("irb140", "IRB 140"),
        ("IRB 120", "IRB 120-3/0.58"),
        ("irb120t", "IRB 120T-3/0.58"),
        ("irb7600", "IRB 7600-150/3.50"),
        ("IRB 2400-12/1.55", "IRB 2400-10"),
        ("irb2400-20/1.55", "IRB 2400-16"),
    ] {
        assert_eq!(Robot::abb(given).unwrap().name, meant, "{given}");
    }
}

#[test]
fn a_family_of_several_variants_asks_for_one() {
    let e = Robot::abb("irb2600").unwrap_err();
    assert_eq!(e.kind, ErrorKind::Usage);
    assert_eq!(
        e.message,
        "IRB 2600 comes in 3 variants: IRB 2600-12/1.65, IRB 2600-20/1.65, IRB 2600-12/1.85; name one"
    );
    let e = Robot::abb("IRB 4600").unwrap_err();
    assert!(e.message.contains("IRB 4600-45/2.05"), "{}", e.message);
}

#[test]
fn an_unknown_name_lists_the_nearest() {
    let e = Robot::abb("irb2600-12/1.75").unwrap_err();
    assert_eq!(e.kind, ErrorKind::Usage);
    assert_eq!(
        e.message,
        "no ABB arm named `irb2600-12/1.75` in the catalogue"
    );
    let note = e.to_string();
    assert!(
        note.contains("nearest: IRB 2600-12/1.65, IRB 2600-12/1.85"),
        "{note}"
    );
    // A name cut short lists what it starts.
    let note = Robot::abb("irb2600-12").unwrap_err().to_string();
    assert!(
        note.contains("nearest: IRB 2600-12/1.65, IRB 2600-12/1.85 ("),
        "{note}"
    );
    // A family one digit off brings its variants.
    let note = Robot::abb("irb2700").unwrap_err().to_string();
    assert!(note.contains("IRB 2600-20/1.65"), "{note}");
    assert!(Robot::abb("").is_err());
}

#[test]
fn opw_lengths_of_any_arm_build_a_robot() {
    let geom = Opw {
        c1: 400.0,
        a1: 25.0,
        c2: 455.0,
        c3: 420.0,
        c4: 90.0,
        a2: -35.0,
        b: 0.0,
    };
    let robot = Robot::from_opw("test arm", geom, 0.0, [(-PI, PI); 6], [100.0; 6]);
    assert_eq!(robot.name, "test arm");
    let q = [0.3, -0.2, 0.4, 1.0, -0.6, 2.0];
    let (dp, dr) = pose_dist(&robot.fk(&q), &geom.fk(&q));
    assert!(dp < 1e-9 && dr < 1e-12);
}
