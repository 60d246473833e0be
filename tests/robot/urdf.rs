//! Other arms from URDF files: forward kinematics for any serial chain,
//! OPW parameters (signs, offsets, flange rotation) extracted where the
//! arm has that shape, and clear errors where it has not.

use nalgebra::{Isometry3, Quaternion, UnitQuaternion};
use rapidtherm::error::ErrorKind;
use rapidtherm::model::ThermalExpansion;
use rapidtherm::robot::Robot;
use rs_opw_kinematics::kinematic_traits::Kinematics;
use rs_opw_kinematics::kinematics_impl::OPWKinematics;
use rs_opw_kinematics::parameters::opw_kinematics::Parameters;

const LIM: &str = r#"<limit lower="-3.0" upper="3.0" effort="0" velocity="2.0"/>"#;

/// A URDF from (name, type, parent, child, xyz, rpy, axis) rows.
fn urdf(joints: &[(&str, &str, &str, &str, &str, &str, &str)]) -> String {
    let mut links: Vec<&str> = Vec::new();
    for j in joints {
        for l in [j.2, j.3] {
            if !links.contains(&l) {
                links.push(l);
            }
        }
    }
    let mut s = String::from("<?xml version=\"1.0\"?>\n<robot name=\"test_arm\">\n");
    for l in links {
        s += &format!("  <link name=\"{l}\"/>\n");
    }
    for (name, ty, parent, child, xyz, rpy, axis) in joints {
        s += &format!(
            "  <joint name=\"{name}\" type=\"{ty}\"><parent link=\"{parent}\"/><child link=\"{child}\"/><origin xyz=\"{xyz}\" rpy=\"{rpy}\"/>"
        );
        if *ty != "fixed" {
            s += &format!("<axis xyz=\"{axis}\"/>{LIM}");
        }
        s += "</joint>\n";
    }
    s + "</robot>\n"
}

/// The ABB IRB 120 as ROS-Industrial describes it.
fn irb120() -> String {
    urdf(&[
        (
            "joint_1",
            "revolute",
            "base_link",
            "link_1",
            "0 0 0",
            "0 0 0",
            "0 0 1",
        ),
        (
            "joint_2", "revolute", "link_1", "link_2", "0 0 0.29", "0 0 0", "0 1 0",
        ),
        (
            "joint_3", "revolute", "link_2", "link_3", "0 0 0.27", "0 0 0", "0 1 0",
        ),
        (
            "joint_4", "revolute", "link_3", "link_4", "0 0 0.07", "0 0 0", "1 0 0",
        ),
        (
            "joint_5",
            "revolute",
            "link_4",
            "link_5",
            "0.302 0 0",
            "0 0 0",
            "0 1 0",
        ),
        (
            "joint_6",
            "revolute",
            "link_5",
            "link_6",
            "0.072 0 0",
            "0 0 0",
            "1 0 0",
        ),
        (
            "joint_6-tool0",
            "fixed",
            "link_6",
            "tool0",
            "0 0 0",
            "0 1.5707963267948966 0",
            "",
        ),
    ])
}

use crate::rng::Rng;

