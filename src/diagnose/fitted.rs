//! What a fit of effects gives: the effects with their parameters, each
//! parameter's standard error or why the data hold it, the residual and
//! the Bayesian information criterion.

use super::unidentified::Unidentified;
use crate::model::Effect;

/// A fitted parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct FitParam {
    pub value: f64,
    /// Standard error; `None` when the data cannot identify the parameter
    /// (held at zero).
    pub stderr: Option<f64>,
    /// Why the data cannot identify it, where they cannot (held at zero; a
    /// time constant keeps its start value).
    pub held: Option<Unidentified>,
}

/// The outcome of a fit.
#[derive(Debug, Clone)]
pub struct Fit {
    pub effects: Vec<Effect>,
    /// Per effect, per parameter.
    pub params: Vec<Vec<FitParam>>,
    pub rss: f64,
    /// Number of residuals.
    pub n_obs: usize,
    /// Number of free (identifiable) parameters.
    pub n_free: usize,
    pub iterations: usize,
}

impl Fit {
    /// Bayesian information criterion of the fit (Gaussian residuals).
    pub fn bic(&self) -> f64 {
        let n = self.n_obs.max(1) as f64;
        n * (self.rss.max(1e-300) / n).ln() + self.n_free as f64 * n.ln()
    }
}
