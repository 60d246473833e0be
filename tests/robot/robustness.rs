//! Nothing panics on any input: arbitrary poses (huge, tiny, NaN,
//! unnormalised quaternions), temperatures, robconfs and URDF text give a
//! value or an error.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};
use proptest::prelude::*;
use rapidtherm::model::ThermalExpansion;
use rapidtherm::robot::frames::pose_from_rapid;
use rapidtherm::robot::urdf::IRB140_URDF;
use rapidtherm::robot::{RobConf, Robot};

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        -2000.0f64..2000.0,
        Just(0.0),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(-1e300),
        Just(1e-300),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn ik_never_panics_and_its_solutions_are_exact(
        x in any_f64(), y in any_f64(), z in any_f64(),
        w in -1.0f64..1.0, i in -1.0f64..1.0, j in -1.0f64..1.0, k in -1.0f64..1.0,
        temps in proptest::option::of(proptest::array::uniform6(-50.0f64..200.0)),
        conf in proptest::array::uniform4(-6i32..8),
    ) {
        let robot = Robot::irb140();
        let q = Quaternion::new(w, i, j, k);
        prop_assume!(q.norm() > 1e-6);
        // Non-finite translations go straight in (IK must refuse them).
        let pose = Isometry3::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_quaternion(q),
        );
        // Cold (unit scales) or warm: the arm's segments scaled by the
        // default thermal model at any temperatures.
        let scales = temps.map_or([1.0; 4], |t| ThermalExpansion::default().scales(&t));
        if let Ok(sols) = robot.ik_scaled(&pose, &scales) {
            for s in &sols {
                let back = robot.fk_scaled(&s.q, &scales);
                let d = (back.translation.vector - pose.translation.vector).norm();
                prop_assert!(d < 1e-6, "{d}");
            }
        }
        let _ = robot.ik_conf_scaled(&pose, &RobConf::new(conf[0], conf[1], conf[2], conf[3]), &scales);
        let _ = pose_from_rapid([x, y, z], [w, i, j, k]);
    }

    #[test]
    fn urdf_reader_never_panics(cut in 0usize..4000, pos in 0usize..4000, junk in "[ <>/=\"a-z0-9.-]{0,12}") {
        let text = IRB140_URDF;
        let cut = cut.min(text.len());
        let pos = pos.min(text.len());
        let mut s: String = text.chars().take(cut).collect();
        s.push_str(&text.chars().skip(cut + junk.len().min(3)).collect::<String>());
        let pos = pos.min(s.len());
        if s.is_char_boundary(pos) {
            s.insert_str(pos, &junk);
        }
        let _ = Robot::from_urdf_str("fuzz.urdf", &s);
    }
}
