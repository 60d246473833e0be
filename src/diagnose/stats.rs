//! The significance tests behind every verdict: nested least-squares models
//! compared by F tests against a noise level the data show, the lack-of-fit
//! test that decides whether a gap is within the noise, and the smallest
//! effect a design would have revealed (the noncentral χ² of the same
//! test). Distribution functions are `puruspe`'s regularised incomplete beta
//! and gamma functions.

use serde::Serialize;

/// The level of every family of tests of one stage: one in a hundred sets
/// without the effect would still name it. At each step of a selection the
/// level is shared among the candidates tried (Bonferroni).
pub const LEVEL: f64 = 0.01;

/// Probability with which the detection limit is reached: an effect at the
/// limit is named in 90 % of sets like these.
pub const POWER: f64 = 0.9;

/// How precisely the noise variance is known: its degrees of freedom
/// (infinite for a level given by the user).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NoiseDof(pub f64);

impl NoiseDof {
    /// A noise level the caller gave: taken as exact.
    pub const EXACT: NoiseDof = NoiseDof(f64::INFINITY);
}

/// Survival function of F(d1, d2) at `x`: the p-value of an F statistic.
pub fn f_sf(x: f64, d1: f64, d2: f64) -> f64 {
    // NaN compares false: refused with the rest.
    if x.is_nan() || x <= 0.0 || d1.is_nan() || d1 <= 0.0 {
        return 1.0;
    }
    if !d2.is_finite() || d2 > 1e7 {
        return chi2_sf(x * d1, d1);
    }
    let z = (d1 * x / (d1 * x + d2)).clamp(0.0, 1.0);
    (1.0 - puruspe::betai(d1 / 2.0, d2.max(1e-9) / 2.0, z)).clamp(0.0, 1.0)
}

/// The upper-`alpha` quantile of F(d1, d2).
pub fn f_critical(alpha: f64, d1: f64, d2: f64) -> f64 {
    let d1 = d1.max(1e-9);
    if !d2.is_finite() || d2 > 1e7 {
        return chi2_critical(alpha, d1) / d1;
    }
    let b = puruspe::invbetai(1.0 - alpha.clamp(1e-300, 1.0), d1 / 2.0, d2.max(1e-9) / 2.0);
    if b >= 1.0 {
        return f64::INFINITY;
    }
    d2 * b / (d1 * (1.0 - b))
}

/// Survival function of χ²(k) at `x`.
pub fn chi2_sf(x: f64, k: f64) -> f64 {
    if x.is_nan() || x <= 0.0 || k.is_nan() || k <= 0.0 {
        return 1.0;
    }
    (1.0 - puruspe::gammp(k / 2.0, x / 2.0)).clamp(0.0, 1.0)
}

/// The upper-`alpha` quantile of χ²(k).
pub fn chi2_critical(alpha: f64, k: f64) -> f64 {
    2.0 * puruspe::invgammp(1.0 - alpha.clamp(1e-300, 1.0), k.max(1e-9) / 2.0)
}

/// P(X ≤ x) for X ~ noncentral χ²(k, λ): central χ² distributions of
/// k + 2j degrees of freedom mixed with Poisson(λ/2) weights.
pub fn noncentral_chi2_cdf(x: f64, k: f64, lambda: f64) -> f64 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    let half = lambda.max(0.0) / 2.0;
    let centre = half.floor() as i64;
    let weight = |j: i64| {
        let j = j as f64;
        (-half + j * half.max(1e-300).ln() - puruspe::ln_gamma(j + 1.0)).exp()
    };
    let term = |j: i64| weight(j) * puruspe::gammp((k + 2.0 * j as f64) / 2.0, x / 2.0);
    // Sum outwards from the Poisson mode until the weights vanish.
    let mut sum = term(centre);
    let mut j = centre + 1;
    while weight(j) > 1e-14 && j < centre + 100_000 {
        sum += term(j);
        j += 1;
    }
    let mut j = centre - 1;
    while j >= 0 && weight(j) > 1e-14 {
        sum += term(j);
        j -= 1;
    }
    sum.clamp(0.0, 1.0)
}

