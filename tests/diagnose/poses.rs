//! Poses for simulated measurements: the ISO 9283 cube and a program's
//! targets, solved by inverse kinematics and checked by forward kinematics.

use nalgebra::Vector3;
use rapidtherm::diagnose::arm::{Arm, IsoCube};
use rapidtherm::diagnose::simulate::{iso_cube_poses, program_poses};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::robot::Robot;

#[test]
fn iso_cube_points_lie_on_the_diagonal_plane_at_ten_percent_from_the_corners() {
    let robot = Robot::irb140();
    let cube = IsoCube {
        centre: [480.0, 0.0, 450.0],
        side: 300.0,
    };
    let poses = iso_cube_poses(&robot, &cube).unwrap();
    let names: Vec<&str> = poses.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["P1", "P2", "P3", "P4", "P5"]);
    let expected = [
        [480.0, 0.0, 450.0],
        [360.0, -120.0, 330.0],
        [360.0, 120.0, 330.0],
        [600.0, 120.0, 570.0],
        [600.0, -120.0, 570.0],
    ];
    for ((name, q), e) in poses.iter().zip(expected) {
        let f = robot.fk(q);
        let miss = (f.translation.vector - Vector3::from(e)).norm();
        assert!(miss < 1e-9, "{name}: {miss} mm off");
        // Tool pointing down.
        let z = f.rotation * Vector3::z();
        assert!((z + Vector3::z()).norm() < 1e-9, "{name}: tool axis {z:?}");
        assert_eq!(robot.conf_of(q).cfx, 0, "{name}: natural configuration");
    }
}

/// The IRB 140's own cube (scaled to its reach like every arm's) is
/// reachable with the tool down in the natural configuration.
#[test]
fn irb140_iso_cube_is_reachable() {
    let robot = Robot::irb140();
    let cube = Arm::of_model(&Model::default())
        .unwrap()
        .iso_cube()
        .unwrap();
    let poses = iso_cube_poses(&robot, &cube).unwrap();
    assert_eq!(poses.len(), 5);
    let f = robot.fk(&poses[0].1);
    assert!((f.translation.vector - Vector3::from(cube.centre)).norm() < 1e-9);
}

#[test]
fn program_poses_reach_the_program_targets() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/cmd/correct_data/cell.mod"
    );
    let bytes = std::fs::read(path).unwrap();
    let program = rapid::parse("cell.mod", &bytes).unwrap();
    let robot = Robot::irb140();
    let poses = program_poses(&program, &robot).unwrap();
    let names: Vec<&str> = poses.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["p10", "p20", "main#1"]);
    // main#1 is [450,100,500] with tool0 in wobj0: the flange itself.
    let f = robot.fk(&poses[2].1);
    assert!((f.translation.vector - Vector3::new(450.0, 100.0, 500.0)).norm() < 1e-9);
    // p10 is [100,150,380] in wTable (origin 400,-200,100) with a 120 mm
    // tool pointing down: flange 120 mm above the TCP.
    let f = robot.fk(&poses[0].1);
    assert!((f.translation.vector - Vector3::new(500.0, -50.0, 600.0)).norm() < 1e-9);
}
