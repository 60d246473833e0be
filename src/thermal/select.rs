//! Choosing a saturating heating model by how well it forecasts, not by how
//! well it fits: each candidate is fitted to the first part of the
//! recording and judged on the rows it has not seen. Inside its window a
//! two-time-constant curve always fits at least as well as a first-order
//! one; beyond a recording shorter than its time constants it can forecast
//! anything (a real 49-minute recording once gave a 4,900-min term of
//! 116 K, 7.7 K off five hours later, where a first-order fit was within
//! about 1 K).

use super::kind_fit::{fit_without_interval, steady_interval_of, AxisFit, Candidate, ModelKind};
use crate::error::{Error, ErrorKind, Result};

/// The models `auto` chooses among, simplest first.
pub const CANDIDATES: [ModelKind; 2] = [ModelKind::FirstOrder, ModelKind::TwoTau];

/// A more complex candidate is chosen only when its held-out error is below
/// this fraction of the simpler one's: a tail of a fifth of the rows is
/// short, and an extra time constant that forecasts it barely better is
/// more likely fitted to its noise than to a second heat path.
pub const SIMPLER_PREFERRED_BELOW: f64 = 0.8;

/// Fit every candidate to one axis and keep the one that forecasts the
/// held-out rows best (the simpler unless the other is clearly better),
/// fitted to all rows. Candidates whose fit is no result are listed with
/// the reason; when none gives a result, the simplest one's error is
/// returned.
pub fn select_saturating(
    axis: usize,
    t: &[f64],
    y: &[f64],
    pin_t0: Option<f64>,
) -> Result<AxisFit> {
    let mut candidates = Vec::new();
    let mut best: Option<AxisFit> = None;
    let mut first_error = None;
    for kind in CANDIDATES {
        match fit_without_interval(axis, t, y, kind, pin_t0) {
            Ok(fit) => {
                let rmse = fit.holdout.as_ref().map(|m| m.rmse);
                candidates.push(Candidate {
                    kind,
                    holdout_rmse: rmse,
                    refused: None,
                });
                let better = match (&best, rmse) {
                    (None, _) => true,
                    (Some(b), Some(r)) => match b.holdout.as_ref() {
                        Some(m) => r < SIMPLER_PREFERRED_BELOW * m.rmse,
                        None => true,
                    },
                    (Some(_), None) => false,
                };
                if better {
                    best = Some(fit);
                }
            }
            Err(e) if e.kind == ErrorKind::NoConvergence => {
                candidates.push(Candidate {
                    kind,
                    holdout_rmse: None,
                    refused: Some(e.message.clone()),
                });
                first_error.get_or_insert(e);
            }
            Err(e) => return Err(e),
        }
    }
    let Some(mut fit) = best else {
        return Err(first_error.unwrap_or_else(|| {
            Error::new(ErrorKind::NoConvergence, "no heating model to choose from")
        }));
    };
    fit.steady_interval = steady_interval_of(&fit.curve, t, y, pin_t0);
    fit.chosen_from = candidates;
    Ok(fit)
}
