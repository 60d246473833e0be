//! Warm-up and cool-down: the motors' temperatures over a day of running
//! and stops, from saturating heating curves.
//!
//! A saturating curve T(t) = T0 + Σ ΔTᵢ·(1 − e^(−t/τᵢ)) is the response of
//! first-order heat paths to a step of power at t = 0: each term's rise
//! xᵢ obeys dxᵢ/dt = (ΔTᵢ − xᵢ)/τᵢ while the program runs. When it stops
//! the power goes and each term decays toward the room, dxᵢ/dt = −xᵢ/τᵢ,
//! through the same heat path, so with the same time constant. Both have
//! an exact discrete update over a span of length Δt:
//!
//! - running: xᵢ ← ΔTᵢ + (xᵢ − ΔTᵢ)·e^(−Δt/τᵢ)
//! - stopped: xᵢ ← xᵢ·e^(−Δt/τᵢ)
//!
//! Continuous running from a cold start gives the curve itself, to the
//! last bit that `exp` gives; this is the update that `correct --schedule`
//! with idle spans uses and the one the generated controller module
//! (`correct --runtime`) runs, so the two agree. Assumed, and said in
//! docs/runtime.md: a stopped robot's motors give no heat (brakes on,
//! servo off), the room stays at T0, and the mean power while running is
//! the one the curves were fitted at.

use super::saturating::SatCurve;
use super::{HeatingProfile, MotorTemps};
use crate::error::{Error, Result};

/// What the robot does over a span of time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Duty {
    /// The program runs: the motors heat toward the curves' steady rises.
    Running,
    /// The robot stands: the motors cool toward the room.
    Idle,
}

/// The rise of each term of each axis's curve above T0: the state the
/// exact update carries.
#[derive(Debug, Clone, PartialEq)]
pub struct HeatState {
    /// `rises[axis][term]`, °C, in the order of the curve's terms.
    pub rises: [Vec<f64>; 6],
}

impl HeatState {
    /// A cold robot: every rise zero.
    pub fn cold(curves: &[SatCurve; 6]) -> HeatState {
        HeatState {
            rises: std::array::from_fn(|a| vec![0.0; curves[a].terms.len()]),
        }
    }

    /// After `dt_min` minutes of `duty`.
    pub fn advance(&mut self, curves: &[SatCurve; 6], dt_min: f64, duty: Duty) {
        for (rises, curve) in self.rises.iter_mut().zip(curves) {
            for (x, term) in rises.iter_mut().zip(&curve.terms) {
                // e^(−Δt/τ) through exp_m1: exact 1 at Δt = 0, and
                // ΔT + (x − ΔT)·e = x − (x − ΔT)·(1 − e) as the curve's
                // own evaluation writes it.
                let grown = -(-dt_min / term.tau).exp_m1();
                *x = match duty {
                    Duty::Running => *x + (term.delta - *x) * grown,
                    Duty::Idle => *x - *x * grown,
                };
            }
        }
    }

    /// The motor temperatures of this state.
    pub fn temps(&self, curves: &[SatCurve; 6]) -> MotorTemps {
        std::array::from_fn(|a| curves[a].t0 + self.rises[a].iter().sum::<f64>())
    }
}

/// A span of a day: from this minute on (since the cold start), until the
/// next span starts, the robot does `duty`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DutyChange {
    pub from_min: f64,
    pub duty: Duty,
}

/// Saturating curves driven by a day of running and stops: the motor
/// temperatures at any minute, by the exact update over every span before
/// it. Running from minute 0 until the first change.
#[derive(Debug, Clone, PartialEq)]
pub struct DutyProfile {
    curves: [SatCurve; 6],
    /// Each change, with the state at its minute (computed once).
    changes: Vec<(DutyChange, HeatState)>,
}

impl DutyProfile {
    /// `changes` in increasing time, each after minute 0.
    pub fn new(curves: [SatCurve; 6], changes: &[DutyChange]) -> Result<DutyProfile> {
        let mut state = HeatState::cold(&curves);
        let mut at = 0.0;
        let mut duty = Duty::Running;
        let mut out = Vec::with_capacity(changes.len());
        for c in changes {
            if !(c.from_min.is_finite() && c.from_min >= at) {
                return Err(Error::input(format!(
                    "a change of duty at minute {} comes before minute {at}: the spans must be in increasing time",
                    c.from_min
                )));
            }
            state.advance(&curves, c.from_min - at, duty);
            at = c.from_min;
            duty = c.duty;
            out.push((*c, state.clone()));
        }
        Ok(DutyProfile {
            curves,
            changes: out,
        })
    }

    /// The curves of `profile` driven by `changes`; an error where the
    /// profile has no curves whose state can be carried (a polynomial, a
    /// recording).
    pub fn over(profile: &dyn HeatingProfile, changes: &[DutyChange]) -> Result<DutyProfile> {
        let curves = profile.curves().ok_or_else(|| {
            Error::usage(
                "idle spans need a heating model that cools: the heating curves in use have no state to carry through a stop (fit a saturating one: heating fit --model two-tau)",
            )
        })?;
        DutyProfile::new(curves, changes)
    }

