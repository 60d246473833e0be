//! Fits recover the curves they were given, over random parameters.

use proptest::prelude::*;
use rapidtherm::thermal::poly::{fit_poly, PolyCurve};
use rapidtherm::thermal::saturating::fit_saturating;

fn times(n: usize, span: f64) -> Vec<f64> {
    (0..n).map(|i| span * i as f64 / (n - 1) as f64).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any polynomial up to degree 8 over any window is recovered: values
    /// to 1e-9 of its scale, from noise-free samples.
    #[test]
    fn polynomial_recovered(
        coeffs in proptest::collection::vec(-10.0f64..10.0, 1..9),
        lo in 0.0f64..100.0,
        width in 1.0f64..500.0,
    ) {
        // Coefficients in scaled time, so that every term matters.
        let truth = PolyCurve::from_coefficients(-1.0, 1.0, &coeffs).unwrap();
        let t: Vec<f64> = times(300, width).iter().map(|x| lo + x).collect();
        let s = |x: f64| (2.0 * x - 2.0 * lo - width) / width;
        let y: Vec<f64> = t.iter().map(|&x| truth.eval(s(x))).collect();
        let fit = fit_poly(&t, &y, coeffs.len() - 1).unwrap();
        let scale = coeffs.iter().map(|c| c.abs()).sum::<f64>().max(1.0);
        for (&x, &v) in t.iter().zip(&y) {
            prop_assert!((fit.eval(x) - v).abs() < 1e-9 * scale);
        }
        let back = fit.scaled_coefficients();
        for (a, b) in back.iter().zip(&coeffs) {
            prop_assert!((a - b).abs() < 1e-8 * scale);
        }
    }

    /// First-order heating with any plausible parameters is recovered.
    #[test]
    fn first_order_recovered(
        t0 in -10.0f64..40.0,
        delta in -30.0f64..30.0,
        tau in 3.0f64..150.0,
    ) {
        prop_assume!(delta.abs() > 0.5);
        let t = times(400, 168.0);
        let y: Vec<f64> = t.iter().map(|&x| t0 + delta * -(-x / tau).exp_m1()).collect();
        let c = fit_saturating(&t, &y, 1, None).unwrap();
        prop_assert!((c.t0 - t0).abs() < 1e-6, "{:?}", c);
        prop_assert!((c.terms[0].delta - delta).abs() < 1e-5 * delta.abs().max(1.0), "{:?}", c);
        prop_assert!((c.terms[0].tau - tau).abs() < 1e-5 * tau, "{:?}", c);
    }
}
