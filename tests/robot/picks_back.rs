//! `Robot::picks_back`, which lets the main job skip solving a corrected
//! target again: wherever it says the controller picks the joints back
//! from their pose and robconf, solving does give them back. Checked on
//! joints placed where the pick goes wrong or nearly does: on quadrant
//! boundaries and a rounding error off them, at the wrist, shoulder and
//! elbow singularities, at the joint limits, with another robconf than the
//! joints'. And it does say so for what correction gives it: taught joints
//! away from every boundary, the benchmark's targets (axis 4 at 0).

use crate::rng::Rng;
use rapidtherm::robot::ik::CONF_TOLERANCE;
use rapidtherm::robot::{Joints, RobConf, Robot};
use std::f64::consts::FRAC_PI_2;

/// Three catalogue arms (one with a parallel arm's axis 3), and the
/// IRB 140 with more than a turn on axes 2, 3 and 5, where the solve
/// takes the first turn within the limits, not the joints' own.
fn robots() -> [Robot; 4] {
    let mut wide = Robot::irb140();
    for axis in [1, 2, 4] {
        wide.limits[axis] = (-1.8 * std::f64::consts::PI, 1.8 * std::f64::consts::PI);
    }
    [
        Robot::irb140(),
        Robot::abb("irb2600-12/1.65").expect("in the catalogue"),
        Robot::abb("irb2400-10").expect("in the catalogue"),
        wide,
    ]
}

/// Offsets from a boundary: on it, rounding errors, around the rule's
/// clearances, the near-match tolerance.
const OFFSETS: [f64; 17] = [
    0.0,
    1e-16,
    -1e-16,
    1e-12,
    -1e-12,
    1e-10,
    -1e-10,
    1e-9,
    -1e-9,
    1e-7,
    -1e-7,
    1e-6,
    -1e-6,
    CONF_TOLERANCE * (1.0 - 1e-6),
    -CONF_TOLERANCE * (1.0 - 1e-6),
    CONF_TOLERANCE * (1.0 + 1e-6),
    -CONF_TOLERANCE * (1.0 + 1e-6),
];

/// Which edge a sample was placed on.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Edge {
    None,
    Quadrant,
    Wrist,
    Elbow,
    Shoulder,
    Limit,
}

fn offset(rng: &mut Rng) -> f64 {
    OFFSETS[(rng.next() * OFFSETS.len() as f64) as usize]
}

/// Joints of `robot` within its limits, put on one edge.
fn sample(robot: &Robot, rng: &mut Rng) -> (Joints, Edge) {
    let arm = robot.opw_arm(None).expect("OPW form");
    let mut q = rng.joints_within(robot);
    let edge = match (rng.next() * 8.0) as usize {
        0 | 1 => Edge::None,
        2 | 3 => {
            for axis in [0, 3, 5] {
                if rng.next() < 0.6 {
                    q[axis] = (q[axis] / FRAC_PI_2).round() * FRAC_PI_2 + offset(rng);
                }
            }
            Edge::Quadrant
        }
        4 => {
            q[4] = offset(rng) * if rng.next() < 0.5 { 1.0 } else { 1e3 };
            Edge::Wrist
        }
        5 => {
            // The wrist centre on the lower arm's line: k·sin(θ3 + ψ3) = 0.
            let mut t = arm.theta_of(&q);
            let g = arm.geom;
            t[2] = (-g.a2).atan2(g.c3) + offset(rng) * 1e3;
            q[2] = arm.q_of(&t)[2];
            Edge::Elbow
        }
        6 => {
            // The wrist centre on axis 1: θ2 by Newton for forward = 0.
            let mut t = arm.theta_of(&q);
            let g = arm.geom;
            for _ in 0..50 {
                let f = g.cfx_geometry(&t).0;
                let h = 1e-7;
                let mut tp = t;
                tp[1] += h;
                let d = (g.cfx_geometry(&tp).0 - f) / h;
                t[1] -= f / d;
            }
            t[1] += offset(rng) * 1e-2;
            q[1] = arm.q_of(&t)[1];
            Edge::Shoulder
        }
        _ => {
            let axis = (rng.next() * 6.0) as usize;
            let (lo, hi) = robot.limits[axis];
            q[axis] = if rng.next() < 0.5 { lo } else { hi } + offset(rng);
            Edge::Limit
        }
    };
    (q, edge)
}

