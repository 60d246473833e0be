//! Where a gap lies: over the warm-up (time bins, a sudden step), in which
//! directions, at which poses and workspace regions, and whether it follows
//! one joint's angle (a harmonic of that angle: gear or encoder errors).

pub use super::finding::{direction_words, JointFollow, PoseGap, Step, TimeShape};
use super::finding::{Finding, Principal, Split};
use super::fit::Problem;
use crate::robot::Joints;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};

#[derive(Debug, Clone, Serialize)]
pub struct TimeBin {
    pub from_min: f64,
    pub to_min: f64,
    pub rms_mm: f64,
    pub n: usize,
}

#[derive(Debug, Clone, Serialize)]
pub struct Direction {
    /// Mean gap vector (x, y, z), mm.
    pub mean_mm: [f64; 3],
    /// RMS per axis, mm.
    pub rms_mm: [f64; 3],
    /// Principal direction of the gap vectors (unit).
    pub dominant: [f64; 3],
    /// Share of the gap's mean square along `dominant`.
    pub dominant_share: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct Region {
    pub name: String,
    pub rms_mm: f64,
    pub n: usize,
}

impl Where {
    /// Put `step` here where none was found (a step scored as a candidate
    /// is stronger evidence than the trend test).
    pub fn with_step(mut self, step: Step) -> Where {
        if self.step.is_none() {
            self.findings.push(Finding::Step(step.clone()));
            self.step = Some(step);
        }
        self
    }
}

/// The localisation of a gap.
#[derive(Debug, Clone, Serialize)]
pub struct Where {
    pub rms_mm: f64,
    pub time_bins: Vec<TimeBin>,
    /// How it changes over the warm-up (not among `words`: the report
    /// words it beside the verdict, see [`TimeShape::words`]).
    pub time_shape: Option<TimeShape>,
    /// Correlation of the gap size with the mean motor temperature rise.
    pub temperature_correlation: Option<f64>,
    pub direction: Direction,
    pub worst_poses: Vec<PoseGap>,
    pub regions: Vec<Region>,
    pub joint: Option<JointFollow>,
    pub step: Option<Step>,
    /// What is said about it, in order (the JSON gives their sentences).
    #[serde(rename = "words", serialize_with = "super::finding::serialize_words")]
    pub findings: Vec<Finding>,
}

impl Where {
    /// Whether the gap shows any structure a noise floor would not: a step
    /// in time, growth over the warm-up, a joint it follows, a dominant
    /// direction, or a size that follows the temperatures.
    pub fn has_structure(&self) -> bool {
        let grows = match (self.time_bins.first(), self.time_bins.last()) {
            (Some(a), Some(b)) => b.rms_mm > 1.5 * a.rms_mm || a.rms_mm > 1.5 * b.rms_mm,
            _ => false,
        } || matches!(self.time_shape, Some(TimeShape::Grows { .. }));
        self.step.is_some()
            || self.joint.is_some()
            || grows
            || self.direction.dominant_share > 0.6
            || self.temperature_correlation.is_some_and(|c| c > 0.5)
    }
}

impl Where {
    /// The findings in sentences.
    pub fn words(&self) -> Vec<String> {
        self.findings.iter().map(Finding::words).collect()
    }
}

fn rms(v: &[Vector3<f64>]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    (v.iter().map(|g| g.norm_squared()).sum::<f64>() / v.len() as f64).sqrt()
}

/// The gaps being localised, with what counts as large.
struct Gaps<'a> {
    problem: &'a Problem,
    /// One per row of `problem` (the first `gaps.len()` rows).
    gaps: &'a [Vector3<f64>],
    /// Their RMS, mm.
    total: f64,
    noise_rms: f64,
}

