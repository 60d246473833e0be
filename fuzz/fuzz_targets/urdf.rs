//! Any bytes as a URDF: the reader returns an arm or an error, never
//! panics, overflows its stack or hangs; an arm it returns is finite, so
//! that its kinematics at the zero pose are finite too.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rapidtherm::robot::Robot;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(robot) = Robot::from_urdf_str("fuzz.urdf", text) {
        let pose = robot.chain.fk(&[0.0; 6]);
        assert!(pose.translation.vector.iter().all(|v| v.is_finite()));
    }
});
