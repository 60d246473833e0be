//! The noise the significance tests compare a larger model with: measured
//! from repeats or given, else each nested test's own larger model's
//! residual variance.

use super::fit;
use super::stats::{NoiseDof, Test};

/// The noise the tests compare with.
#[derive(Debug, Clone, Copy)]
pub struct TestNoise {
    /// 3-D RMS of the noise, mm.
    pub rms_mm: f64,
    /// Variance of one residual component, mm².
    pub sigma2: f64,
    /// How well that variance is known.
    pub dof: NoiseDof,
    /// Measured from repeats or given. Where it is not, `sigma2` is only a
    /// first fit's residual variance, and every nested test divides by
    /// the residual variance of its own larger model instead
    /// ([`TestNoise::nested`]).
    pub measured: bool,
}

impl TestNoise {
    /// The nested F test of a model with residual sum of squares `rss1`
    /// on `resid_dof` degrees of freedom against the one inside it with
    /// `rss0`, `dp` parameters fewer: against the noise where it was
    /// measured or given, else the textbook extra-sum-of-squares F test,
    /// whose denominator is the larger model's residual variance,
    /// rss1 / resid_dof, on resid_dof degrees of freedom.
    pub fn nested(&self, rss0: f64, rss1: f64, dp: usize, resid_dof: usize, level: f64) -> Test {
        if self.measured {
            Test::nested(rss0, rss1, dp, self.sigma2, self.dof, level)
        } else {
            let d = resid_dof.max(1);
            Test::nested(
                rss0,
                rss1,
                dp,
                rss1.max(0.0) / d as f64,
                NoiseDof(d as f64),
                level,
            )
        }
    }

    /// [`TestNoise::nested`] of the fit `larger` against `rss0` with
    /// `free0` free parameters.
    pub fn nested_fit(&self, rss0: f64, free0: usize, larger: &fit::Fit, level: f64) -> Test {
        self.nested(
            rss0,
            larger.rss,
            larger.n_free.saturating_sub(free0),
            larger.n_obs.saturating_sub(larger.n_free),
            level,
        )
    }
}
