//! The module's arithmetic in Rust, step for step as the generated RAPID
//! writes it: the clock's day number, the update of the heating state,
//! the link temperatures and the flange drift. Tests hold it to the
//! project's own warm arm (`Robot::fk_scaled`) and curves
//! (`SatCurve::eval`); the interpreter then holds the RAPID to it.

use super::spec::{RuntimeSpec, MAX_TERMS};
use nalgebra::Vector3;

/// Days from 2000-01-01 to a civil date (proleptic Gregorian), as the
/// module's `RtDays` computes it with RAPID's integer `DIV`
/// (days-from-civil after H. Hinnant, shifted to 2000).
pub fn days_since_2000(y: i64, m: i64, d: i64) -> i64 {
    crate::interp::clock::days_from_civil(y, m, d)
}

/// 1 − e^(−u) as the module computes it: by its series below 0.01, where
/// `1 - Exp(-u)` in single precision would lose most of its digits.
pub fn grown(u: f64) -> f64 {
    if u < 0.01 {
        u * (1.0 - u / 2.0 * (1.0 - u / 3.0 * (1.0 - u / 4.0)))
    } else {
        1.0 - (-u).exp()
    }
}

/// The heating state: the rise of each term of each axis, °C.
pub type Rises = [[f64; MAX_TERMS]; 6];

/// After `dt_min` minutes running (or stopped), as `RtAdvance` does.
pub fn advance(spec: &RuntimeSpec, x: &mut Rises, dt_min: f64, running: bool) {
    for (a, curve) in spec.curves.iter().enumerate() {
        for (k, term) in curve.terms.iter().enumerate() {
            let g = grown(dt_min / term.tau);
            x[a][k] = if running {
                x[a][k] + (term.delta - x[a][k]) * g
            } else {
                x[a][k] - x[a][k] * g
            };
        }
    }
}

/// Motor temperatures of a state.
pub fn temps(spec: &RuntimeSpec, x: &Rises) -> [f64; 6] {
    std::array::from_fn(|a| spec.curves[a].t0 + x[a].iter().sum::<f64>())
}

/// Each link's growth over its cold length, L·(scale − 1)/L.
pub fn growth(spec: &RuntimeSpec, motor_temps: &[f64; 6]) -> [f64; 4] {
    std::array::from_fn(|l| {
        let link = &spec.links[l];
        let (sum, n) = (0..6)
            .filter(|&m| link.motors[m])
            .fold((0.0, 0.0), |(s, n), m| (s + motor_temps[m], n + 1.0));
        if n == 0.0 {
            0.0
        } else {
            link.per_degree * (sum / n - spec.t_ref)
        }
    })
}

/// The warm flange's move at joints `q_deg` (the controller's), in the
/// robot base frame, mm: the OPW position with every length replaced by
/// its growth (the position is linear in the lengths at fixed angles), as
/// `RtDrift` computes it.
pub fn drift_base(spec: &RuntimeSpec, q_deg: &[f64; 6], growth: &[f64; 4]) -> Vector3<f64> {
    let g = &spec.geom;
    let [eb, el, eu, ew] = *growth;
    let (da1, db, dc1) = (g.a1 * eb, g.b * eb, g.c1 * eb);
    let dc2 = g.c2 * el;
    let (dc3, da2) = (g.c3 * eu, g.a2 * eu);
    let dc4 = g.c4 * ew;
    let th: [f64; 6] = std::array::from_fn(|i| spec.signs[i] * q_deg[i] + spec.offsets_deg[i]);
    let sc = |d: f64| d.to_radians().sin_cos();
    let ((s1, c1), (s2, c2)) = (sc(th[0]), sc(th[1]));
    let (s23, c23) = sc(th[1] + th[2]);
    let ((s4, c4), (s5, c5)) = (sc(th[3]), sc(th[4]));
    let cx = dc2 * s2 + dc3 * s23 + da2 * c23 + da1;
    let cz = dc2 * c2 + dc3 * c23 - da2 * s23;
    // The flange's axis: Rz(θ1)·Ry(θ23)·(cos θ4 sin θ5, sin θ4 sin θ5, cos θ5).
    let (ax, ay, az) = (c4 * s5, s4 * s5, c5);
    let (bx, by, bz) = (c23 * ax + s23 * az, ay, -s23 * ax + c23 * az);
    Vector3::new(
        cx * c1 - db * s1 + dc4 * (c1 * bx - s1 * by),
        cx * s1 + db * c1 + dc4 * (s1 * bx + c1 * by),
        cz + dc1 + dc4 * bz,
    )
}