fn dist(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

fn assert_ik_round_trips(robot: &Robot, seed: u64) {
    let mut rng = Rng(seed);
    for _ in 0..300 {
        let q = rng.joints_within(robot);
        let pose = robot.fk(&q);
        let (dp, dr) = dist(&pose, &robot.chain.fk(&q));
        assert!(dp < 1e-9 && dr < 1e-12, "OPW vs chain {dp} {dr}");
        let sols = robot.ik(&pose).unwrap();
        assert!(sols
            .iter()
            .any(|s| (0..6).all(|i| (s.q[i] - q[i]).abs() < 1e-7)));
        for s in &sols {
            let (dp, dr) = dist(&robot.fk(&s.q), &pose);
            assert!(dp < 1e-8 && dr < 1e-9, "{dp} {dr}");
        }
    }
}

#[test]
fn irb120_matches_the_rs_opw_kinematics_preset() {
    let robot = Robot::from_urdf_str("irb120.urdf", &irb120()).unwrap();
    let arm = robot.opw.clone().unwrap();
    let p = Parameters::irb120_3_58();
    // Its preset is in metres, ours in mm.
    assert!((arm.geom.a2 - p.a2 * 1000.0).abs() < 1e-9, "{:?}", arm.geom);
    assert!((arm.geom.c3 - p.c3 * 1000.0).abs() < 1e-9);
    let reference = OPWKinematics::new(p);
    let mut rng = Rng(3);
    for _ in 0..1000 {
        let q = rng.joints_within(&robot);
        let theirs = reference.forward(&q);
        let t = theirs.translation * 1000.0;
        let r = theirs.rotation;
        let theirs = Isometry3::from_parts(
            nalgebra::Translation3::new(t.x, t.y, t.z),
            UnitQuaternion::from_quaternion(Quaternion::new(r.w, r.x, r.y, r.z)),
        );
        let (dp, dr) = dist(&robot.fk(&q), &theirs);
        assert!(dp < 1e-9 && dr < 1e-12, "{dp} {dr}");
    }
    assert_ik_round_trips(&robot, 4);
}

#[test]
fn reversed_axes_split_lengths_and_extra_fixed_frames_are_understood() {
    // The IRB 140 written differently: a fixed base frame, axis 3 and
    // axis 5 pointing the other way, the upper arm split over joints 4 and
    // 5, a flange link and a tool0 turned about the flange axis.
    let text = urdf(&[
        (
            "base_link-base",
            "fixed",
            "base_link",
            "base",
            "0 0 0",
            "0 0 0",
            "",
        ),
        (
            "joint_1", "revolute", "base", "link_1", "0 0 0.1", "0 0 0", "0 0 1",
        ),
        (
            "joint_2",
            "revolute",
            "link_1",
            "link_2",
            "0.070 0 0.252",
            "0 0 0",
            "0 1 0",
        ),
        (
            "joint_3",
            "revolute",
            "link_2",
            "link_3",
            "0 0 0.360",
            "0 0 0",
            "0 -1 0",
        ),
        (
            "joint_4", "revolute", "link_3", "link_4", "0.2 0 0", "0 0 0", "1 0 0",
        ),
        (
            "joint_5", "revolute", "link_4", "link_5", "0.18 0 0", "0 0 0", "0 -1 0",
        ),
        (
            "joint_6", "revolute", "link_5", "link_6", "0 0 0", "0 0 0", "1 0 0",
        ),
        (
            "link_6-flange",
            "fixed",
            "link_6",
            "flange",
            "0.065 0 0",
            "0 0 0",
            "",
        ),
        (
            "flange-tool0",
            "fixed",
            "flange",
            "tool0",
            "0 0 0",
            "0.3 1.5707963267948966 0",
            "",
        ),
    ]);
    let robot = Robot::from_urdf_str("variant.urdf", &text).unwrap();
    let arm = robot.opw.clone().unwrap();
    assert_eq!(arm.signs, [1.0, 1.0, -1.0, 1.0, -1.0, 1.0]);
    assert!((arm.geom.c1 - 352.0).abs() < 1e-9);
    assert!((arm.geom.c3 - 380.0).abs() < 1e-9);
    assert!((arm.geom.c4 - 65.0).abs() < 1e-9);
    assert_ik_round_trips(&robot, 8);
    // Thermal scaling of a general chain follows its segments: at the
    // calibration pose c1 and a1 grow with T1 only.
    let d = robot
        .fk_scaled(
            &[0.0; 6],
            &ThermalExpansion::default().scales(&[17.0, 7.0, 7.0, 7.0, 7.0, 7.0]),
        )
        .translation
        .vector
        - robot.fk(&[0.0; 6]).translation.vector;
    let k0 = ThermalExpansion::default().k0;
    assert!((d.z - 352.0 * k0 * 21.8e-6 * 10.0).abs() < 1e-12, "{d}");
    assert!((d.x - 70.0 * k0 * 21.8e-6 * 10.0).abs() < 1e-12, "{d}");
}

#[test]
fn an_arm_without_a_spherical_wrist_has_fk_and_numeric_ik() {
    let text = urdf(&[
        (
            "joint_1",
            "revolute",
            "base_link",
            "link_1",
            "0 0 0",
            "0 0 0",
            "0 0 1",
        ),
        (
            "joint_2",
            "revolute",
            "link_1",
            "link_2",
            "0.070 0 0.352",
            "0 0 0",
            "0 1 0",
        ),
        (
            "joint_3",
            "revolute",
            "link_2",
            "link_3",
            "0 0 0.360",
            "0 0 0",
            "0 1 0",
        ),
        (
            "joint_4", "revolute", "link_3", "link_4", "0 0 0", "0 0 0", "1 0 0",
        ),
        (
            "joint_5",
            "revolute",
            "link_4",
            "link_5",
            "0.380 0 0",
            "0 0 0",
            "0 1 0",
        ),
        (
            "joint_6",
            "revolute",
            "link_5",
            "link_6",
            "0.065 0.03 0",
            "0 0 0",
            "1 0 0",
        ),
    ]);
    let robot = Robot::from_urdf_str("offset_wrist.urdf", &text).unwrap();
    let why = robot.opw.clone().unwrap_err();
    assert!(why.contains("spherical wrist"), "{why}");
    // FK through the chain: at zero the flange (link_6) is at
    // (70 + 380 + 65, 30, 712) mm.
    let p = robot.fk(&[0.0; 6]).translation.vector;
    assert!((p - nalgebra::Vector3::new(515.0, 30.0, 712.0)).norm() < 1e-9);
    // No closed form: the numeric IK (`tests/robot/ik_chain.rs`) finds
    // the joints back.
    let q = [0.1, 0.2, -0.3, 0.4, 0.5, 0.6];
    let back = robot.ik_conf(&robot.fk(&q), &robot.conf_of(&q)).unwrap();
    assert!(
        back.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9),
        "{back:?}"
    );
    let e = robot.opw_arm(None).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported);
    assert!(e.message.contains("spherical wrist"), "{}", e.message);
}

