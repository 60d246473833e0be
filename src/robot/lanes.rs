//! The kinematics' trigonometry, several angles at once in SIMD lanes
//! (`wide`, after Agner Fog's vector class library: within an ulp or two
//! of libm). One forward kinematics needs six sin/cos pairs: called one by
//! one in libm they were more than half of its time.

use wide::{f64x2, CmpLt, CmpNe};

/// Angles up to this size (rad) take [`sin_cos_modest`]; joint angles
/// are a few radians.
const MODEST: f64 = 1e9;

/// Sines and cosines of six angles.
#[inline]
pub(super) fn sin_cos6(a: [f64; 6]) -> ([f64; 6], [f64; 6]) {
    let (p0, p1, p2) = (
        f64x2::new([a[0], a[1]]),
        f64x2::new([a[2], a[3]]),
        f64x2::new([a[4], a[5]]),
    );
    // Not a NaN, not an infinity, not astronomic: the quadrant below is
    // exact.
    let modest = (p0.abs().max(p1.abs()).max(p2.abs()))
        .cmp_lt(f64x2::splat(MODEST))
        .all();
    let ((s0, c0), (s1, c1), (s2, c2)) = if modest {
        (sin_cos_modest(p0), sin_cos_modest(p1), sin_cos_modest(p2))
    } else {
        (p0.sin_cos(), p1.sin_cos(), p2.sin_cos())
    };
    let (s0, s1, s2) = (s0.to_array(), s1.to_array(), s2.to_array());
    let (c0, c1, c2) = (c0.to_array(), c1.to_array(), c2.to_array());
    (
        [s0[0], s0[1], s1[0], s1[1], s2[0], s2[1]],
        [c0[0], c0[1], c1[0], c1[1], c2[0], c2[1]],
    )
}

/// `wide`'s `f64x2::sin_cos` to the bit, for angles below [`MODEST`]: the
/// same reduction by the nearest multiple q of π/2 and the same
/// polynomials, with q's last two bits (which pick sine or cosine and the
/// signs) read from the float that rounds to q, 2^52 + q, whose last
/// mantissa bits are q's. `wide` converts q to an integer, which SSE2
/// does one lane at a time with checks for overflow.
#[inline(always)]
fn sin_cos_modest(v: f64x2) -> (f64x2, f64x2) {
    let k = f64x2::splat;
    let bits = |b: u64| f64x2::splat(f64::from_bits(b));
    let xa = v.abs();
    // `wide`'s round of a number ≥ 0: add 2^52 and take it away.
    let magic = bits(0x4330_0000_0000_0000);
    let t = xa * k(2.0 / std::f64::consts::PI) + magic;
    let y = t - magic;
    let x = y.mul_neg_add(
        k(3.061_616_997_868_383e-17 * 2.0),
        y.mul_neg_add(
            k(7.946_627_356_147_928e-9 * 2.0),
            y.mul_neg_add(k(7.853_981_554_508_209e-1 * 2.0), xa),
        ),
    );
    let x2 = x * x;
    let s = polynomial_5(
        x2,
        [
            -1.666_666_666_666_663e-1,
            8.333_333_333_322_118e-3,
            -1.984_126_982_958_954e-4,
            2.755_731_362_138_572_2e-6,
            -2.505_074_776_285_780_7e-8,
            1.589_623_015_765_465_6e-10,
        ],
    );
    let c = polynomial_5(
        x2,
        [
            4.166_666_666_666_659_5e-2,
            -1.388_888_888_887_305_6e-3,
            2.480_158_728_885_170_4e-5,
            -2.755_731_417_929_674e-7,
            2.087_570_084_197_473e-9,
            -1.135_853_652_138_768_2e-11,
        ],
    );
    let s = (x * x2).mul_add(s, x);
    let c = (x2 * x2).mul_add(c, x2.mul_neg_add(k(0.5), k(1.0)));
    // Bit b of q set: the bits of t masked to it are a subnormal, not 0
    // (compared as such: nothing here flushes subnormals).
    let zero = k(0.0);
    let sign = k(-0.0);
    let swap = (t & bits(1)).cmp_ne(zero);
    let sin = swap.blend(c, s) ^ ((t & bits(2)).cmp_ne(zero) & sign) ^ (v & sign);
    let cos = swap.blend(s, c) ^ (((t + k(1.0)) & bits(2)).cmp_ne(zero) & sign);
    (sin, cos)
}

/// `wide`'s polynomial of degree 5, in its order of operations.
#[inline(always)]
fn polynomial_5(x: f64x2, c: [f64; 6]) -> f64x2 {
    let k = f64x2::splat;
    let x2 = x * x;
    let x4 = x2 * x2;
    k(c[3]).mul_add(x, k(c[2])).mul_add(
        x2,
        k(c[5])
            .mul_add(x, k(c[4]))
            .mul_add(x4, k(c[1]).mul_add(x, k(c[0]))),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same bits as `wide` (the polynomials' constants as written
    /// there, the quadrant arithmetic), on joint angles of every size
    /// and the quadrant boundaries; beyond [`MODEST`] `wide` itself.
    #[test]
    fn sin_cos6_is_wide_to_the_bit() {
        use std::f64::consts::FRAC_PI_2;
        let mut xs = vec![0.0, -0.0, 1e-300, -1e-300, 3.0, -3.0, 1e8, -1e8];
        for k in -20..=20 {
            let b = f64::from(k) * FRAC_PI_2;
            xs.extend([
                b,
                f64::from_bits(b.to_bits() + 1),
                f64::from_bits(b.to_bits().wrapping_sub(1)),
            ]);
            xs.extend([
                b + 0.25 * FRAC_PI_2,
                b + 0.5 * FRAC_PI_2,
                b + 0.75 * FRAC_PI_2,
            ]);
        }
        let mut state = 11u64;
        for _ in 0..200_000 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            xs.push((u - 0.5) * 30.0);
        }
        xs.extend([1e10, f64::NAN, f64::INFINITY]);
        for w in xs.chunks(6).filter(|w| w.len() == 6) {
            let a: [f64; 6] = std::array::from_fn(|i| w[i]);
            let (s, c) = sin_cos6(a);
            for i in 0..6 {
                let (ws, wc) = f64x2::splat(a[i]).sin_cos();
                let (ws, wc) = (ws.to_array()[0], wc.to_array()[0]);
                let same =
                    |x: f64, y: f64| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
                assert!(same(s[i], ws) && same(c[i], wc), "sin_cos({:e})", a[i]);
            }
        }
    }
}
