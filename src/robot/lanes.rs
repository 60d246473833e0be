//! The kinematics' trigonometry, several angles at once in SIMD lanes
//! (`wide`, after Agner Fog's vector class library: within an ulp or two
//! of libm). One forward kinematics needs six sin/cos pairs and one
//! inverse up to 23 atan2: called one by one in libm they were most of the
//! time of each.

use wide::{f64x2, f64x4};

/// Sines and cosines of four angles.
#[inline]
pub(super) fn sin_cos4(a: [f64; 4]) -> ([f64; 4], [f64; 4]) {
    let (s, c) = f64x4::new(a).sin_cos();
    (s.to_array(), c.to_array())
}

/// Sines and cosines of two angles.
#[inline]
pub(super) fn sin_cos2(a: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    let (s, c) = f64x2::new(a).sin_cos();
    (s.to_array(), c.to_array())
}

/// `y[i].atan2(x[i])` for four pairs (the same signs of zero and the
/// same quadrants as `f64::atan2`).
#[inline]
pub(super) fn atan2_4(y: [f64; 4], x: [f64; 4]) -> [f64; 4] {
    f64x4::new(y).atan2(f64x4::new(x)).to_array()
}