/// Localise `gaps` (one per row of `problem`, mm). `pose_names` labels pose
/// ids; `noise_rms` (3-D RMS of noise, mm) sets what counts as large.
pub fn locate(
    problem: &Problem,
    gaps: &[Vector3<f64>],
    pose_names: &[String],
    noise_rms: f64,
) -> Where {
    let rows = &problem.rows;
    let n = gaps.len().min(rows.len());
    let total = rms(&gaps[..n]);
    let mut findings = Vec::new();
    let g = Gaps {
        problem,
        gaps: &gaps[..n],
        total,
        noise_rms,
    };

    // Over time.
    let time_bins = g.time_bins();
    let time_shape = time_shape(problem, &gaps[..n], &time_bins, noise_rms);
    let t_ref = problem.base.thermal.t_ref;
    let rise: Vec<f64> = rows
        .iter()
        .take(n)
        .map(|r| r.temps.iter().map(|t| t - t_ref).sum::<f64>() / 6.0)
        .collect();
    let size: Vec<f64> = gaps[..n].iter().map(|g| g.norm()).collect();
    let temperature_correlation = pearson(&rise, &size);
    if let Some(c) = temperature_correlation {
        if c > 0.8 && total > 1.5 * noise_rms {
            findings.push(Finding::FollowsTemperature { correlation: c });
        }
    }

    let direction = g.direction(&mut findings);
    let worst_poses = g.worst_poses(pose_names, &mut findings);
    let regions = g.regions(&mut findings);

    let joint = follow_joint(problem, &gaps[..n]);
    if let Some(j) = &joint {
        if j.share > 0.3 && total > 1.5 * noise_rms {
            findings.push(Finding::FollowsJoint(j.clone()));
        }
    }
    let step = find_step(problem, &gaps[..n], noise_rms);
    if let Some(s) = &step {
        findings.push(Finding::Step(s.clone()));
    }
    Where {
        rms_mm: total,
        time_bins,
        time_shape,
        temperature_correlation,
        direction,
        worst_poses,
        regions,
        joint: joint.filter(|j| j.share > 0.3),
        step,
        findings,
    }
}

impl Gaps<'_> {
    /// The gaps' RMS in six bins of equal length over the times measured
    /// (empty bins left out).
    fn time_bins(&self) -> Vec<TimeBin> {
        let (rows, gaps) = (&self.problem.rows, self.gaps);
        let n = gaps.len();
        let (tmin, tmax) = rows
            .iter()
            .take(n)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, r| {
                (a.0.min(r.time_min), a.1.max(r.time_min))
            });
        let mut time_bins = Vec::new();
        if n > 0 && tmax > tmin {
            let nb = 6;
            let width = (tmax - tmin) / nb as f64;
            for b in 0..nb {
                let lo = tmin + b as f64 * width;
                let hi = if b + 1 == nb { tmax } else { lo + width };
                let sel: Vec<Vector3<f64>> = (0..n)
                    .filter(|&i| {
                        let t = rows[i].time_min;
                        t >= lo && (t < hi || (b + 1 == nb && t <= hi))
                    })
                    .map(|i| gaps[i])
                    .collect();
                if !sel.is_empty() {
                    time_bins.push(TimeBin {
                        from_min: lo,
                        to_min: hi,
                        rms_mm: rms(&sel),
                        n: sel.len(),
                    });
                }
            }
        }
        time_bins
    }

    /// The gaps' mean, RMS per axis and dominant direction; a finding
    /// where one direction holds most of them.
    fn direction(&self, findings: &mut Vec<Finding>) -> Direction {
        let (gaps, total, noise_rms) = (self.gaps, self.total, self.noise_rms);
        let n = gaps.len();
        let mut mean = Vector3::zeros();
        let mut second = Matrix3::zeros();
        let mut sq = Vector3::zeros();
        for g in gaps {
            mean += g;
            second += g * g.transpose();
            sq += g.component_mul(g);
        }
        let nf = n.max(1) as f64;
        mean /= nf;
        let eig = second.symmetric_eigen();
        let (imax, lmax) = eig.eigenvalues.iter().copied().enumerate().fold(
            (0, f64::NEG_INFINITY),
            |a, (i, v)| if v > a.1 { (i, v) } else { a },
        );
        let mut dominant: Vector3<f64> = eig.eigenvectors.column(imax).into();
        if dominant.dot(&mean) < 0.0 {
            dominant = -dominant;
        }
        let trace = second.trace().max(1e-300);
        let share = (lmax / trace).clamp(0.0, 1.0);
        if share > 0.6 && total > 1.5 * noise_rms {
            findings.push(Finding::Along {
                direction: Principal::of(&dominant, &mean, (lmax / nf).max(0.0).sqrt()),
                share,
            });
        }
        Direction {
            mean_mm: [mean.x, mean.y, mean.z],
            rms_mm: [(sq.x / nf).sqrt(), (sq.y / nf).sqrt(), (sq.z / nf).sqrt()],
            dominant: [dominant.x, dominant.y, dominant.z],
            dominant_share: share,
        }
    }

    /// The five poses of the largest gaps (`pose_names` labels them); a
    /// finding naming the first three where they stand out.
    fn worst_poses(&self, pose_names: &[String], findings: &mut Vec<Finding>) -> Vec<PoseGap> {
        let (rows, gaps) = (&self.problem.rows, self.gaps);
        let n = gaps.len();
        let mut per_pose: BTreeMap<usize, Vec<Vector3<f64>>> = BTreeMap::new();
        for i in 0..n {
            per_pose.entry(rows[i].pose).or_default().push(gaps[i]);
        }
        let mut worst_poses: Vec<PoseGap> = per_pose
            .iter()
            .map(|(&p, v)| PoseGap {
                pose: pose_names
                    .get(p)
                    .cloned()
                    .unwrap_or_else(|| format!("#{}", p + 1)),
                rms_mm: rms(v),
                n: v.len(),
            })
            .collect();
        worst_poses.sort_by(|a, b| b.rms_mm.total_cmp(&a.rms_mm));
        worst_poses.truncate(5);
        if worst_poses.len() > 1 && self.total > 1.5 * self.noise_rms {
            findings.push(Finding::LargestAt {
                poses: worst_poses.iter().take(3).cloned().collect(),
            });
        }
        worst_poses
    }

    /// Workspace regions: reach and height split at their medians; a
    /// finding where one half's gaps are much larger.
    fn regions(&self, findings: &mut Vec<Finding>) -> Vec<Region> {
        let (rows, gaps) = (&self.problem.rows, self.gaps);
        let (total, noise_rms) = (self.total, self.noise_rms);
        let n = gaps.len();
        let nominal = &self.problem.base.nominal;
        let flange: Vec<Vector3<f64>> = rows
            .iter()
            .take(n)
            .map(|r| nominal.fk(&r.q).translation.vector)
            .collect();
        let reach: Vec<f64> = flange
            .iter()
            .map(|p| (p.x * p.x + p.y * p.y).sqrt())
            .collect();
        let height: Vec<f64> = flange.iter().map(|p| p.z).collect();
        let mut regions = Vec::new();
        for (split, vals) in [(Split::Reach, &reach), (Split::Height, &height)] {
            let (what, lo_name, hi_name) = split.names();
            let Some((med, [low, high])) = split_at_median(what, vals, lo_name, hi_name, gaps)
            else {
                continue;
            };
            let (rl, rh) = (low.rms_mm, high.rms_mm);
            regions.extend([low, high]);
            if total > 1.5 * noise_rms && (rh > 1.5 * rl || rl > 1.5 * rh) {
                findings.push(Finding::LargerAt {
                    split,
                    upper: rh > rl,
                    median_mm: med,
                    larger_mm: rh.max(rl),
                    smaller_mm: rh.min(rl),
                });
            }
        }
        regions
    }
}

