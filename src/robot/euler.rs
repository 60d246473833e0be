//! Orientation as RobotStudio shows it beside a target's quaternion:
//! Euler angles RX, RY, RZ in degrees for R = Rz(RZ)·Ry(RY)·Rx(RX)
//! (turn about the fixed x axis first, then y, then z).
//!
//! nalgebra's `euler_angles` returns (roll, pitch, yaw) for exactly that
//! product, R = Rz(yaw)·Ry(pitch)·Rx(roll), so RX = roll, RY = pitch,
//! RZ = yaw. Two rules make the numbers one per rotation:
//!
//! - Ranges: RY in [−90°, 90°], RX and RZ in (−180°, 180°] (−180° is
//!   written 180°, −0 is 0).
//! - Gimbal lock (RY = ±90°): only RX − RZ (RY = +90°) or RX + RZ
//!   (RY = −90°) is defined. RZ is then 0 and the whole turn is in RX.
//!   A rotation counts as locked when cos(RY) < 1e-7 (RY within 6e-6° of
//!   ±90°): below that, rounding in the quaternion decides RX and RZ
//!   apart (`[0.707107, 0, 0.707107, 0]` would give RX = RZ = 180° or
//!   0° by the sign of a 1e-17).
//!
//! q and −q are one rotation: the angles depend on the rotation only.

use nalgebra::{Rotation3, UnitQuaternion};

/// cos(RY) below which RX and RZ are no longer told apart (see the
/// module's rules); 1 − |sin RY| is then below cos²/2.
const LOCKED_COS: f64 = 1e-7;

/// RX, RY, RZ in degrees (RobotStudio's Euler ZYX) of a rotation.
pub fn euler_zyx_deg(rotation: &UnitQuaternion<f64>) -> [f64; 3] {
    let mut m = rotation.to_rotation_matrix().into_inner();
    // m[(2, 0)] = −sin(RY): at the lock nalgebra's own branch (RZ = 0)
    // takes over once it is exactly ±1.
    if 1.0 - m[(2, 0)].abs() < LOCKED_COS * LOCKED_COS / 2.0 {
        m[(2, 0)] = m[(2, 0)].signum();
    }
    let (rx, ry, rz) = Rotation3::from_matrix_unchecked(m).euler_angles();
    [rx, ry, rz].map(|a| tidy(a.to_degrees()))
}

/// −180° as 180°, −0 as 0, and values within 1e-9° of those as them.
fn tidy(deg: f64) -> f64 {
    if deg <= -180.0 + 1e-9 {
        180.0
    } else if deg.abs() < 1e-9 {
        0.0
    } else {
        deg
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Quaternion, Vector3};

    fn q(w: f64, x: f64, y: f64, z: f64) -> UnitQuaternion<f64> {
        UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z))
    }

    fn close(a: [f64; 3], b: [f64; 3]) {
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-6, "{a:?} != {b:?}");
        }
    }

    /// Hand-computed: a turn θ about one axis is (cos θ/2, sin θ/2 · axis).
    #[test]
    fn single_axis_turns() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        close(euler_zyx_deg(&q(1.0, 0.0, 0.0, 0.0)), [0.0, 0.0, 0.0]);
        close(euler_zyx_deg(&q(h, h, 0.0, 0.0)), [90.0, 0.0, 0.0]);
        close(euler_zyx_deg(&q(h, 0.0, 0.0, h)), [0.0, 0.0, 90.0]);
        close(euler_zyx_deg(&q(h, 0.0, 0.0, -h)), [0.0, 0.0, -90.0]);
        // 30° about y: (cos 15°, 0, sin 15°, 0).
        let (s, c) = 15f64.to_radians().sin_cos();
        close(euler_zyx_deg(&q(c, 0.0, s, 0.0)), [0.0, 30.0, 0.0]);
    }

    /// The usual tool-down orientation of RAPID programs, [0,0,1,0]: 180°
    /// about y, which ZYX writes as RX = 180°, RY = 0, RZ = 180°
    /// (Rz(180°)·Rx(180°) = diag(−1, 1, −1)), never −180°.
    #[test]
    fn tool_down_is_180_0_180() {
        assert_eq!(euler_zyx_deg(&q(0.0, 0.0, 1.0, 0.0)), [180.0, 0.0, 180.0]);
        assert_eq!(euler_zyx_deg(&q(0.0, 0.0, -1.0, 0.0)), [180.0, 0.0, 180.0]);
        // 180° about x alone.
        assert_eq!(euler_zyx_deg(&q(0.0, 1.0, 0.0, 0.0)), [180.0, 0.0, 0.0]);
    }

    /// A composed case by hand: Rz(90°)·Ry(0)·Rx(180°) is the quaternion
    /// (cos 45°, 0, 0, sin 45°)·(0, 1, 0, 0) = (0, h, h, 0).
    #[test]
    fn composed_turn_reads_back() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        close(euler_zyx_deg(&q(0.0, h, h, 0.0)), [180.0, 0.0, 90.0]);
    }

    /// Angles chosen, turned into a quaternion by the product itself, and
    /// read back; q and −q give the same angles.
    #[test]
    fn product_reads_back_and_sign_does_not_matter() {
        for &(rx, ry, rz) in &[
            (10.0, 20.0, 30.0),
            (-170.0, 45.0, 120.0),
            (179.0, -89.0, -1.0),
            (0.5, 89.9, 0.0),
        ] {
            let r = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), f64::to_radians(rz))
                * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), f64::to_radians(ry))
                * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), f64::to_radians(rx));
            close(euler_zyx_deg(&r), [rx, ry, rz]);
            let minus = UnitQuaternion::new_unchecked(-r.into_inner());
            close(euler_zyx_deg(&minus), [rx, ry, rz]);
        }
    }

    /// RY = +90°: RZ is 0 and RX carries the turn (RX − RZ of the
    /// product). pHome of samples/fixtures.mod, [0.707107,0,0.707107,0],
    /// is 90° about y.
    // 0.707107 is the six-digit number RAPID programs write, not 1/√2.
    #[allow(clippy::approx_constant)]
    #[test]
    fn gimbal_lock_puts_the_turn_in_rx() {
        close(
            euler_zyx_deg(&q(0.707107, 0.0, 0.707107, 0.0)),
            [0.0, 90.0, 0.0],
        );
        let h = std::f64::consts::FRAC_1_SQRT_2;
        close(euler_zyx_deg(&q(-h, 0.0, -h, 0.0)), [0.0, 90.0, 0.0]);
        let locked = |rx: f64, ry: f64, rz: f64| {
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), f64::to_radians(rz))
                * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), f64::to_radians(ry))
                * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), f64::to_radians(rx))
        };
        // RY = +90°: Rz(a)·Ry(90°)·Rx(b) depends on b − a only.
        close(euler_zyx_deg(&locked(50.0, 90.0, 20.0)), [30.0, 90.0, 0.0]);
        // RY = −90°: on b + a only.
        close(
            euler_zyx_deg(&locked(50.0, -90.0, 20.0)),
            [70.0, -90.0, 0.0],
        );
    }
}