/// The joints' own robconf, or one a quadrant or a branch away.
fn conf_for(robot: &Robot, q: &Joints, rng: &mut Rng) -> RobConf {
    let own = robot.conf_of(q);
    let step = if rng.next() < 0.5 { 1 } else { -1 };
    match (rng.next() * 8.0) as usize {
        0 => RobConf::new(own.cf1 + step, own.cf4, own.cf6, own.cfx),
        1 => RobConf::new(own.cf1, own.cf4 + step, own.cf6, own.cfx),
        2 => RobConf::new(own.cf1, own.cf4, own.cf6 + step, own.cfx),
        3 => RobConf::new(own.cf1, own.cf4, own.cf6, (rng.next() * 8.0) as i32),
        _ => own,
    }
}

/// Whether solving the pose of `q` with `conf` gives `q` back (the main
/// job's check, tighter: 1e-9 rad where it allows 1e-6).
fn solved_back(robot: &Robot, q: &Joints, conf: &RobConf) -> bool {
    robot
        .ik_conf(&robot.fk(q), conf)
        .is_ok_and(|p| p.iter().zip(q).all(|(a, b)| (a - b).abs() <= 1e-9))
}

#[test]
fn where_it_says_yes_solving_gives_the_joints_back() {
    let mut rng = Rng(0x5eed_0b0e);
    for (which, robot) in robots().into_iter().enumerate() {
        let mut said = 0;
        let mut wrong_if_always = 0;
        let mut clear = (0, 0);
        for _ in 0..30_000 {
            let (q, edge) = sample(&robot, &mut rng);
            let conf = conf_for(&robot, &q, &mut rng);
            let back = solved_back(&robot, &q, &conf);
            if robot.picks_back(&q, &conf) {
                said += 1;
                assert!(back, "{}: {q:?} {conf} ({edge:?})", robot.name);
            }
            wrong_if_always += usize::from(!back);
            if edge == Edge::None && conf == robot.conf_of(&q) {
                clear.0 += 1;
                clear.1 += usize::from(robot.picks_back(&q, &conf));
            }
        }
        // The samples reach where the pick goes wrong, and the rule still
        // says yes for most of what a program holds (on the arm with wide
        // limits most joints have another turn within them: solved).
        assert!(wrong_if_always > 1000, "{}: {wrong_if_always}", robot.name);
        if which == 3 {
            continue;
        }
        assert!(said > 5_000, "{}: {said}", robot.name);
        assert!(
            clear.1 * 100 >= clear.0 * 97,
            "{}: {} of {} clear joints",
            robot.name,
            clear.1,
            clear.0
        );
    }
}

/// The benchmark's targets, the tool pointing straight down: axis 4 lands
/// a rounding error either side of 0 in their written cf4 = 0, and axis 6
/// of half of them on a boundary too. Each is picked back, and the rule
/// says so without solving.
#[test]
fn a_tool_pointing_straight_down_is_picked_back_without_solving() {
    let robot = Robot::irb140();
    for (flange, want) in crate::straight_down::flanges() {
        let q = robot.ik_conf(&flange, &want).expect("reachable");
        assert!(robot.picks_back(&q, &want), "{want} at {q:?}");
        assert!(solved_back(&robot, &q, &want));
    }
}

/// An arm without the OPW form is always solved.
#[test]
fn a_chain_arm_is_always_solved() {
    let ur5 = Robot::from_urdf_file(std::path::Path::new("tests/data/ur5/ur5.urdf"))
        .expect("the UR5 URDF of tests/data/ur5");
    let q = [0.3, -1.0, 1.2, -0.5, 0.8, 0.2];
    assert!(!ur5.picks_back(&q, &ur5.conf_of(&q)));
}