/// The noncentrality λ at which a χ²(k) test at level `alpha` rejects with
/// probability `power`: what an effect must add to the residual sum of
/// squares, in noise variances, to be found.
pub fn detectable_noncentrality(alpha: f64, k: f64, power: f64) -> f64 {
    let crit = chi2_critical(alpha, k);
    let miss = |lambda: f64| noncentral_chi2_cdf(crit, k, lambda);
    let (mut lo, mut hi) = (0.0, 1.0);
    while miss(hi) > 1.0 - power && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if miss(mid) > 1.0 - power {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// A nested-model test: does the larger model lower the residual sum of
/// squares by more than the noise would?
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Test {
    /// The F statistic: the drop in the residual sum of squares per added
    /// parameter, over the noise variance.
    pub f: f64,
    /// Parameters added.
    pub df1: usize,
    /// Degrees of freedom of the noise variance (`null`: known exactly).
    #[serde(serialize_with = "finite_or_null")]
    pub df2: f64,
    pub p_value: f64,
    /// The level it was judged at.
    pub level: f64,
}

fn finite_or_null<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if v.is_finite() {
        s.serialize_f64(*v)
    } else {
        s.serialize_none()
    }
}

impl Test {
    /// The test of a model with residual sum of squares `rss1` against the
    /// one inside it with `rss0`, `dp` parameters fewer, with noise
    /// variance `sigma2` per residual known to `dof`, at `level`.
    pub fn nested(rss0: f64, rss1: f64, dp: usize, sigma2: f64, dof: NoiseDof, level: f64) -> Test {
        let df1 = dp.max(1);
        let f = ((rss0 - rss1).max(0.0) / df1 as f64) / sigma2.max(1e-300);
        Test {
            f,
            df1,
            df2: dof.0,
            p_value: f_sf(f, df1 as f64, dof.0),
            level,
        }
    }

    /// The lack-of-fit test of a residual sum of squares `rss` on `dof_fit`
    /// degrees of freedom against the noise: is what is left larger than
    /// noise alone leaves?
    pub fn lack_of_fit(rss: f64, dof_fit: usize, sigma2: f64, dof: NoiseDof, level: f64) -> Test {
        let df1 = dof_fit.max(1);
        let f = (rss.max(0.0) / df1 as f64) / sigma2.max(1e-300);
        Test {
            f,
            df1,
            df2: dof.0,
            p_value: f_sf(f, df1 as f64, dof.0),
            level,
        }
    }

    /// Whether the larger model (or the lack of fit) is significant.
    pub fn significant(&self) -> bool {
        self.p_value < self.level
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_tables() {
        // χ²(1) at 5 %: 3.841; χ²(10) at 1 %: 23.209; F(4, 60) at 1 %: 3.649.
        assert!((chi2_critical(0.05, 1.0) - 3.841).abs() < 1e-3);
        assert!((chi2_critical(0.01, 10.0) - 23.209).abs() < 1e-3);
        assert!((f_critical(0.01, 4.0, 60.0) - 3.649).abs() < 2e-3);
        assert!((f_sf(3.649, 4.0, 60.0) - 0.01).abs() < 2e-4);
        assert!((chi2_sf(23.209, 10.0) - 0.01).abs() < 1e-5);
        // F with infinite denominator is χ²/d1.
        assert!((f_critical(0.01, 10.0, f64::INFINITY) - 2.3209).abs() < 1e-3);
    }

    #[test]
    fn noncentral_chi2_is_the_central_one_at_zero_and_shifts_right() {
        for x in [0.5, 2.0, 7.0] {
            let central = 1.0 - chi2_sf(x, 3.0);
            assert!((noncentral_chi2_cdf(x, 3.0, 0.0) - central).abs() < 1e-8);
        }
        // χ²(1, λ) is (Z + √λ)²: P(X ≤ 3.841) at λ = 10.51 is 0.1 (the
        // classic 5 % level, 90 % power noncentrality).
        assert!((noncentral_chi2_cdf(3.841, 1.0, 10.507) - 0.1).abs() < 2e-3);
        assert!((detectable_noncentrality(0.05, 1.0, 0.9) - 10.507).abs() < 0.02);
    }

    #[test]
    fn nested_tests_reject_only_real_drops() {
        let t = Test::nested(100.0, 99.0, 2, 1.0, NoiseDof(500.0), LEVEL);
        assert!(!t.significant(), "{t:?}");
        let t = Test::nested(100.0, 60.0, 2, 1.0, NoiseDof(500.0), LEVEL);
        assert!(t.significant(), "{t:?}");
        let t = Test::lack_of_fit(1000.0, 1000, 1.0, NoiseDof::EXACT, LEVEL);
        assert!(!t.significant(), "{t:?}");
        let t = Test::lack_of_fit(1200.0, 1000, 1.0, NoiseDof::EXACT, LEVEL);
        assert!(t.significant(), "{t:?}");
    }
}
