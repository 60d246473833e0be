//! The thermal lag: a link's structure follows its motors' temperature
//! through a first-order lag. Motor temperatures over time become a
//! piecewise-linear history, sampled on one grid ([`LAG_STEP_MIN`]), and the
//! lag is integrated exactly over each piece.

use super::{HeatingProfile, MotorTemps};
use crate::error::Result;

/// The sampling step of every temperature history a lag integrates, in
/// minutes: one discretisation for correction and diagnosis alike. The
/// lag is exact for the piecewise-linear input, so the step only decides
/// how closely the history follows a curved heating profile (the error is
/// second order in the step, far below a hundredth of a kelvin here).
pub const LAG_STEP_MIN: f64 = 0.25;

/// Motor temperatures over time as a piecewise-linear history, the input of
/// the thermal lag.
#[derive(Debug, Clone, PartialEq)]
pub struct TempHistory {
    times: Vec<f64>,
    temps: Vec<MotorTemps>,
    /// SHA-256 of the samples, taken once: what a fit's memo keys on
    /// instead of hashing twenty thousand samples per fit.
    digest: [u8; 32],
}

impl TempHistory {
    /// Sample a heating profile every [`LAG_STEP_MIN`] from 0 to `t_end`.
    pub fn from_profile(profile: &dyn HeatingProfile, t_end: f64) -> Result<Self> {
        // At most 20,000 samples whatever the span (a lag needs no finer
        // steps than span/20,000).
        let step = LAG_STEP_MIN.max(t_end.max(0.0) / 20_000.0).max(1e-6);
        let n = (t_end.max(0.0) / step).ceil() as usize + 1;
        let mut times = Vec::with_capacity(n);
        let mut temps = Vec::with_capacity(n);
        for i in 0..n {
            let t = (i as f64 * step).min(t_end.max(0.0));
            times.push(t);
            temps.push(profile.temps_at(t)?);
        }
        Ok(TempHistory::of(times, temps))
    }

    fn of(times: Vec<f64>, temps: Vec<MotorTemps>) -> Self {
        use sha2::{Digest, Sha256};
        let mut h = Sha256::new();
        for (t, m) in times.iter().zip(&temps) {
            h.update(t.to_le_bytes());
            for v in m {
                h.update(v.to_le_bytes());
            }
        }
        TempHistory {
            times,
            temps,
            digest: h.finalize().into(),
        }
    }

    /// SHA-256 of the samples (times and temperatures, little-endian f64).
    pub fn digest(&self) -> &[u8; 32] {
        &self.digest
    }

    /// From measured (time, temperatures) pairs in any order: averaged per
    /// time, sorted, and started from T_ref at t = 0 (the cold start) when
    /// the first record is later.
    pub fn from_records(records: &[(f64, MotorTemps)], t_ref: f64) -> Self {
        let mut sorted: Vec<(f64, MotorTemps)> = records.to_vec();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut times: Vec<f64> = Vec::new();
        let mut temps: Vec<MotorTemps> = Vec::new();
        let mut counts: Vec<f64> = Vec::new();
        for (t, temp) in sorted {
            match times.last() {
                Some(&last) if (t - last).abs() < 1e-9 => {
                    if let (Some(acc), Some(c)) = (temps.last_mut(), counts.last_mut()) {
                        for i in 0..6 {
                            acc[i] += temp[i];
                        }
                        *c += 1.0;
                    }
                }
                _ => {
                    times.push(t);
                    temps.push(temp);
                    counts.push(1.0);
                }
            }
        }
        for (acc, c) in temps.iter_mut().zip(&counts) {
            for v in acc.iter_mut() {
                *v /= c;
            }
        }
        if times.first().is_none_or(|&t| t > 1e-9) {
            times.insert(0, 0.0);
            temps.insert(0, [t_ref; 6]);
        }
        TempHistory::of(times, temps)
    }

    /// The structure temperatures through a first-order lag of time
    /// constant `tau` (minutes), starting at the first record's value.
    /// Integrated exactly for the piecewise-linear input.
    pub fn lagged(&self, tau: f64) -> Lagged<'_> {
        let mut states = Vec::with_capacity(self.times.len());
        if let Some(first) = self.temps.first() {
            states.push(*first);
        }
        for k in 1..self.times.len() {
            let prev = states[k - 1];
            states.push(lag_step(
                tau,
                self.times[k] - self.times[k - 1],
                &self.temps[k - 1],
                &self.temps[k],
                &prev,
            ));
        }
        Lagged {
            history: self,
            tau,
            states,
        }
    }
}

/// One exact step of y' = (u − y)/τ over `h` minutes with u linear from
/// `u0` to `u1`, starting at `y0`.
fn lag_step(tau: f64, h: f64, u0: &MotorTemps, u1: &MotorTemps, y0: &MotorTemps) -> MotorTemps {
    if tau < 1e-9 || h <= 0.0 {
        return if h <= 0.0 { *y0 } else { *u1 };
    }
    let decay = (-h / tau).exp();
    std::array::from_fn(|i| {
        let slope = (u1[i] - u0[i]) / h;
        u1[i] - slope * tau + (y0[i] - u0[i] + slope * tau) * decay
    })
}

/// A history passed through the lag, evaluated at any time.
pub struct Lagged<'a> {
    history: &'a TempHistory,
    tau: f64,
    states: Vec<MotorTemps>,
}

impl Lagged<'_> {
    pub fn at(&self, t: f64) -> MotorTemps {
        let times = &self.history.times;
        let temps = &self.history.temps;
        if times.is_empty() {
            return [0.0; 6];
        }
        // Index of the last knot at or before t.
        let k = times.partition_point(|&x| x <= t).saturating_sub(1);
        let (Some(&t0), Some(u0), Some(y0)) = (times.get(k), temps.get(k), self.states.get(k))
        else {
            return [0.0; 6];
        };
        let (t1, u1) = match (times.get(k + 1), temps.get(k + 1)) {
            (Some(&t1), Some(u1)) if t > t0 => (t1, *u1),
            // Before the first knot or past the last: input held constant.
            _ => (t0 + 1.0, *u0),
        };
        let h = t - t0;
        let u_t: MotorTemps = if t1 > t0 && h > 0.0 {
            std::array::from_fn(|i| u0[i] + (u1[i] - u0[i]) * (h / (t1 - t0)).min(1.0))
        } else {
            *u0
        };
        lag_step(self.tau, h.max(0.0), u0, &u_t, y0)
    }
}
