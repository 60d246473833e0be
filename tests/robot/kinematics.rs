//! The IRB 140 model: check poses of docs/model.md, embedded URDF vs docs/model.md's
//! numbers, IK round trips, robconf, singularities, unreachable targets,
//! and the thermal drift at the calibration pose.

use approx::assert_relative_eq;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rapidtherm::error::ErrorKind;
use rapidtherm::model::ThermalExpansion;
use rapidtherm::robot::ik::{wrap, OpwArm, CONF_TOLERANCE};
use rapidtherm::robot::{irb140_opw, Joints, Opw, RobConf, Robot};
use rapidtherm::thermal::TABLE1_TMAX;

fn deg(q: [f64; 6]) -> Joints {
    q.map(f64::to_radians)
}

use crate::rng::Rng;

fn pose_dist(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

#[allow(clippy::approx_constant)]
const CHECK_POSES: [([f64; 6], [f64; 3], [f64; 4]); 4] = [
    ([0.0; 6], [515.0, 0.0, 712.0], [0.70711, 0.0, 0.70711, 0.0]),
    (
        [0.0, 0.0, 0.0, 0.0, 90.0, 0.0],
        [450.0, 0.0, 647.0],
        [0.0, 0.0, 1.0, 0.0],
    ),
    (
        [90.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 515.0, 712.0],
        [0.5, -0.5, 0.5, 0.5],
    ),
    (
        [30.0, 20.0, -40.0, 50.0, 60.0, 70.0],
        [492.1012, 333.9077, 797.3712],
        [0.07631, -0.31555, -0.75926, -0.56403],
    ),
];

fn assert_check_pose(pose: &Isometry3<f64>, p: [f64; 3], quat: [f64; 4]) {
    let t = pose.translation.vector;
    assert_relative_eq!(t.x, p[0], epsilon = 1e-4);
    assert_relative_eq!(t.y, p[1], epsilon = 1e-4);
    assert_relative_eq!(t.z, p[2], epsilon = 1e-4);
    let r = pose.rotation.quaternion();
    let s = if r.w < -1e-12 { -1.0 } else { 1.0 };
    assert_relative_eq!(s * r.w, quat[0], epsilon = 1e-5);
    assert_relative_eq!(s * r.i, quat[1], epsilon = 1e-5);
    assert_relative_eq!(s * r.j, quat[2], epsilon = 1e-5);
    assert_relative_eq!(s * r.k, quat[3], epsilon = 1e-5);
}

#[test]
fn check_poses_through_every_model() {
    let robot = Robot::irb140();
    for (q, p, quat) in CHECK_POSES {
        let q = deg(q);
        assert_check_pose(&robot.fk(&q), p, quat);
        // The OPW geometry alone, as the diagnosis's base model uses it.
        assert_check_pose(&irb140_opw().fk(&q), p, quat);
        // The URDF chain itself (general serial FK), not the OPW shortcut.
        assert_check_pose(&robot.chain.fk(&q), p, quat);
        // At the reference temperature the warm model is the nominal one.
        let at_ref = ThermalExpansion::default().scales(&[7.0; 6]);
        assert_check_pose(&robot.fk_scaled(&q, &at_ref), p, quat);
    }
}

/// The IRB 140 of `docs/model.md` ("Geometry"), mm: the reference
/// the embedded URDF is checked against (the model itself is data).
const SPEC_OPW: Opw = Opw {
    c1: 352.0,
    a1: 70.0,
    c2: 360.0,
    c3: 380.0,
    c4: 65.0,
    a2: 0.0,
    b: 0.0,
};

#[test]
fn embedded_urdf_is_the_spec_arm() {
    let urdf = Robot::from_urdf_str("irb140.urdf", rapidtherm::robot::urdf::IRB140_URDF).unwrap();
    assert_eq!(urdf, Robot::irb140());
    assert_eq!(urdf.name, "abb_irb140");
    // Joint limits of docs/model.md, degrees.
    let limits = [
        (-180.0, 180.0),
        (-90.0, 110.0),
        (-230.0, 50.0),
        (-200.0, 200.0),
        (-115.0, 115.0),
        (-400.0, 400.0),
    ];
    // Maximum axis speeds of the ABB product specification, deg/s.
    let speeds = [200.0, 200.0, 260.0, 360.0, 360.0, 450.0];
    for i in 0..6 {
        assert_relative_eq!(
            urdf.limits[i].0,
            f64::to_radians(limits[i].0),
            epsilon = 1e-15
        );
        assert_relative_eq!(
            urdf.limits[i].1,
            f64::to_radians(limits[i].1),
            epsilon = 1e-15
        );
        assert_relative_eq!(urdf.max_speed_deg_s[i], speeds[i], epsilon = 1e-9);
    }
    // The OPW form: docs/model.md's lengths, bit for bit (the diagnosis's base
    // model and the default model file use them), ABB's joint conventions.
    let a = urdf.opw.clone().unwrap();
    assert_eq!(a.geom, SPEC_OPW);
    assert_eq!(irb140_opw(), SPEC_OPW);
    let b = OpwArm::abb(SPEC_OPW);
    assert_eq!(a.signs, [1.0; 6]);
    assert_eq!(a.signs, b.signs);
    assert_eq!(a.offsets, b.offsets);
    assert!(a.tip.angle_to(&b.tip) < 1e-12);
    // The URDF chain and docs/model.md's OPW arm agree everywhere, cold and warm.
    let mut rng = Rng(7);
    let warm = [20.0, 25.0, 30.0, 35.0, 40.0, 45.0];
    for _ in 0..500 {
        let q = rng.joints_within(&urdf);
        let (dp, dr) = pose_dist(&urdf.chain.fk(&q), &b.fk(&q));
        assert!(dp < 1e-9 && dr < 1e-12, "{dp} {dr}");
        let scales = ThermalExpansion::default().scales(&warm);
        let warm_spec = OpwArm {
            geom: SPEC_OPW.scaled(&scales),
            ..b
        };
        let (dp, dr) = pose_dist(&urdf.chain.fk_scaled(&q, &scales), &warm_spec.fk(&q));
        assert!(dp < 1e-9 && dr < 1e-12, "warm {dp} {dr}");
    }
}

#[test]
fn every_ik_solution_reaches_the_pose_and_the_source_is_among_them() {
    let robot = Robot::irb140();
    let mut rng = Rng(42);
    for _ in 0..2000 {
        let q = rng.joints_within(&robot);
        let pose = robot.fk(&q);
        let sols = robot.ik(&pose).unwrap();
        assert!(!sols.is_empty());
        let mut found = false;
        for s in &sols {
            let (dp, dr) = pose_dist(&robot.fk(&s.q), &pose);
            assert!(dp < 1e-9 && dr < 1e-9, "{dp} {dr} {:?}", s.q);
            assert_eq!(s.conf, robot.conf_of(&s.q));
            for i in 0..6 {
                let (lo, hi) = robot.limits[i];
                assert!(s.q[i] >= lo && s.q[i] <= hi);
            }
            found |= (0..6).all(|i| (s.q[i] - q[i]).abs() < 1e-7);
        }
        assert!(
            found,
            "source joints {q:?} not among {} solutions",
            sols.len()
        );
    }
}

#[test]
fn axis_4_and_6_turns_are_enumerated() {
    let robot = Robot::irb140();
    // q4 = 170° also exists as −190°; q6 = 10° as −350° and 370°.
    let q = deg([10.0, 10.0, 10.0, 170.0, 30.0, 10.0]);
    let sols = robot.ik(&robot.fk(&q)).unwrap();
    let has = |target: [f64; 6]| {
        let t = deg(target);
        sols.iter()
            .any(|s| (0..6).all(|i| (s.q[i] - t[i]).abs() < 1e-7))
    };
    for q4 in [170.0, -190.0] {
        for q6 in [10.0, -350.0, 370.0] {
            assert!(has([10.0, 10.0, 10.0, q4, 30.0, q6]), "{q4} {q6}");
        }
    }
}

#[test]
fn robconf_of_the_check_poses() {
    let robot = Robot::irb140();
    // Calibration pose: wrist in front of axis 1 and of the lower arm,
    // axis 5 at 0 counts as positive.
    assert_eq!(robot.conf_of(&[0.0; 6]), RobConf::new(0, 0, 0, 0));
    assert_eq!(
        robot.conf_of(&deg([30.0, 20.0, -40.0, 50.0, 60.0, 70.0])),
        RobConf::new(0, 0, 0, 0)
    );
    assert_eq!(
        robot.conf_of(&deg([-100.0, 0.0, 0.0, 100.0, -10.0, -200.0])),
        RobConf::new(-2, 1, -3, 1)
    );
    // Axis 3 below −90°: the wrist is behind the lower-arm line (and,
    // 70 − 380·sin 10° = 4 mm, still in front of axis 1).
    assert_eq!(
        robot.conf_of(&deg([0.0, 0.0, -100.0, 0.0, 20.0, 0.0])).cfx,
        2
    );
    // 70 − 380·sin 30° < 0: behind axis 1 as well.
    assert_eq!(
        robot.conf_of(&deg([0.0, 0.0, -120.0, 0.0, 20.0, 0.0])).cfx,
        6
    );
    // Lower arm far back, forearm up and back: wrist centre behind axis 1
    // (x = 70 − 360·sin 80° + ... < 0).
    let q = deg([0.0, -80.0, -10.0, 0.0, 20.0, 0.0]);
    let w = robot.fk(&q) * nalgebra::Point3::new(0.0, 0.0, -65.0);
    assert!(w.x < 0.0);
    assert_eq!(robot.conf_of(&q).cfx, 4);
}

#[test]
fn conf_picks_back_the_taught_joints() {
    let robot = Robot::irb140();
    let mut rng = Rng(99);
    let mut checked = 0;
    while checked < 2000 {
        let q = rng.joints_within(&robot);
        let near_boundary = [q[0], q[3], q[5]].iter().any(|a| {
            let r = a / std::f64::consts::FRAC_PI_2;
            (r - r.round()).abs() < 1e-6
        });
        if near_boundary || q[4].abs() < 1e-3 {
            continue;
        }
        let pose = robot.fk(&q);
        let back = robot.ik_conf(&pose, &robot.conf_of(&q)).unwrap();
        for i in 0..6 {
            assert!((back[i] - q[i]).abs() < 1e-8, "{q:?} -> {back:?}");
        }
        checked += 1;
    }
}

#[test]
fn wrist_singularity_keeps_the_requested_quadrants() {
    let robot = Robot::irb140();
    // q5 = 0: only q4 + q6 matters.
    let q = deg([20.0, 10.0, -20.0, 30.0, 0.0, 40.0]);
    let pose = robot.fk(&q);
    let conf = robot.conf_of(&q);
    let back = robot.ik_conf(&pose, &conf).unwrap();
    let (dp, dr) = pose_dist(&robot.fk(&back), &pose);
    assert!(dp < 1e-9 && dr < 1e-9);
    assert_eq!(robot.conf_of(&back), conf);
    // The defined choice: q4 as close to 0 as the quadrants allow.
    assert_relative_eq!(back[3], 0.0, epsilon = 1e-12);
    assert_relative_eq!(back[5], 70f64.to_radians(), epsilon = 1e-9);
    // Ask for cf4 = 1 (q4 in 90..180°) and cf6 = -1: q4 + q6 = 70° is
    // still reachable, q4 = 90° (closest to 0 in its quadrant).
    let want = RobConf::new(conf.cf1, 1, -1, conf.cfx);
    let back = robot.ik_conf(&pose, &want).unwrap();
    assert_eq!(robot.conf_of(&back), want);
    assert_relative_eq!(back[3], 90f64.to_radians(), epsilon = 1e-9);
    assert_relative_eq!(back[3] + back[5], 70f64.to_radians(), epsilon = 1e-9);
    let (dp, dr) = pose_dist(&robot.fk(&back), &pose);
    assert!(dp < 1e-9 && dr < 1e-9);
}

#[test]
fn shoulder_singularity_takes_axis_1_from_cf1() {
    let robot = Robot::irb140();
    // Wrist centre on axis 1: lower arm tilted back so that the 70 mm
    // shoulder offset is cancelled, forearm pointing straight up.
    // x_w = 70 + 360·sin q2 (+ forearm vertical) = 0.
    let q2 = (-70.0f64 / 360.0).asin();
    // Forearm vertical up: θ2+θ3 = 0 → q3 = −q2 − 90°.
    let q = [0.3, q2, -q2 - std::f64::consts::FRAC_PI_2, 0.2, 0.5, 0.1];
    let pose = robot.fk(&q);
    let w = pose * nalgebra::Point3::new(0.0, 0.0, -65.0);
    assert!(w.x.hypot(w.y) < 1e-9);
    let arm = robot.opw.clone().unwrap();
    for cf1 in [-2, -1, 0, 1] {
        let want = RobConf::new(cf1, 0, 0, 0);
        let sols = arm.solve(&pose, &robot.limits, Some(&want)).unwrap();
        let mut seen = false;
        for s in &sols {
            let (dp, dr) = pose_dist(&robot.fk(&s.q), &pose);
            assert!(dp < 1e-6 && dr < 1e-9, "{dp} {dr}");
            seen |= s.conf.cf1 == cf1;
        }
        assert!(seen, "no solution with q1 in quadrant {cf1}");
        // q1 from the middle of the quadrant.
        let mid = (f64::from(cf1) + 0.5) * std::f64::consts::FRAC_PI_2;
        assert!(sols.iter().any(|s| (s.q[0] - mid).abs() < 1e-12));
    }
    // The taught joints' robconf gives a solution in their cf1 quadrant.
    let back = robot.ik_conf(&pose, &robot.conf_of(&q)).unwrap();
    assert_eq!(robot.conf_of(&back).cf1, 0);
    let (dp, dr) = pose_dist(&robot.fk(&back), &pose);
    assert!(dp < 1e-6 && dr < 1e-9);
}

#[test]
fn unreachable_targets_say_why() {
    let robot = Robot::irb140();
    let far = Isometry3::from_parts(
        Translation3::new(2000.0, 0.0, 500.0),
        UnitQuaternion::identity(),
    );
    let e = robot.ik(&far).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert!(e.message.contains("out of reach"), "{}", e.message);
    // Reachable geometrically, but only with the elbow folded beyond axis
    // 3's limits: wrist centre at (20, 0, 250), 114 mm from axis 2.
    let folded = Isometry3::from_parts(
        Translation3::new(20.0, 0.0, 185.0),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::PI),
    );
    let e = robot.ik(&folded).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert!(e.message.contains("joint limit"), "{}", e.message);
    assert!(
        e.notes.iter().any(|n| n.contains("axis 3")),
        "{:?}",
        e.notes
    );
    let pose = robot.fk(&[0.0; 6]);
    // A configuration the pose does not have.
    let e = robot.ik_conf(&pose, &RobConf::new(0, 0, 0, 6)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert!(
        e.notes.iter().any(|n| n.contains("[0,0,0,0]")),
        "{:?}",
        e.notes
    );
    let e = robot.ik_conf(&pose, &RobConf::new(0, 0, 0, 9)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    let nan = Isometry3::translation(f64::NAN, 0.0, 0.0);
    assert_eq!(robot.ik(&nan).unwrap_err().kind, ErrorKind::Input);
}

#[test]
fn conf_tolerance_accepts_a_joint_just_over_a_quadrant_boundary() {
    let robot = Robot::irb140();
    // Taught at q6 = 90.0° (cf6 = 1); a warm correction lands at 89.99°.
    let q = deg([10.0, 10.0, 10.0, 10.0, 30.0, 89.99]);
    let pose = robot.fk(&q);
    let want = RobConf::new(0, 0, 1, 0);
    let back = robot.ik_conf(&pose, &want).unwrap();
    assert_relative_eq!(back[5], q[5], epsilon = 1e-9);
    // Too far outside the quadrant: refused.
    let q = deg([
        10.0,
        10.0,
        10.0,
        10.0,
        30.0,
        89.0 - CONF_TOLERANCE.to_degrees(),
    ]);
    assert!(robot.ik_conf(&robot.fk(&q), &want).is_err());
}

#[test]
fn warm_ik_inverts_warm_fk() {
    let robot = Robot::irb140();
    let scales = ThermalExpansion::default().scales(&TABLE1_TMAX);
    let mut rng = Rng(5);
    for _ in 0..500 {
        let q = rng.joints_within(&robot);
        if q[4].abs() < 1e-3 {
            continue;
        }
        let pose = robot.fk_scaled(&q, &scales);
        let back = robot.ik_conf_scaled(&pose, &robot.conf_of(&q), &scales);
        let back = match back {
            Ok(b) => b,
            // Near a quadrant boundary the nominal robconf may differ.
            Err(_) => continue,
        };
        let (dp, dr) = pose_dist(&robot.fk_scaled(&back, &scales), &pose);
        assert!(dp < 1e-9 && dr < 1e-9);
        for i in 0..6 {
            assert!(wrap(back[i] - q[i]).abs() < 1e-8);
        }
    }
}

/// Flange drift at the calibration pose with the table-1 maxima and T_ref
/// 7 °C, computed by hand from docs/model.md's table:
/// base 18.837 → ΔT 11.837; lower (21.596+18.849)/2 = 20.2225 → 13.2225;
/// upper (21.665+27.537+30.705)/3 = 26.635667 → 19.635667;
/// wrist (27.537+30.705)/2 = 29.121 → 22.121. With α = 21.8e-6/K:
/// Δa1 = 70·α·11.837 = 0.0180633, Δc1 = 352·α·11.837 = 0.0908324,
/// Δc2 = 360·α·13.2225 = 0.1037702, Δc3 = 380·α·19.635667 = 0.1626619,
/// Δc4 = 65·α·22.121 = 0.0313455.
/// Δx = Δa1 + Δc3 + Δc4 = 0.2120706, Δz = Δc1 + Δc2 = 0.1946026,
/// |Δ| = 0.2878265 mm with the base model (K0 = 1); the FEA gives 0.097 mm.
#[test]
fn calibration_pose_drift_with_table1_temperatures() {
    let robot = Robot::irb140();
    let cold = robot.fk(&[0.0; 6]);
    let base = ThermalExpansion {
        k0: 1.0,
        ..Default::default()
    };
    let warm = robot.fk_scaled(&[0.0; 6], &base.scales(&TABLE1_TMAX));
    let d = warm.translation.vector - cold.translation.vector;
    assert_relative_eq!(d.x, 0.2120706, epsilon = 1e-6);
    assert_relative_eq!(d.y, 0.0, epsilon = 1e-12);
    assert_relative_eq!(d.z, 0.1946026, epsilon = 1e-6);
    assert_relative_eq!(d.norm(), 0.2878265, epsilon = 1e-6);
    // Expansion moves positions only.
    assert!(warm.rotation.angle_to(&cold.rotation) < 1e-15);
}

/// The calibrated default (`data/irb140/model.toml`, K0 = 0.33699) moves
/// the flange 0.097 mm at the calibration pose with the table-1
/// temperatures: the FEA's number (`docs/model.md`, "Calibrated
/// default"), and `--model base` keeps docs/model.md's unscaled 0.2878 mm.
#[test]
fn the_calibrated_default_drifts_as_the_fea_says() {
    let robot = Robot::irb140();
    let drift = |m: &rapidtherm::model::Model| {
        let warm = robot.fk_scaled(&[0.0; 6], &m.thermal.scales(&TABLE1_TMAX));
        (warm.translation.vector - robot.fk(&[0.0; 6]).translation.vector).norm()
    };
    let default = rapidtherm::model::Model::default();
    assert_eq!(default.thermal.k0, 0.33699);
    assert_relative_eq!(drift(&default), 0.097, epsilon = 5e-5);
    let base = rapidtherm::model::Model::named("base").unwrap();
    assert_relative_eq!(drift(&base), 0.2878265, epsilon = 1e-6);
}

#[test]
fn thermal_model_is_data() {
    let text = "t_ref = 20.0\n\
        [base]\nalpha = 11.5e-6\nmotors = [1]\n\
        [lower_arm]\nalpha = 21.8e-6\nmotors = [2, 3]\n\
        [upper_arm]\nalpha = 21.8e-6\nmotors = [4]\n\
        [wrist]\nalpha = 0.0\nmotors = [6]\n";
    let th = ThermalExpansion::from_toml("m.toml", text).unwrap();
    assert_eq!(th.t_ref, 20.0);
    let warm = th.expand(&irb140_opw(), &[30.0, 20.0, 20.0, 40.0, 0.0, 99.0]);
    assert_relative_eq!(warm.c1, 352.0 * (1.0 + 11.5e-6 * 10.0), epsilon = 1e-12);
    assert_relative_eq!(warm.c3, 380.0 * (1.0 + 21.8e-6 * 20.0), epsilon = 1e-12);
    assert_eq!(warm.c4, 65.0);
    let robot = Robot::irb140();
    let t = [30.0, 20.0, 20.0, 20.0, 20.0, 20.0];
    let d = robot
        .fk_scaled(&[0.0; 6], &th.scales(&t))
        .translation
        .vector
        - robot.fk(&[0.0; 6]).translation.vector;
    assert_relative_eq!(d.z, 352.0 * 11.5e-6 * 10.0, epsilon = 1e-12);
    assert_relative_eq!(d.x, 70.0 * 11.5e-6 * 10.0, epsilon = 1e-12);

    let bad = "t_ref = 7.0\n[base]\nalpha = 1e-6\nmotors = [7]\n\
        [lower_arm]\nalpha = 1e-6\nmotors = [2]\n\
        [upper_arm]\nalpha = 1e-6\nmotors = [4]\n[wrist]\nalpha = 1e-6\nmotors = [5]\n";
    let e = ThermalExpansion::from_toml("m.toml", bad).unwrap_err();
    assert!(e.message.contains("base.motors"), "{}", e.message);
    let typo = "t_ref = 7.0\ntref = 3\n";
    let e = ThermalExpansion::from_toml("m.toml", typo).unwrap_err();
    assert_eq!(e.location.as_ref().map(|l| l.line), Some(2));
}

#[test]
fn near_the_wrist_singularity_every_solution_still_reaches_the_pose() {
    let robot = Robot::irb140();
    for q5 in [
        0.0, 1e-14, 1e-12, 1e-11, 1e-9, 1e-7, 1e-5, -1e-12, -1e-9, -1e-5,
    ] {
        let q = [0.4, 0.3, -0.2, 1.0, q5, -0.5];
        let pose = robot.fk(&q);
        let sols = robot.ik(&pose).unwrap();
        for s in &sols {
            let (dp, dr) = pose_dist(&robot.fk(&s.q), &pose);
            assert!(dp < 1e-9 && dr < 1e-9, "q5 {q5}: {dp} mm {dr} rad");
        }
        let back = robot.ik_conf(&pose, &robot.conf_of(&q)).unwrap();
        let (dp, dr) = pose_dist(&robot.fk(&back), &pose);
        assert!(dp < 1e-9 && dr < 1e-9, "q5 {q5}: {dp} mm {dr} rad");
    }
}

#[test]
fn the_most_solutions_the_irb140_can_have_fit_the_buffer() {
    // Axis 1 exactly at 180° (both ±180° are within the limits), axis 4 at
    // 170° (also −190°), axis 6 at 10° (also ±350°/370°).
    let robot = Robot::irb140();
    let q = deg([180.0, 10.0, 10.0, 170.0, 30.0, 10.0]);
    let sols = robot.ik(&robot.fk(&q)).unwrap();
    assert!(sols.len() < rapidtherm::robot::ik::MAX_SOLUTIONS);
    assert!(sols.len() >= 12, "{}", sols.len());
    let has = |t: [f64; 6]| {
        let t = deg(t);
        sols.iter()
            .any(|s| (0..6).all(|i| (s.q[i] - t[i]).abs() < 1e-7))
    };
    assert!(has([180.0, 10.0, 10.0, 170.0, 30.0, 10.0]));
    assert!(has([-180.0, 10.0, 10.0, -190.0, 30.0, 370.0]));
}
