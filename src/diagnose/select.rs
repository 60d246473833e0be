//! Which effect: every candidate fitted to the gap and scored on held-out
//! data (group K-fold holding out whole time blocks and whole poses), by
//! BIC, forward selection while the held-out gap still drops clearly, and
//! honest verdicts (`none`, `unexplained`, ambiguities).

use super::fit::{fit, fit_from, Fit, Problem};
use crate::error::{ErrorKind, Result};
use crate::model::{Effect, EffectKind};
use nalgebra::Vector3;

/// Held-out folds: row indices to fit on and to score on.
#[derive(Debug, Clone)]
pub struct Folds {
    pub folds: Vec<(Vec<usize>, Vec<usize>)>,
}

/// Group K-fold: fold f holds out time block f (contiguous measurement
/// times) and pose group f together, and fits on rows in neither, so each
/// score is on times and poses the fit never saw.
pub fn make_folds(problem: &Problem, k: usize) -> Folds {
    let rows = &problem.rows;
    let k = k.max(2);
    let mut times: Vec<f64> = rows.iter().map(|r| r.time_min).collect();
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let n_poses = rows.iter().map(|r| r.pose + 1).max().unwrap_or(0);
    let use_time = times.len() >= k;
    // With a pose's own offset fitted, a held-out pose cannot be predicted:
    // hold out time only.
    let use_pose = n_poses >= k && !problem.centre_poses;
    // With pose offsets, twice as many blocks, dealt out in turn: each fold
    // holds out two spans apart, so that the offsets are still pinned on
    // both sides of every held-out span.
    let blocks = if problem.centre_poses { 2 * k } else { k };
    let time_block = |t: f64| -> usize {
        let i = times.partition_point(|&x| x < t - 1e-9);
        (i * blocks / times.len().max(1)).min(blocks - 1) % k
    };
    let mut folds = Vec::new();
    for f in 0..k {
        let mut train = Vec::new();
        let mut test = Vec::new();
        for (i, r) in rows.iter().enumerate() {
            let held = if use_time || use_pose {
                (use_time && time_block(r.time_min) == f) || (use_pose && r.pose % k == f)
            } else {
                i % k == f
            };
            if held {
                test.push(i);
            } else {
                train.push(i);
            }
        }
        if !train.is_empty() && !test.is_empty() {
            folds.push((train, test));
        }
    }
    Folds { folds }
}

/// A candidate scored at one selection step.
#[derive(Debug, Clone)]
pub struct Scored {
    pub kind: EffectKind,
    /// Held-out RMS gap with the candidate added, mm.
    pub cv_rms_mm: f64,
    /// Fit on all rows.
    pub fit: Option<Fit>,
    pub error: Option<String>,
    /// The candidate's predicted contribution (positions, stacked), for
    /// collinearity checks.
    pub contribution: Vec<f64>,
}

/// Held-out RMS of position gaps with `kinds` fitted on each fold's
/// training rows.
pub fn cv_rms(problem: &Problem, folds: &Folds, kinds: &[EffectKind]) -> Result<f64> {
    let mut sum = 0.0;
    let mut count = 0usize;
    // Each fold's fit starts where the fit on all rows ended (asked for
    // beside every score, and remembered): a fold leaves out a fifth of the
    // rows, and its minimum lies near; the time constants' grid search and
    // most iterations are saved.
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let full = match kinds {
        [] => None,
        _ => fit(problem, &all, kinds).ok(),
    };
    // The folds' fits are independent: made on the cores at once, their
    // gaps summed in the folds' order (the serial sum, bit for bit) and
    // the first fold's error in that order reported, as before.
    use rayon::prelude::*;
    let per_fold: Vec<Result<Vec<Vector3<f64>>>> = folds
        .folds
        .par_iter()
        .map(|(train, test)| {
            let effects: Vec<Effect> = match (kinds, &full) {
                ([], _) => Vec::new(),
                (_, Some(f)) => fit_from(problem, train, kinds, &f.effects)?.effects,
                (_, None) => fit(problem, train, kinds)?.effects,
            };
            Ok(held_out_gaps(problem, &effects, train, test))
        })
        .collect();
    for gaps in per_fold {
        for g in gaps? {
            sum += g.norm_squared();
            count += 1;
        }
    }
    Ok((sum / count.max(1) as f64).sqrt())
}

/// Gaps of the `test` rows with `effects`; with pose offsets, each pose's
/// offset is its mean gap over the `train` rows (a pose never trained on
/// cannot be predicted and is left out).
pub fn held_out_gaps(
    problem: &Problem,
    effects: &[Effect],
    train: &[usize],
    test: &[usize],
) -> Vec<Vector3<f64>> {
    let gaps = problem.position_gaps(effects, test);
    if !problem.centre_poses {
        return gaps;
    }
    let offsets = pose_means(problem, train, &problem.position_gaps(effects, train));
    test.iter()
        .zip(gaps)
        .filter_map(|(&i, g)| {
            let pose = problem.rows.get(i)?.pose;
            offsets.get(&pose).map(|o| g - o)
        })
        .collect()
}

