//! IK for one robconf: the direct path (`OpwArm::solve_conf`, what
//! `Robot::ik_conf` calls) gives exactly what enumerating every solution
//! and picking the robconf gives (`OpwArm::solve_conf_by_enumeration`):
//! the same joints to the bit, the same `None`, the same failure, on
//! random poses and robconfs of the IRB 140, the IRB 2600-12/1.65 and the
//! parallel-arm IRB 2400-10, cold and warm, at the wrist and shoulder
//! singularities and on quadrant boundaries (exactly on them, a rounding
//! error off, within and just beyond the tolerance of a near match); and
//! `wrap` and `quadrant`, which skip libm calls, against their formulas to
//! the bit.

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rapidtherm::robot::ik::{IkFailure, OpwArm, CONF_TOLERANCE};
use rapidtherm::robot::Solution;
use rapidtherm::robot::{Joints, RobConf, Robot};
use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

fn robots() -> &'static [Robot; 3] {
    static ROBOTS: OnceLock<[Robot; 3]> = OnceLock::new();
    ROBOTS.get_or_init(|| {
        [
            Robot::irb140(),
            Robot::abb("irb2600-12/1.65").expect("in the catalogue"),
            Robot::abb("irb2400-10").expect("in the catalogue"),
        ]
    })
}

/// The direct path and the enumeration agree on `pose` and `want`, to the
/// bit; returns whether the direct path alone answered (an exact or a
/// near match).
fn agree(arm: &OpwArm, robot: &Robot, pose: &Isometry3<f64>, want: &RobConf) -> bool {
    let fast = arm.solve_conf(pose, &robot.limits, want);
    let slow = arm
        .solve_conf_by_enumeration(pose, &robot.limits, want)
        .map(|(found, _)| found);
    let bits = |r: &Result<Option<Solution>, IkFailure>| {
        r.clone()
            .map(|s| s.map(|s| (s.q.map(f64::to_bits), s.conf)))
    };
    assert_eq!(
        bits(&fast),
        bits(&slow),
        "{}: {want} at {pose:?}: {fast:?} vs {slow:?}",
        robot.name
    );
    let direct = arm.solve_conf_direct(pose, &robot.limits, want);
    if let Some(d) = direct {
        assert_eq!(fast, Ok(Some(d)), "{}: {want} at {pose:?}", robot.name);
    }
    direct.is_some()
}

