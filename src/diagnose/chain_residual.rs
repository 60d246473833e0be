//! Where the gap left after a calibration of a general chain lies: its
//! directions, the poses it is largest at, the workspace regions, whether it
//! follows one joint's angle or the measurement order. Each share is the
//! part of the gap's mean square a small least-squares model explains.

use super::finding::{Principal, RemainderFinding, Split};
use super::gap::{gap_stats, GapStats};
use super::locate::{split_at_median, Region};
use crate::robot::Joints;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde::Serialize;

/// One row of the remainder: joints, gap (robot base frame axes), the
/// point's position in the base frame, its order and label.
#[derive(Debug, Clone)]
pub struct ResidualRow {
    pub q: Joints,
    pub gap: Vector3<f64>,
    pub at: Vector3<f64>,
    pub time_min: f64,
    pub pose: String,
}

/// A share of the remainder explained by one pattern.
#[derive(Debug, Clone, Serialize)]
pub struct Share {
    pub what: String,
    pub share: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct ChainPoseGap {
    pub pose: String,
    pub gap_mm: f64,
}

/// The structure of a remainder.
#[derive(Debug, Clone, Serialize)]
pub struct Remainder {
    pub gap: GapStats,
    /// Principal direction (robot base frame) and its share.
    pub dominant: [f64; 3],
    pub dominant_share: f64,
    pub worst_poses: Vec<ChainPoseGap>,
    pub regions: Vec<Region>,
    /// The joint whose angle (two harmonics) explains most, and how much.
    pub joint: Option<Share>,
    /// A smooth trend over the measurement order (quadratic).
    pub order: Share,
    /// What is said about it, in order (the JSON gives their sentences).
    #[serde(
        rename = "words",
        serialize_with = "super::finding::serialize_remainder_words"
    )]
    pub findings: Vec<RemainderFinding>,
}

impl Remainder {
    /// The findings in sentences.
    pub fn words(&self) -> Vec<String> {
        self.findings.iter().map(RemainderFinding::words).collect()
    }
}

/// Share of the mean square of `gaps` that a least-squares fit of each
/// component on the columns `basis` (one row per gap) explains, beyond a
/// constant.
fn explained(basis: &DMatrix<f64>, gaps: &[Vector3<f64>]) -> f64 {
    let n = gaps.len();
    let a = DMatrix::from_fn(n, basis.ncols() + 1, |i, c| {
        if c == 0 {
            1.0
        } else {
            basis[(i, c - 1)]
        }
    });
    let svd = a.clone().svd(true, true);
    let (mut total, mut left, mut const_left) = (0.0, 0.0, 0.0);
    for axis in 0..3 {
        let b = DVector::from_iterator(n, gaps.iter().map(|g| g[axis]));
        let mean = b.mean();
        total += b.norm_squared();
        const_left += b.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
        left += match svd.solve(&b, 1e-12) {
            Ok(coef) => (&a * coef - &b).norm_squared(),
            Err(_) => b.norm_squared(),
        };
    }
    if total <= 0.0 {
        return 0.0;
    }
    ((const_left - left) / total).clamp(0.0, 1.0)
}

/// Describe the remainder of `rows`.
pub fn remainder(rows: &[ResidualRow]) -> Remainder {
    let gaps: Vec<Vector3<f64>> = rows.iter().map(|r| r.gap).collect();
    let gap = gap_stats(&gaps);
    let n = rows.len();
    let mut findings = Vec::new();

    let mut second = Matrix3::zeros();
    let mut mean = Vector3::zeros();
    for g in &gaps {
        second += g * g.transpose();
        mean += g;
    }
    let eig = second.symmetric_eigen();
    let imax = eig.eigenvalues.imax();
    let mut dominant: Vector3<f64> = eig.eigenvectors.column(imax).into();
    if dominant.dot(&mean) < 0.0 {
        dominant = -dominant;
    }
    let dominant_share = (eig.eigenvalues[imax] / second.trace().max(1e-300)).clamp(0.0, 1.0);
    findings.push(RemainderFinding::Axes {
        axis_rms_mm: gap.axis_rms_mm,
        direction: Principal::of(
            &dominant,
            &(mean / gaps.len().max(1) as f64),
            (eig.eigenvalues[imax] / gaps.len().max(1) as f64)
                .max(0.0)
                .sqrt(),
        ),
        share: dominant_share,
    });

    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| gaps[b].norm().total_cmp(&gaps[a].norm()));
    let worst_poses: Vec<ChainPoseGap> = order
        .iter()
        .take(5)
        .map(|&i| ChainPoseGap {
            pose: rows[i].pose.clone(),
            gap_mm: gaps[i].norm(),
        })
        .collect();
    if !worst_poses.is_empty() {
        findings.push(RemainderFinding::LargestAt {
            poses: worst_poses
                .iter()
                .take(3)
                .map(|p| (p.pose.clone(), p.gap_mm))
                .collect(),
        });
    }

    let mut regions = Vec::new();
    let reach: Vec<f64> = rows.iter().map(|r| r.at.xy().norm()).collect();
    let height: Vec<f64> = rows.iter().map(|r| r.at.z).collect();
    for (split, vals) in [(Split::Reach, &reach), (Split::Height, &height)] {
        let (what, ..) = split.names();
        let (lo_name, hi_name) = split.short_names();
        let Some((med, [low, high])) = split_at_median(what, vals, lo_name, hi_name, &gaps) else {
            continue;
        };
        let (rl, rh) = (low.rms_mm, high.rms_mm);
        regions.extend([low, high]);
        if rh > 1.3 * rl || rl > 1.3 * rh {
            findings.push(RemainderFinding::ByRegion {
                split,
                median_mm: med,
                lower_mm: rl,
                upper_mm: rh,
            });
        }
    }

    // Two harmonics of each joint's angle; four columns per component, so
    // that chance alone explains about 4/n of it.
    let mut joint: Option<(usize, Share)> = None;
    if n >= 20 {
        for k in 0..6 {
            let basis = DMatrix::from_fn(n, 4, |i, c| {
                let x = rows[i].q[k] * (1 + c / 2) as f64;
                if c % 2 == 0 {
                    x.sin()
                } else {
                    x.cos()
                }
            });
            let share = explained(&basis, &gaps);
            if joint.as_ref().is_none_or(|(_, j)| share > j.share) {
                joint = Some((
                    k + 1,
                    Share {
                        what: format!("axis {}", k + 1),
                        share,
                    },
                ));
            }
        }
    }
    if let Some((axis, j)) = &joint {
        findings.push(RemainderFinding::Joint {
            axis: *axis,
            share: j.share,
        });
    }
    let (t0, t1) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, r| {
            (a.0.min(r.time_min), a.1.max(r.time_min))
        });
    let span = (t1 - t0).max(1e-9);
    let basis = DMatrix::from_fn(n, 2, |i, c| {
        ((rows[i].time_min - t0) / span).powi(c as i32 + 1)
    });
    let order_share = Share {
        what: "measurement order".into(),
        share: if n >= 6 {
            explained(&basis, &gaps)
        } else {
            0.0
        },
    };
    findings.push(RemainderFinding::Order {
        share: order_share.share,
    });
    Remainder {
        gap,
        dominant: [dominant.x, dominant.y, dominant.z],
        dominant_share,
        worst_poses,
        regions,
        joint: joint.map(|(_, j)| j),
        order: order_share,
        findings,
    }
}
