//! The kinematics' trigonometry, several angles at once in SIMD lanes
//! (`wide`, after Agner Fog's vector class library: within an ulp or two
//! of libm). One forward kinematics needs six sin/cos pairs: called one by
//! one in libm they were more than half of its time.

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