/// Joints from unit numbers: within the limits, or (`wide`) anywhere in
/// ±1.2 times them, so that some are out of reach of the limits.
fn joints(robot: &Robot, u: &[f64; 6], wide: bool) -> Joints {
    std::array::from_fn(|i| {
        let (lo, hi) = robot.limits[i];
        let (lo, hi) = if wide {
            let m = 0.5 * (lo + hi);
            (m + 1.2 * (lo - m), m + 1.2 * (hi - m))
        } else {
            (lo, hi)
        };
        lo + (hi - lo) * u[i]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Taught joints' own robconf, another robconf, and the pose moved a
    /// little (a thermal correction), on each arm, cold and warm.
    #[test]
    fn direct_robconf_ik_equals_enumerate_and_pick(
        which in 0usize..3,
        u in proptest::array::uniform6(0.0f64..1.0),
        wide in proptest::bool::weighted(0.2),
        // Axis 5 at 0 (the wrist singularity), axes 1, 4, 6 on a quadrant
        // boundary or a rounding error off it.
        snap in proptest::array::uniform4(0u8..6),
        other in (-3i32..3, -3i32..3, -5i32..5, 0i32..8),
        nudge in proptest::array::uniform3(-0.5f64..0.5),
        warm in proptest::bool::weighted(0.3),
    ) {
        let robot = &robots()[which];
        let mut q = joints(robot, &u, wide);
        for (k, &axis) in [0usize, 3, 5].iter().enumerate() {
            match snap[k] {
                0 => q[axis] = (q[axis] / FRAC_PI_2).round() * FRAC_PI_2,
                1 => q[axis] = (q[axis] / FRAC_PI_2).round() * FRAC_PI_2 - 1e-4,
                _ => {}
            }
        }
        if snap[3] == 0 {
            q[4] = 0.0;
        } else if snap[3] == 1 {
            q[4] = 1e-4;
        }
        let scales = [1.0 + 3e-4, 1.0 + 2e-4, 1.0 + 4e-4, 1.0 + 1e-4];
        let arm = robot
            .opw_arm(warm.then_some(&scales))
            .expect("these arms have OPW form");
        let pose = robot.fk(&q);
        let moved = Isometry3::from_parts(
            (pose.translation.vector + Vector3::new(nudge[0], nudge[1], nudge[2])).into(),
            pose.rotation * UnitQuaternion::from_scaled_axis(Vector3::new(nudge[2], 0.0, nudge[1]) * 1e-3),
        );
        let own = robot.conf_of(&q);
        let (cf1, cf4, cf6, cfx) = other;
        for p in [pose, moved] {
            agree(&arm, robot, &p, &own);
            agree(&arm, robot, &p, &RobConf::new(cf1, cf4, cf6, cfx));
            agree(&arm, robot, &p, &RobConf::new(own.cf1, own.cf4, own.cf6, cfx));
        }
    }
}

/// Offsets from a quadrant boundary (axes 1, 4, 6) or from 0 (axis 5):
/// on it, a rounding error off, within and just beyond the tolerance of a
/// near match.
const OFF_BOUNDARY: [f64; 14] = [
    0.0,
    1e-16,
    -1e-16,
    1e-12,
    -1e-12,
    1e-9,
    -1e-9,
    1e-4,
    -1e-4,
    CONF_TOLERANCE * (1.0 - 1e-6),
    -CONF_TOLERANCE * (1.0 - 1e-6),
    CONF_TOLERANCE * (1.0 + 1e-6),
    -CONF_TOLERANCE * (1.0 + 1e-6),
    0.3,
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Near matches: taught joints on or next to a quadrant boundary, the
    /// robconf of the quadrant on either side (what a target written on
    /// the boundary holds after a rounding error), cold and warm, the pose
    /// as taught and moved a little.
    #[test]
    fn near_matches_equal_enumerate_and_pick(
        which in 0usize..3,
        u in proptest::array::uniform6(0.0f64..1.0),
        off in proptest::array::uniform4(0usize..OFF_BOUNDARY.len()),
        shift in proptest::array::uniform3(-1i32..=1),
        flip5 in proptest::bool::ANY,
        nudge in proptest::array::uniform3(-0.05f64..0.05),
        warm in proptest::bool::weighted(0.5),
    ) {
        let robot = &robots()[which];
        let mut q = joints(robot, &u, false);
        for (k, &axis) in [0usize, 3, 5].iter().enumerate() {
            q[axis] = (q[axis] / FRAC_PI_2).round() * FRAC_PI_2 + OFF_BOUNDARY[off[k]];
        }
        q[4] = OFF_BOUNDARY[off[3]];
        let scales = [1.0 + 3e-4, 1.0 + 2e-4, 1.0 + 4e-4, 1.0 + 1e-4];
        let arm = robot
            .opw_arm(warm.then_some(&scales))
            .expect("these arms have OPW form");
        let pose = robot.fk(&q);
        let moved = Isometry3::from_parts(
            (pose.translation.vector + Vector3::new(nudge[0], nudge[1], nudge[2])).into(),
            pose.rotation,
        );
        let own = robot.conf_of(&q);
        let cfx = if flip5 { own.cfx ^ 1 } else { own.cfx };
        let near = RobConf::new(own.cf1 + shift[0], own.cf4 + shift[1], own.cf6 + shift[2], cfx);
        for p in [pose, moved] {
            agree(&arm, robot, &p, &own);
            agree(&arm, robot, &p, &near);
        }
    }

    /// The shoulder singularity: the wrist centre on axis 1 or a hair
    /// off it, where the enumeration searches cf1's quadrant.
    #[test]
    fn shoulder_singular_poses_equal_enumerate_and_pick(
        u in proptest::array::uniform6(0.0f64..1.0),
        off in 0usize..4,
        height in 0.3f64..0.9,
        other in (-2i32..2, -2i32..2, -2i32..2, 0i32..8),
    ) {
        // The IRB 140 and the IRB 2600 (b = 0: axis 1 passes through the
        // arm plane).
        for robot in &robots()[..2] {
            let arm = robot.opw_arm(None).expect("OPW form");
            let q = joints(robot, &u, false);
            let rotation = robot.fk(&q).rotation;
            let z = (rotation * arm.tip.inverse()) * Vector3::z();
            let g = arm.geom;
            let centre = Vector3::new(
                [0.0, 1e-12, 1e-9, 1e-6][off],
                0.0,
                g.c1 + height * (g.c2 + g.c3),
            );
            let pose = Isometry3::from_parts((centre + g.c4 * z).into(), rotation);
            let (cf1, cf4, cf6, cfx) = other;
            agree(&arm, robot, &pose, &RobConf::new(cf1, cf4, cf6, cfx));
            agree(&arm, robot, &pose, &robot.conf_of(&q));
        }
    }
}

/// The targets of `cargo bench --bench correct` (a tool pointing straight
/// down: axis 4 lands a rounding error below 0 in half of them, outside
/// their written cf4 = 0) are answered by the direct path, as the
/// enumeration answers them.
#[test]
fn targets_a_rounding_error_off_their_quadrant_are_answered_directly() {
    let robot = &robots()[0];
    let arm = robot.opw_arm(None).expect("OPW form");
    let mut near = 0;
    for (flange, want) in crate::straight_down::flanges() {
        assert!(agree(&arm, robot, &flange, &want), "{want} at {flange:?}");
        let q = robot.ik_conf(&flange, &want).expect("reachable");
        near += usize::from(robot.conf_of(&q) != want);
    }
    // The near matches are there, and answered directly.
    assert!(near > 0);
}

/// The direct path does answer: taught joints away from boundaries are
/// found by it alone, and `Robot::ik_conf` gives what the enumeration
/// picks.
#[test]
fn the_direct_path_answers_taught_targets() {
    for robot in robots() {
        let arm = robot.opw_arm(None).expect("OPW form");
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut direct = 0;
        for _ in 0..500 {
            let u: [f64; 6] = std::array::from_fn(|_| next());
            let q = joints(robot, &u, false);
            let pose = robot.fk(&q);
            let conf = robot.conf_of(&q);
            direct += usize::from(agree(&arm, robot, &pose, &conf));
            let (found, _) = arm
                .solve_conf_by_enumeration(&pose, &robot.limits, &conf)
                .expect("taught joints are reachable");
            let back = robot
                .ik_conf(&pose, &conf)
                .expect("taught joints are reachable");
            assert_eq!(Some(back), found.map(|s| s.q), "{}", robot.name);
        }
        assert!(direct >= 490, "{}: {direct} of 500 direct", robot.name);
    }
}

/// `wrap` and `quadrant` skip libm's `round` and `floor` where the answer
/// is exact without them; they still give those formulas' bits.
#[test]
fn wrap_and_quadrant_are_the_formulas_to_the_bit() {
    use rapidtherm::robot::conf::quadrant;
    use rapidtherm::robot::ik::wrap;
    use std::f64::consts::{PI, TAU};
    let mut xs = vec![
        0.0,
        -0.0,
        PI,
        -PI,
        3.0,
        -3.0,
        FRAC_PI_2,
        -FRAC_PI_2,
        TAU,
        1e300,
        -1e300,
        f64::INFINITY,
        f64::NAN,
        2_147_483_648.0 * FRAC_PI_2,
        -2_147_483_648.0 * FRAC_PI_2,
        4_503_599_627_370_496.0,
    ];
    for x in xs.clone() {
        xs.push(f64::from_bits(x.to_bits().wrapping_add(1)));
        xs.push(f64::from_bits(x.to_bits().wrapping_sub(1)));
    }
    let mut state = 3u64;
    for _ in 0..100_000 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let u = (state >> 11) as f64 / (1u64 << 53) as f64;
        xs.push((u - 0.5) * 40.0);
        xs.push(((u - 0.5) * 20.0).round() * FRAC_PI_2);
    }
    for x in xs {
        let w = x - TAU * (x / TAU).round();
        assert!(
            wrap(x).to_bits() == w.to_bits() || (w.is_nan() && wrap(x).is_nan()),
            "wrap({x:e})"
        );
        assert_eq!(
            quadrant(x),
            (x / FRAC_PI_2).floor() as i32,
            "quadrant({x:e})"
        );
    }
}
