//! A sudden shift of the whole robot at one moment (a knock, a loosened
//! foot, a bumped fixture): outside the library, but a shape of its own
//! that a thermal effect can half-follow. Scored like a candidate, on the
//! same held-out time spans with each pose's own offset, so that a thermal
//! effect is not named where a step fits the time variation better.

use super::fit::Problem;
use super::select::{centre_by_pose, Folds};
use nalgebra::Vector3;
use std::collections::HashMap;

/// The best step of one fit: when (between two measurement times) and by
/// how much (mm, in the robot base frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knock {
    pub after_min: f64,
    pub shift_mm: Vector3<f64>,
}

/// The best step of `gaps` (one per row of `rows`) with each pose's own
/// offset: the step, the residual sum of squares about the pose means
/// without it and with it, and how many splits were tried (the F test of
/// the step shares its level among them).
pub fn best(
    problem: &Problem,
    rows: &[usize],
    gaps: &[Vector3<f64>],
) -> Option<(Knock, f64, f64, usize)> {
    let gc = centre_by_pose(problem, rows, gaps.to_vec());
    let rss0: f64 = gc.iter().map(|g| g.norm_squared()).sum();
    let (k, rss, tried) = fit_rss(problem, rows, gaps)?;
    Some((k, rss0, rss, tried))
}

/// Per-pose offsets plus one shift from `after_min` on, fitted to `gaps`
/// of `rows` (closed form for each split; the best split of the distinct
/// times).
fn fit(problem: &Problem, rows: &[usize], gaps: &[Vector3<f64>]) -> Option<Knock> {
    fit_rss(problem, rows, gaps).map(|(k, _, _)| k)
}

/// [`fit`], with the residual sum of squares of the best split and the
/// number of splits tried.
fn fit_rss(
    problem: &Problem,
    rows: &[usize],
    gaps: &[Vector3<f64>],
) -> Option<(Knock, f64, usize)> {
    let mut times: Vec<f64> = rows.iter().map(|&i| problem.rows[i].time_min).collect();
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    if times.len() < 6 {
        return None;
    }
    // Splits where the measurements pause (the start of a sweep over the
    // poses, when a program measures them in turn), else at every time; at
    // most about a hundred, never the first or last two (a step there is a
    // trend's end).
    let mut steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let typical = steps[steps.len() / 2];
    let pauses: Vec<usize> = (2..times.len() - 1)
        .filter(|&k| times[k] - times[k - 1] > 2.0 * typical)
        .collect();
    let mut splits = if pauses.len() >= 4 {
        pauses
    } else {
        (2..times.len() - 1).collect()
    };
    let stride = (splits.len() / 100).max(1);
    splits = splits.into_iter().step_by(stride).collect();
    let tried = splits.len();
    let gc = centre_by_pose(problem, rows, gaps.to_vec());
    let mut best: Option<(f64, Knock)> = None;
    for k in splits {
        let tau = times[k];
        let h: Vec<f64> = rows
            .iter()
            .map(|&i| f64::from(u8::from(problem.rows[i].time_min >= tau - 1e-9)))
            .collect();
        let hc = centre_by_pose(problem, rows, h);
        let hh: f64 = hc.iter().map(|x| x * x).sum();
        if hh <= 1e-12 {
            continue;
        }
        let s = hc
            .iter()
            .zip(&gc)
            .map(|(x, g)| g * *x)
            .sum::<Vector3<f64>>()
            / hh;
        let rss: f64 = hc
            .iter()
            .zip(&gc)
            .map(|(x, g)| (g - s * *x).norm_squared())
            .sum();
        if best.as_ref().is_none_or(|(r, _)| rss < *r) {
            best = Some((
                rss,
                Knock {
                    after_min: tau,
                    shift_mm: s,
                },
            ));
        }
    }
    best.map(|(rss, k)| (k, rss, tried))
}

/// Held-out RMS of `gaps` (one per row of the problem) under a step with
/// each pose's own offset, on the folds' time spans; and the step fitted
/// to all rows.
pub fn score(problem: &Problem, folds: &Folds, gaps: &[Vector3<f64>]) -> Option<(f64, Knock)> {
    let mut sum = 0.0;
    let mut count = 0usize;
    for (train, test) in &folds.folds {
        let train_gaps: Vec<Vector3<f64>> = train.iter().map(|&i| gaps[i]).collect();
        let k = fit(problem, train, &train_gaps)?;
        let step = |i: usize| {
            if problem.rows[i].time_min >= k.after_min - 1e-9 {
                k.shift_mm
            } else {
                Vector3::zeros()
            }
        };
        let mut offsets: HashMap<usize, (Vector3<f64>, usize)> = HashMap::new();
        for &i in train {
            let e = offsets
                .entry(problem.rows[i].pose)
                .or_insert((Vector3::zeros(), 0));
            e.0 += gaps[i] - step(i);
            e.1 += 1;
        }
        for &i in test {
            if let Some((o, n)) = offsets.get(&problem.rows[i].pose) {
                sum += (gaps[i] - step(i) - o / *n as f64).norm_squared();
                count += 1;
            }
        }
    }
    if count == 0 {
        return None;
    }
    let all: Vec<usize> = (0..problem.rows.len()).collect();
    let k = fit(problem, &all, gaps)?;
    Some(((sum / count as f64).sqrt(), k))
}
