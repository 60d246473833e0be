//! Every refusal for reach or joint limits names the arm it used and
//! carries the remedy of another arm (issue 49): a program written for a
//! larger arm is otherwise refused as if the pose were wrong.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rapidtherm::error::{ErrorKind, Remedy};
use rapidtherm::robot::{RobConf, Robot};

fn far() -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(2000.0, 0.0, 500.0),
        UnitQuaternion::identity(),
    )
}

#[test]
fn out_of_reach_names_the_arm_and_another_arm_as_the_remedy() {
    for name in ["IRB 140", "IRB 1200-5/0.9"] {
        let robot = Robot::abb(name).unwrap();
        // 2 m out: beyond either arm (0.81 and 0.9 m).
        let e = robot.ik(&far()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Unreachable);
        assert!(
            e.message.contains(&format!("; the arm {name} reaches ")),
            "{}",
            e.message
        );
        assert_eq!(e.remedy, Some((Remedy::AnotherArm, None)), "{name}");
        assert!(
            e.to_string()
                .ends_with("mm; a program for another arm: name that arm"),
            "{e}"
        );
    }
}

#[test]
fn joint_limit_refusals_name_the_arm() {
    let robot = Robot::abb("irb140").unwrap();
    // Reachable only with the elbow folded beyond axis 3's limits (as in
    // kinematics.rs): the limits refuse it.
    let folded = Isometry3::from_parts(
        Translation3::new(20.0, 0.0, 185.0),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::PI),
    );
    let e = robot.ik(&folded).unwrap_err();
    assert_eq!(
        e.message,
        "every solution violates a joint limit of the arm IRB 140"
    );
    assert_eq!(e.remedy, Some((Remedy::AnotherArm, Some(0))));
    // A robconf the pose has no solution of within the limits.
    let pose = robot.fk(&[0.0; 6]);
    let e = robot.ik_conf(&pose, &RobConf::new(0, 0, 0, 6)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unreachable);
    assert!(e.message.ends_with("of the arm IRB 140"), "{}", e.message);
    assert!(
        matches!(e.remedy, Some((Remedy::AnotherArm, _))),
        "{:?}",
        e.remedy
    );
}