    /// The changes of duty of idle spans `[from, to)`, in increasing time:
    /// idle from each span's start, running again from its end.
    pub fn spans_to_changes(spans: impl IntoIterator<Item = (f64, f64)>) -> Vec<DutyChange> {
        spans
            .into_iter()
            .flat_map(|(from, to)| {
                [
                    DutyChange {
                        from_min: from,
                        duty: Duty::Idle,
                    },
                    DutyChange {
                        from_min: to,
                        duty: Duty::Running,
                    },
                ]
            })
            .collect()
    }

    /// The state at `t_min`, with the duty then.
    pub fn state_at(&self, t_min: f64) -> HeatState {
        // The last change at or before t (binary search: a day may have
        // hundreds of stops, a program a million targets).
        let k = self.changes.partition_point(|(c, _)| c.from_min <= t_min);
        let (mut state, from, duty) = match k.checked_sub(1) {
            Some(i) => {
                let (c, s) = &self.changes[i];
                (s.clone(), c.from_min, c.duty)
            }
            None => (HeatState::cold(&self.curves), 0.0, Duty::Running),
        };
        state.advance(&self.curves, t_min - from, duty);
        state
    }

    pub fn curves(&self) -> &[SatCurve; 6] {
        &self.curves
    }
}

impl HeatingProfile for DutyProfile {
    fn temps_at(&self, t_min: f64) -> Result<MotorTemps> {
        if !t_min.is_finite() || t_min < 0.0 {
            return Err(Error::usage(format!(
                "minute {t_min} is not a time since the cold start (t ≥ 0)"
            )));
        }
        Ok(self.state_at(t_min).temps(&self.curves))
    }

    fn steady(&self) -> Result<MotorTemps> {
        Ok(std::array::from_fn(|a| self.curves[a].steady()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thermal::default_profile;

    fn curves() -> [SatCurve; 6] {
        default_profile().axes.clone()
    }

    #[test]
    fn continuous_running_is_the_curve_itself() {
        let c = curves();
        let p = DutyProfile::new(c.clone(), &[]).unwrap();
        for t in [0.0, 10.0, 30.0, 60.0, 120.0, 240.0, 10_000.0] {
            let got = p.temps_at(t).unwrap();
            for a in 0..6 {
                assert!((got[a] - c[a].eval(t)).abs() < 1e-12, "axis {a} at {t}");
            }
        }
        assert_eq!(p.temps_at(0.0).unwrap(), [7.0; 6]);
        // Many small steps give what one step gives: the update is exact.
        let mut s = HeatState::cold(&c);
        for _ in 0..1200 {
            s.advance(&c, 0.1, Duty::Running);
        }
        let one = p.temps_at(120.0).unwrap();
        for (a, b) in s.temps(&c).iter().zip(one) {
            assert!((a - b).abs() < 1e-10);
        }
    }

    #[test]
    fn a_stop_cools_and_running_again_warms() {
        let c = curves();
        let p = DutyProfile::new(
            c.clone(),
            &[
                DutyChange {
                    from_min: 120.0,
                    duty: Duty::Idle,
                },
                DutyChange {
                    from_min: 180.0,
                    duty: Duty::Running,
                },
            ],
        )
        .unwrap();
        let at120 = p.temps_at(120.0).unwrap();
        let at180 = p.temps_at(180.0).unwrap();
        let at210 = p.temps_at(210.0).unwrap();
        for a in 0..6 {
            assert!(at180[a] < at120[a], "cools while idle");
            assert!(at180[a] > 7.0, "not all the way in an hour");
            assert!(at210[a] > at180[a], "warms again");
            // Warmer than a cold start after 30 min: it started warm.
            assert!(at210[a] > c[a].eval(30.0));
        }
        // By hand for one term of axis 1 across the stop.
        let term = c[0].terms[1];
        let x120 = term.delta * (1.0 - (-120.0 / term.tau).exp());
        let x180 = x120 * (-60.0 / term.tau).exp();
        let s = p.state_at(180.0);
        assert!((s.rises[0][1] - x180).abs() < 1e-12);
        // A stop of days is a cold start.
        let long = DutyProfile::new(
            c.clone(),
            &[DutyChange {
                from_min: 120.0,
                duty: Duty::Idle,
            }],
        )
        .unwrap();
        let cold = long.temps_at(120.0 + 3.0 * 24.0 * 60.0).unwrap();
        for v in cold {
            assert!((v - 7.0).abs() < 1e-9);
        }
    }

    #[test]
    fn changes_out_of_order_are_refused() {
        let e = DutyProfile::new(
            curves(),
            &[
                DutyChange {
                    from_min: 60.0,
                    duty: Duty::Idle,
                },
                DutyChange {
                    from_min: 30.0,
                    duty: Duty::Running,
                },
            ],
        );
        assert!(e.is_err());
    }
}
