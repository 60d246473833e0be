//! Work objects and tools: robtarget → flange → joints (with the target's
//! robconf) → flange → robtarget reproduces the target, for the kinds of
//! tooldata and wobjdata RAPID programs use.

// Quaternions as RAPID programs print them (0.7071, not 1/√2): on purpose.
#![allow(clippy::approx_constant)]

use nalgebra::{Isometry3, Point3};
use rapidtherm::error::ErrorKind;
use rapidtherm::model::ThermalExpansion;
use rapidtherm::robot::frames::{
    flange_of_target, pose_from_rapid, pose_to_rapid, target_of_flange, ToolFrame, WobjFrames,
};
use rapidtherm::robot::{RobConf, Robot};

/// `tool1 := [TRUE,[[97.4,0,223.1],[0.924,0,0.383,0]],[5,[23,0,75],[1,0,0,0],0,0,0]]`:
/// a bent welding torch; its quaternion is printed to 3 decimals (norm
/// 1.0002), as in real programs.
fn torch() -> ToolFrame {
    ToolFrame::new(true, [97.4, 0.0, 223.1], [0.924, 0.0, 0.383, 0.0]).unwrap()
}

/// `wobj1 := [FALSE,TRUE,"",[[600,-200,300],[0.7071,0,0,0.7071]],[[10,20,0],[0.9962,0,0,0.0872]]]`:
/// a fixture turned 90° with an object frame turned 10° more.
fn fixture() -> WobjFrames {
    WobjFrames::new(
        false,
        true,
        "",
        ([600.0, -200.0, 300.0], [0.7071, 0.0, 0.0, 0.7071]),
        ([10.0, 20.0, 0.0], [0.9962, 0.0, 0.0, 0.0872]),
    )
    .unwrap()
}

/// Stationary tool: a grinder fixed in the cell,
/// `tool_st := [FALSE,[[700,100,400],[0,0.7071,0.7071,0]],...]`, and the
/// part held by the robot, `wobj_part := [TRUE,TRUE,"",[[0,0,80],[1,0,0,0]],[[0,0,0],[1,0,0,0]]]`.
fn grinder() -> (ToolFrame, WobjFrames) {
    (
        ToolFrame::new(false, [700.0, 100.0, 400.0], [0.0, 0.7071, 0.7071, 0.0]).unwrap(),
        WobjFrames::new(
            true,
            true,
            "",
            ([0.0, 0.0, 80.0], [1.0, 0.0, 0.0, 0.0]),
            ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]),
        )
        .unwrap(),
    )
}

fn round_trip(target: &Isometry3<f64>, conf: RobConf, tool: &ToolFrame, wobj: &WobjFrames) -> f64 {
    let robot = Robot::irb140();
    let flange = flange_of_target(target, tool, wobj).unwrap();
    let q = robot.ik_conf(&flange, &conf).unwrap();
    let reached = robot.fk(&q);
    let back = target_of_flange(&reached, tool, wobj).unwrap();
    assert!(back.rotation.angle_to(&target.rotation) < 1e-12);
    (back.translation.vector - target.translation.vector).norm()
}

#[test]
fn robot_held_tool_in_a_work_object_round_trips() {
    let robot = Robot::irb140();
    let tool = torch();
    let wobj = fixture();
    // Targets made from reachable joints, expressed in the program's frames.
    for q in [
        [10.0, 20.0, 10.0, 30.0, 40.0, 50.0],
        [-40.0, 35.0, -10.0, -120.0, 70.0, 200.0],
        [60.0, -10.0, 20.0, 5.0, -60.0, -30.0],
    ] {
        let q = q.map(f64::to_radians);
        let target = target_of_flange(&robot.fk(&q), &tool, &wobj).unwrap();
        let err = round_trip(&target, robot.conf_of(&q), &tool, &wobj);
        assert!(err < 1e-9, "{err} mm");
    }
}

#[test]
fn stationary_tool_round_trips() {
    let robot = Robot::irb140();
    let (tool, wobj) = grinder();
    for q in [
        [10.0, 20.0, 10.0, 30.0, 40.0, 50.0],
        [-20.0, 5.0, 30.0, 100.0, -50.0, -100.0],
    ] {
        let q = q.map(f64::to_radians);
        let target = target_of_flange(&robot.fk(&q), &tool, &wobj).unwrap();
        let err = round_trip(&target, robot.conf_of(&q), &tool, &wobj);
        assert!(err < 1e-9, "{err} mm");
    }
}