/// The shape of `gaps` over time (see [`TimeShape`]); where no pose is
/// measured in the first time bin and again later, none.
fn time_shape(
    problem: &Problem,
    gaps: &[Vector3<f64>],
    bins: &[TimeBin],
    noise_rms: f64,
) -> Option<TimeShape> {
    let (first, last) = (bins.first()?, bins.last()?);
    if bins.len() < 2 {
        return None;
    }
    let in_first = |t: f64| t >= first.from_min && t <= first.to_min && t < last.from_min;
    let mut start: BTreeMap<usize, (Vector3<f64>, usize)> = BTreeMap::new();
    for (r, g) in problem.rows.iter().zip(gaps) {
        if in_first(r.time_min) {
            let e = start.entry(r.pose).or_insert((Vector3::zeros(), 0));
            e.0 += g;
            e.1 += 1;
        }
    }
    let late: Vec<Vector3<f64>> = problem
        .rows
        .iter()
        .zip(gaps)
        .filter(|(r, _)| r.time_min >= last.from_min)
        .filter_map(|(r, g)| start.get(&r.pose).map(|(s, k)| g - s / *k as f64))
        .collect();
    if late.is_empty() {
        return None;
    }
    let late_mm = rms(&late);
    if late_mm > 1.5 * noise_rms {
        Some(TimeShape::Grows {
            late_mm,
            late_min: [last.from_min, last.to_min],
        })
    } else if first.rms_mm > 1.5 * noise_rms {
        Some(TimeShape::FromColdStart {
            early_mm: first.rms_mm,
            early_min: [first.from_min, first.to_min],
            late_mm,
        })
    } else {
        None
    }
}

