//! The blind generator's UR5 (`world.rs` with [`super::world::Arm::Ur5`]):
//! its chain written here from the joint origins of
//! `tests/data/ur5/ur5.urdf` (numbers copied, not parsed by the library),
//! each origin growing with its link's temperature as the model's premise
//! says (joints 1–2 base, 3 lower arm, 4–5 upper arm, 6 and the flange
//! wrist), a bent link turning what follows about its end.

use super::world::{rot, rx, ry, rz, tr, Geometry, State};
use nalgebra::Vector3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// The URDF writes a quarter turn as 1.570796327 (π/2 to 10 digits): its
/// own chain, 1e-7 mm from an exact quarter turn, is the one copied.
#[allow(clippy::approx_constant)] // the URDF's own digits, on purpose
const URDF_HALF_TURN: f64 = 1.570796327;

/// The reflector's position in the tracker frame.
pub(super) fn position(g: &Geometry, s: &State, q: &[f64; 6]) -> Vector3<f64> {
    let a = |i: usize| q[i] + g.zero[i] + s.dq[i];
    let [base, lower, upper, wrist] = s.grow;
    // Bent about the joint axis (y) before it: the end moves θL/2 across
    // the link (y × z = +x) and what follows turns by θ.
    let bent =
        |along_y: f64, len: f64, theta: f64| tr(theta * len / 2.0, along_y, len) * rot(ry(theta));
    let chain = s.base
        * tr(0.0, 0.0, 89.159 * base)
        * rot(rz(std::f64::consts::PI))
        * rot(rz(a(0)))
        * g.origin[0]
        * tr(0.0, 135.85 * base, 0.0)
        * rot(ry(URDF_HALF_TURN))
        * rot(ry(a(1)))
        * g.origin[1]
        * bent(-119.7 * lower, 425.0 * lower, s.bend[0])
        * rot(ry(a(2)))
        * g.origin[2]
        * bent(0.0, 392.25 * upper, s.bend[1])
        * rot(ry(URDF_HALF_TURN))
        * rot(ry(a(3)))
        * g.origin[3]
        * tr(0.0, 93.0 * upper, 0.0)
        * rot(rz(a(4)))
        * g.origin[4]
        * tr(0.0, 0.0, 94.65 * wrist)
        * rot(ry(a(5)))
        * g.origin[5]
        * tr(0.0, 82.3 * wrist, 0.0)
        * rot(rx(-URDF_HALF_TURN));
    (g.tracker * chain)
        .transform_point(&g.reflector.into())
        .coords
}

/// A pose of a UR5 measurement program: the shoulder lifted, the wrist
/// clear of its singularity.
pub(super) fn random_pose(rng: &mut ChaCha8Rng) -> [f64; 6] {
    let deg = |rng: &mut ChaCha8Rng, lo: f64, hi: f64| rng.random_range(lo..hi).to_radians();
    let q5 = loop {
        let v: f64 = rng.random_range(-160.0..160.0);
        if v.to_radians().sin().abs() > 0.3 {
            break v.to_radians();
        }
    };
    [
        deg(rng, -170.0, 170.0),
        deg(rng, -160.0, -20.0),
        deg(rng, -140.0, 140.0),
        deg(rng, -170.0, 170.0),
        q5,
        deg(rng, -170.0, 170.0),
    ]
}

#[test]
fn the_ur5_worlds_chain_is_the_urdf_chain() {
    let robot =
        rapidtherm::robot::Robot::from_urdf_file(std::path::Path::new("tests/data/ur5/ur5.urdf"))
            .unwrap();
    let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(3);
    for _ in 0..20 {
        let q = random_pose(&mut rng);
        let a = position(&Geometry::exact(), &State::cold(), &q);
        let b = robot.fk(&q).translation.vector;
        assert!((a - b).norm() < 1e-9, "{a} vs {b}");
    }
}