#[test]
fn frames_compose_as_rapid_defines() {
    // tool0/wobj0: the target is the flange.
    let t = pose_from_rapid([500.0, 10.0, 600.0], [0.5, 0.5, 0.5, 0.5]).unwrap();
    let f = flange_of_target(&t, &ToolFrame::tool0(), &WobjFrames::wobj0()).unwrap();
    assert!((f.translation.vector - t.translation.vector).norm() < 1e-12);
    // A tool 100 mm along the flange z: the flange is 100 mm back along
    // the target's z, which (identity target in a wobj at x = 600) is −z.
    let tool = ToolFrame::new(true, [0.0, 0.0, 100.0], [1.0, 0.0, 0.0, 0.0]).unwrap();
    let wobj = WobjFrames::new(
        false,
        true,
        "",
        ([600.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]),
        ([0.0, 0.0, 50.0], [1.0, 0.0, 0.0, 0.0]),
    )
    .unwrap();
    let f = flange_of_target(&Isometry3::identity(), &tool, &wobj).unwrap();
    assert!((f * Point3::origin() - Point3::new(600.0, 0.0, -50.0)).norm() < 1e-12);
    // Stationary tool: the TCP (in world) is where the object's target
    // sits, so flange · uframe · oframe · target = tframe.
    let (st, part) = grinder();
    let target = pose_from_rapid([5.0, -3.0, 20.0], [0.0, 1.0, 0.0, 0.0]).unwrap();
    let f = flange_of_target(&target, &st, &part).unwrap();
    let tcp = f * part.object_frame() * target;
    assert!((tcp.translation.vector - st.tframe.translation.vector).norm() < 1e-12);
    assert!(tcp.rotation.angle_to(&st.tframe.rotation) < 1e-12);
}

#[test]
fn quaternions_are_normalised_and_printed_with_q1_positive() {
    let p = pose_from_rapid([1.0, 2.0, 3.0], [0.70711, 0.0, 0.70711, 0.0]).unwrap();
    assert!((p.rotation.quaternion().norm() - 1.0).abs() < 1e-15);
    let (_, q) = pose_to_rapid(&pose_from_rapid([0.0; 3], [-0.5, 0.5, -0.5, 0.5]).unwrap());
    assert_eq!(q, [0.5, -0.5, 0.5, -0.5]);
    let e = pose_from_rapid([0.0; 3], [0.0; 4]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    let e = pose_from_rapid([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
}

#[test]
fn moving_and_inconsistent_frames_are_refused() {
    let mut wobj = fixture();
    wobj.ufprog = false;
    wobj.ufmec = "STN1".into();
    let e = flange_of_target(&Isometry3::identity(), &torch(), &wobj).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported);
    assert!(e.message.contains("STN1"));
    let e = target_of_flange(&Isometry3::identity(), &torch(), &wobj).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported);
    // Robot holding both tool and object.
    let (_, part) = grinder();
    let e = flange_of_target(&Isometry3::identity(), &torch(), &part).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
    // Stationary tool with a stationary object.
    let (st, _) = grinder();
    let e = flange_of_target(&Isometry3::identity(), &st, &fixture()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Input);
}

#[test]
fn warm_correction_through_the_programs_frames() {
    // What a correction does: the joints the cold program meant, where the
    // warm arm puts the tool with them, and the target that brings the warm
    // arm back to the cold position.
    let robot = Robot::irb140();
    let (tool, wobj) = (torch(), fixture());
    let temps = rapidtherm::thermal::TABLE1_TMAX;
    let q = [15.0, 25.0, 5.0, 20.0, 50.0, 30.0].map(f64::to_radians);
    let conf = robot.conf_of(&q);
    let target = robot.target_of_joints(&q, &tool, &wobj).unwrap();
    let q_cold = robot.target_joints(&target, &conf, &tool, &wobj).unwrap();
    let scales = ThermalExpansion::default().scales(&temps);
    let warm = target_of_flange(&robot.fk_scaled(&q_cold, &scales), &tool, &wobj).unwrap();
    let drift = (warm.translation.vector - target.translation.vector).norm();
    assert!(drift > 0.03 && drift < 1.0, "{drift} mm");
    // Joints for the target on the warm arm reach the cold position warm.
    let flange = flange_of_target(&target, &tool, &wobj).unwrap();
    let q_warm = robot.ik_conf_scaled(&flange, &conf, &scales).unwrap();
    let reached = target_of_flange(&robot.fk_scaled(&q_warm, &scales), &tool, &wobj).unwrap();
    assert!((reached.translation.vector - target.translation.vector).norm() < 1e-9);
    assert!(reached.rotation.angle_to(&target.rotation) < 1e-12);
}