/// The gaps split at the median of `vals` (one per gap): the RMS of each
/// half, named `lo_name`/`hi_name` and `what`; `None` when a half is empty.
pub(super) fn split_at_median(
    what: &str,
    vals: &[f64],
    lo_name: &str,
    hi_name: &str,
    gaps: &[Vector3<f64>],
) -> Option<(f64, [Region; 2])> {
    let n = gaps.len().min(vals.len());
    let med = median(&vals[..n]);
    let lo: Vec<Vector3<f64>> = (0..n)
        .filter(|&i| vals[i] <= med)
        .map(|i| gaps[i])
        .collect();
    let hi: Vec<Vector3<f64>> = (0..n).filter(|&i| vals[i] > med).map(|i| gaps[i]).collect();
    if lo.is_empty() || hi.is_empty() {
        return None;
    }
    Some((
        med,
        [
            Region {
                name: format!("{lo_name} ({what} <= {med:.0} mm)"),
                rms_mm: rms(&lo),
                n: lo.len(),
            },
            Region {
                name: format!("{hi_name} ({what} > {med:.0} mm)"),
                rms_mm: rms(&hi),
                n: hi.len(),
            },
        ],
    ))
}

/// The upper median (0 for no values).
pub(super) fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s.get(s.len() / 2).copied().unwrap_or(0.0)
}

fn pearson(a: &[f64], b: &[f64]) -> Option<f64> {
    let n = a.len().min(b.len());
    if n < 3 {
        return None;
    }
    let ma = a.iter().sum::<f64>() / n as f64;
    let mb = b.iter().sum::<f64>() / n as f64;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for i in 0..n {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma).powi(2);
        sbb += (b[i] - mb).powi(2);
    }
    let d = (saa * sbb).sqrt();
    (d > 1e-300).then(|| sab / d)
}

/// Which joint's angle the gap follows: the gap of each row projected on
/// that joint's motion (∂p/∂q_k) gives the joint rotation that would explain
/// it; a harmonic of q_k fitted to those rotations says how much of the gap
/// a periodic error of axis k explains.
fn follow_joint(problem: &Problem, gaps: &[Vector3<f64>]) -> Option<JointFollow> {
    let rows = &problem.rows;
    let total: f64 = gaps.iter().map(|g| g.norm_squared()).sum();
    if total <= 0.0 || gaps.len() < 12 {
        return None;
    }
    let mut best: Option<JointFollow> = None;
    for k in 0..6 {
        let mut s = Vec::new();
        let mut w = Vec::new();
        let mut qk = Vec::new();
        for (r, g) in rows.iter().zip(gaps) {
            let scales = problem.base.thermal.scales(&r.temps);
            let h = 1e-6;
            let mut q1 = r.q;
            q1[k] += h;
            let fk = |q: &Joints| {
                problem
                    .base
                    .nominal
                    .fk_scaled(q, &scales)
                    .translation
                    .vector
            };
            let (p0, p1) = (fk(&r.q), fk(&q1));
            let jk = (p1 - p0) / h;
            let n2 = jk.norm_squared();
            if n2 < 1.0 {
                continue; // this joint barely moves the flange here
            }
            s.push(jk.dot(g) / n2);
            w.push(n2);
            qk.push(r.q[k]);
        }
        if s.len() < 12 {
            continue;
        }
        let mut distinct: Vec<f64> = qk.clone();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        let m = s.len();
        let sw: Vec<f64> = w.iter().map(|v| v.sqrt()).collect();
        let b = DVector::from_iterator(m, (0..m).map(|i| sw[i] * s[i]));
        // Energy left after a constant alone (a zero offset, in the library).
        let mean = (0..m).map(|i| w[i] * s[i]).sum::<f64>() / w.iter().sum::<f64>().max(1e-300);
        let rss_const: f64 = (0..m).map(|i| w[i] * (s[i] - mean).powi(2)).sum();
        for harmonic in 1..=8usize {
            // A harmonic needs several distinct angles per cycle to be told
            // from chance.
            if distinct.len() < 4 * harmonic + 6 {
                break;
            }
            let a = DMatrix::from_fn(m, 3, |i, c| {
                let x = harmonic as f64 * qk[i];
                sw[i] * [1.0, x.sin(), x.cos()][c]
            });
            let Ok(coef) = a.clone().svd(true, true).solve(&b, 1e-12) else {
                continue;
            };
            let rss = (&a * &coef - &b).norm_squared();
            // Only what the periodic part adds beyond a constant counts.
            let share = ((rss_const - rss) / total).clamp(0.0, 1.0);
            let amp = (coef[1] * coef[1] + coef[2] * coef[2]).sqrt() * 1e3;
            if best.as_ref().is_none_or(|b| share > b.share + 1e-9) {
                best = Some(JointFollow {
                    axis: k + 1,
                    harmonic,
                    amplitude_mrad: amp,
                    share,
                });
            }
        }
    }
    best
}