/// Mean of `values` (one per row of `rows`) per pose.
pub fn pose_means(
    problem: &Problem,
    rows: &[usize],
    values: &[Vector3<f64>],
) -> std::collections::HashMap<usize, Vector3<f64>> {
    let mut sums: std::collections::HashMap<usize, (Vector3<f64>, usize)> = Default::default();
    for (&i, v) in rows.iter().zip(values) {
        if let Some(r) = problem.rows.get(i) {
            let e = sums.entry(r.pose).or_insert((Vector3::zeros(), 0));
            e.0 += v;
            e.1 += 1;
        }
    }
    sums.into_iter()
        .map(|(p, (s, n))| (p, s / n as f64))
        .collect()
}

/// `values` (one per row of `rows`) less their pose's mean when the
/// problem fits pose offsets.
pub fn centred(problem: &Problem, rows: &[usize], values: Vec<Vector3<f64>>) -> Vec<Vector3<f64>> {
    if problem.centre_poses {
        centre_by_pose(problem, rows, values)
    } else {
        values
    }
}

/// `values` (one per row of `rows`) less their pose's mean over `rows`.
pub fn centre_by_pose<T>(problem: &Problem, rows: &[usize], mut values: Vec<T>) -> Vec<T>
where
    T: Copy + std::ops::AddAssign + std::ops::SubAssign + std::ops::Div<f64, Output = T>,
{
    for ks in problem.pose_groups(rows) {
        let Some(&first) = ks.first() else { continue };
        let mut sum = values[first];
        for &k in &ks[1..] {
            sum += values[k];
        }
        let mean = sum / ks.len() as f64;
        for &k in &ks {
            values[k] -= mean;
        }
    }
    values
}

/// Score adding each of `candidates` to `current` (fitted jointly), in
/// parallel over the machine's cores.
pub fn score_candidates(
    problem: &Problem,
    folds: &Folds,
    current: &[EffectKind],
    current_fit: &[Effect],
    candidates: &[EffectKind],
) -> Vec<Scored> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let before: Vec<Vector3<f64>> = centred(
        problem,
        &all,
        problem
            .predict_rows(current_fit, &all)
            .iter()
            .map(|p| p.translation.vector)
            .collect(),
    );
    let score = |kind: EffectKind| -> Scored {
        let mut kinds = current.to_vec();
        kinds.push(kind);
        let result =
            cv_rms(problem, folds, &kinds).and_then(|cv| Ok((cv, fit(problem, &all, &kinds)?)));
        match result {
            Ok((cv, full)) => {
                let after = centred(
                    problem,
                    &all,
                    problem
                        .predict_rows(&full.effects, &all)
                        .iter()
                        .map(|p| p.translation.vector)
                        .collect(),
                );
                let contribution = after
                    .iter()
                    .zip(&before)
                    .flat_map(|(a, b)| {
                        let d = a - b;
                        [d.x, d.y, d.z]
                    })
                    .collect();
                Scored {
                    kind,
                    cv_rms_mm: cv,
                    fit: Some(full),
                    error: None,
                    contribution,
                }
            }
            Err(e) => Scored {
                kind,
                cv_rms_mm: f64::INFINITY,
                fit: None,
                error: Some(if e.kind == ErrorKind::NoConvergence {
                    format!("did not converge: {}", e.message)
                } else {
                    e.message
                }),
                contribution: Vec::new(),
            },
        }
    };
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .min(candidates.len().max(1));
    if threads <= 1 {
        return candidates.iter().map(|&k| score(k)).collect();
    }
    // A shared queue: fits differ tenfold in cost (the lag is the slowest),
    // so each thread takes the next candidate when it is free.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(Vec::with_capacity(candidates.len()));
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(&kind) = candidates.get(i) else {
                    break;
                };
                let scored = score(kind);
                if let Ok(mut r) = results.lock() {
                    r.push((i, scored));
                }
            });
        }
    });
    let mut out = results.into_inner().unwrap_or_default();
    out.sort_by_key(|(i, _)| *i);
    out.into_iter().map(|(_, s)| s).collect()
}

/// What `chosen` adds to the positions predicted with the rest of
/// `selected` (fitted on all rows, stacked as in [`Scored::contribution`]).
pub fn score_contribution(
    problem: &Problem,
    selected: &[EffectKind],
    chosen: EffectKind,
) -> Option<Vec<f64>> {
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let without: Vec<EffectKind> = selected.iter().copied().filter(|k| *k != chosen).collect();
    let predicted = |kinds: &[EffectKind]| -> Option<Vec<Vector3<f64>>> {
        let effects = match kinds {
            [] => Vec::new(),
            _ => fit(problem, &all, kinds).ok()?.effects,
        };
        Some(centred(
            problem,
            &all,
            problem
                .predict_rows(&effects, &all)
                .iter()
                .map(|p| p.translation.vector)
                .collect(),
        ))
    };
    let (a, b) = (predicted(selected)?, predicted(&without)?);
    Some(
        a.iter()
            .zip(&b)
            .flat_map(|(a, b)| {
                let d = a - b;
                [d.x, d.y, d.z]
            })
            .collect(),
    )
}

/// Cosine of two stacked contribution vectors.
pub fn collinearity(a: &[f64], b: &[f64]) -> f64 {
    let dot: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    let na: f64 = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nb: f64 = b.iter().map(|x| x * x).sum::<f64>().sqrt();
    if na <= 1e-300 || nb <= 1e-300 {
        0.0
    } else {
        (dot / (na * nb)).abs()
    }
}