#[test]
fn urdf_errors_name_the_problem() {
    let e = Robot::from_urdf_str("x.urdf", "<robot name=").unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    // Named with its place: `x.urdf:1:…: error: …`.
    assert!(e.to_string().starts_with("x.urdf:1:"), "{e}");

    let five = urdf(&[
        (
            "joint_1",
            "revolute",
            "base_link",
            "link_1",
            "0 0 0",
            "0 0 0",
            "0 0 1",
        ),
        (
            "joint_2", "revolute", "link_1", "link_2", "0 0 0.3", "0 0 0", "0 1 0",
        ),
        (
            "joint_3", "revolute", "link_2", "link_3", "0 0 0.3", "0 0 0", "0 1 0",
        ),
        (
            "joint_4", "revolute", "link_3", "link_4", "0 0 0", "0 0 0", "1 0 0",
        ),
        (
            "joint_5", "revolute", "link_4", "tool0", "0.3 0 0", "0 0 0", "0 1 0",
        ),
    ]);
    let e = Robot::from_urdf_str("five.urdf", &five).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    assert!(e.message.contains("5 revolute joints"), "{}", e.message);

    let slider = irb120().replace(
        r#"name="joint_3" type="revolute""#,
        r#"name="joint_3" type="prismatic""#,
    );
    let e = Robot::from_urdf_str("slider.urdf", &slider).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported);
    assert!(e.message.contains("joint_3"), "{}", e.message);

    let no_limits = irb120().replacen(LIM, r#"<limit effort="0" velocity="1"/>"#, 1);
    let e = Robot::from_urdf_str("nolim.urdf", &no_limits).unwrap_err();
    assert!(e.message.contains("joint_1"), "{}", e.message);

    let zero_axis = irb120().replacen(r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="0 0 0"/>"#, 1);
    let e = Robot::from_urdf_str("axis.urdf", &zero_axis).unwrap_err();
    assert!(e.message.contains("axis"), "{}", e.message);
}

#[test]
fn robconf_finds_turns_beyond_the_all_solutions_buffer() {
    // Every axis ±12 rad (±688°): thousands of turn combinations, far more
    // than the all-solutions buffer; the robconf still picks the taught one.
    let text = irb120().replace(
        LIM,
        r#"<limit lower="-12.0" upper="12.0" effort="0" velocity="2.0"/>"#,
    );
    let robot = Robot::from_urdf_str("wide.urdf", &text).unwrap();
    let q = [0.5, 0.3, 0.2, 11.0, 0.7, -10.0];
    let pose = robot.fk(&q);
    let all = robot.ik(&pose).unwrap();
    assert_eq!(all.len(), rapidtherm::robot::ik::MAX_SOLUTIONS);
    let back = robot.ik_conf(&pose, &robot.conf_of(&q)).unwrap();
    // robconf fixes the turns of axes 1, 4 and 6 (axes 2, 3, 5 of an ABB
    // arm cannot turn a full circle, this test arm can).
    for i in [0, 3, 5] {
        assert!((back[i] - q[i]).abs() < 1e-9, "{back:?}");
    }
    let (dp, dr) = dist(&robot.fk(&back), &pose);
    assert!(dp < 1e-9 && dr < 1e-9);
}

#[test]
fn meshes_are_ignored_not_resolved() {
    let text = irb120().replace(
        r#"<link name="link_1"/>"#,
        r#"<link name="link_1"><visual><geometry><mesh filename="package://abb_irb120_support/meshes/link_1.stl"/></geometry></visual><inertial><mass value="3.0"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>"#,
    );
    assert!(text.contains("package://"));
    let robot = Robot::from_urdf_str("meshes.urdf", &text).unwrap();
    assert!(robot.opw.is_ok());
}
