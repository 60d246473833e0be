//! How stable each named effect is: over resampled fits, how often its
//! nested F test beyond the rest of the stage's model still names it. A
//! verdict that changes with the split of the data is no verdict: an effect
//! named in fewer than [`MIN_FREQUENCY`] of the resamples is reported as a
//! candidate, not named.
//!
//! The resamples leave out about a quarter of the groups the stage's
//! held-out folds are made of (time blocks where each pose has its own
//! offset, else poses), drawn by a seeded ChaCha8 stream, so the same data
//! give the same frequencies. Each resample refits the stage's model with
//! and without each effect, started from the fit on all rows (a few
//! iterations each, no time-constant grid).

use super::fit::{self, Problem};
use super::stats::LEVEL;
use super::test_noise::TestNoise;
use crate::model::{Effect, EffectKind};
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// Resamples per stage: ten keeps the cost to about ten warm refits per
/// effect named (the diagnosis's held-out folds already cost four full
/// ones), and resolves the 80 % rule (8 of 10).
pub const RESAMPLES: usize = 10;

/// The least share of resamples in which a named effect must be named
/// again.
pub const MIN_FREQUENCY: f64 = 0.8;

/// How often an effect was named over the resamples (JSON `stability`).
#[derive(Debug, Clone, Serialize)]
pub struct Stability {
    pub effect: EffectKind,
    pub named_in: usize,
    pub resamples: usize,
    /// `named_in / resamples`.
    pub frequency: f64,
}

impl Stability {
    /// Named often enough to be a verdict.
    pub fn stable(&self) -> bool {
        self.frequency >= MIN_FREQUENCY
    }
}

/// The row sets of the resamples of `problem`: each leaves out a quarter
/// (at least one) of its groups, time blocks where poses keep their own
/// offsets (`centre_poses`), else poses.
pub fn resamples(problem: &Problem, n: usize, seed: u64) -> Vec<Vec<usize>> {
    let rows = &problem.rows;
    let group_of: Vec<usize> = if problem.centre_poses {
        let mut times: Vec<f64> = rows.iter().map(|r| r.time_min).collect();
        times.sort_by(f64::total_cmp);
        times.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let blocks = times.len().clamp(1, 8);
        rows.iter()
            .map(|r| {
                let i = times.partition_point(|&x| x < r.time_min - 1e-9);
                (i * blocks / times.len().max(1)).min(blocks - 1)
            })
            .collect()
    } else {
        rows.iter().map(|r| r.pose).collect()
    };
    let groups = group_of.iter().map(|g| g + 1).max().unwrap_or(0);
    if groups < 4 {
        return Vec::new();
    }
    let drop = (groups / 4).max(1);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let mut ids: Vec<usize> = (0..groups).collect();
            ids.shuffle(&mut rng);
            let out = &ids[..drop];
            (0..rows.len())
                .filter(|&i| !out.contains(&group_of[i]))
                .collect()
        })
        .collect()
}

/// For each effect of `found` (a stage's selection with its fitted
/// values, fitted on `problem`), how often its nested F test beyond the
/// others (at [`LEVEL`], as the backward elimination's) names it on the
/// resamples.
pub fn of(problem: &Problem, found: &[Effect], noise: &TestNoise, seed: u64) -> Vec<Stability> {
    if found.is_empty() {
        return Vec::new();
    }
    let kinds: Vec<EffectKind> = found.iter().map(|e| e.kind).collect();
    let sets = resamples(problem, RESAMPLES, seed);
    // The resamples are independent: fitted on the cores at once, each
    // giving which effects its tests name (counted afterwards, in order).
    use rayon::prelude::*;
    let per_set: Vec<Option<Vec<bool>>> = sets
        .par_iter()
        .map(|rows| {
            let full = fit::fit_from(problem, rows, &kinds, found).ok()?;
            Some(
                kinds
                    .iter()
                    .map(|k| {
                        let without: Vec<EffectKind> =
                            kinds.iter().copied().filter(|x| x != k).collect();
                        let (rss0, free0) = if without.is_empty() {
                            (problem.residuals(&[], rows).norm_squared(), 0)
                        } else {
                            match fit::fit_from(problem, rows, &without, found) {
                                Ok(f) => (f.rss, f.n_free),
                                Err(_) => return false,
                            }
                        };
                        noise.nested_fit(rss0, free0, &full, LEVEL).significant()
                    })
                    .collect(),
            )
        })
        .collect();
    let mut named = vec![0usize; kinds.len()];
    let mut done = 0usize;
    for hits in per_set.into_iter().flatten() {
        done += 1;
        for (n, hit) in named.iter_mut().zip(hits) {
            *n += usize::from(hit);
        }
    }
    if done == 0 {
        return Vec::new();
    }
    kinds
        .iter()
        .zip(named)
        .map(|(&effect, named_in)| Stability {
            effect,
            named_in,
            resamples: done,
            frequency: named_in as f64 / done as f64,
        })
        .collect()
}