/// Fewest poses measured both before and after a step for it to be a step
/// in time rather than between poses.
const MIN_POSES_ACROSS_STEP: usize = 3;

/// A sudden step in the gap over time (on top of a smooth quadratic trend):
/// per-time mean gap vectors, the split that best fits a step.
fn find_step(problem: &Problem, gaps: &[Vector3<f64>], noise_rms: f64) -> Option<Step> {
    let mut by_time: BTreeMap<u64, (f64, Vector3<f64>, usize)> = BTreeMap::new();
    for (r, g) in problem.rows.iter().zip(gaps) {
        let key = (r.time_min * 1e6).round().max(0.0) as u64;
        let e = by_time
            .entry(key)
            .or_insert((r.time_min, Vector3::zeros(), 0));
        e.1 += g;
        e.2 += 1;
    }
    let series: Vec<(f64, Vector3<f64>, usize)> = by_time
        .into_values()
        .map(|(t, s, c)| (t, s / c as f64, c))
        .collect();
    let tn = series.len();
    if tn < 6 {
        return None;
    }
    let t0 = series[0].0;
    let span = (series[tn - 1].0 - t0).max(1e-9);
    let design = |split: Option<usize>| -> DMatrix<f64> {
        let cols = if split.is_some() { 4 } else { 3 };
        DMatrix::from_fn(tn, cols, |i, c| {
            let x = (series[i].0 - t0) / span;
            match c {
                0 => 1.0,
                1 => x,
                2 => x * x,
                _ => f64::from(u8::from(split.is_some_and(|s| i >= s))),
            }
        })
    };
    let fit = |a: &DMatrix<f64>| -> Option<(f64, Vector3<f64>)> {
        let svd = a.clone().svd(true, true);
        let mut rss = 0.0;
        let mut last = Vector3::zeros();
        for axis in 0..3 {
            let b = DVector::from_iterator(tn, series.iter().map(|s| s.1[axis]));
            let coef = svd.solve(&b, 1e-12).ok()?;
            rss += (a * &coef - &b).norm_squared();
            if a.ncols() == 4 {
                last[axis] = coef[3];
            }
        }
        Some((rss, last))
    };
    let (rss_smooth, _) = fit(&design(None))?;
    let mut best: Option<(f64, usize, Vector3<f64>)> = None;
    for split in 2..=tn - 2 {
        if let Some((rss, d)) = fit(&design(Some(split))) {
            if best.as_ref().is_none_or(|b| rss < b.0) {
                best = Some((rss, split, d));
            }
        }
    }
    let (rss_step, split, d) = best?;
    // A change over time shows only on poses measured on both sides of it:
    // where each pose is measured once (a sweep), the order of the poses
    // is the order of time, and a step between two regions of the
    // workspace would be called a step in time.
    let cut = series[split].0;
    let (mut before, mut after) = (BTreeSet::new(), BTreeSet::new());
    for r in &problem.rows {
        if r.time_min < cut {
            before.insert(r.pose);
        } else {
            after.insert(r.pose);
        }
    }
    if before.intersection(&after).count() < MIN_POSES_ACROSS_STEP {
        return None;
    }
    let rows_per_time = (gaps.len() as f64 / tn as f64).max(1.0);
    // Noise of a per-time mean, per axis.
    let sd_noise = noise_rms / 3f64.sqrt() / rows_per_time.sqrt();
    let sd_fit = (rss_step / (3.0 * (tn as f64 - 4.0)).max(1.0)).sqrt();
    let se = sd_noise.max(sd_fit)
        * (1.0 / split as f64 + 1.0 / (tn - split) as f64).sqrt()
        * 3f64.sqrt();
    // The step must take most of what a smooth trend leaves, or, where
    // every measurement time is its own (a sweep over the poses, one pose a
    // time) and noise dominates each, be overwhelming by the F test (30:
    // far past the best of hundreds of splits under noise alone).
    let f = (rss_smooth - rss_step) / 3.0 / (rss_step / (3.0 * (tn as f64 - 4.0)).max(1e-300));
    let takes_most = rss_step < 0.25 * rss_smooth || f > 30.0;
    if takes_most && d.norm() > 6.0 * se && d.norm() > 0.5 * noise_rms {
        let dir = d.normalize();
        Some(Step {
            before_min: series[split - 1].0,
            after_min: series[split].0,
            size_mm: d.norm(),
            direction: [dir.x, dir.y, dir.z],
        })
    } else {
        None
    }
}
