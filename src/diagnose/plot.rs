//! SVG plots of a diagnosis: the gap over time, and the gap vectors per
//! pose (top view), before and after the diagnosed effects.

use super::{Diagnosis, Prepared};
use crate::error::Result;
use crate::plot::{error as plot_err, FONT};
use nalgebra::Vector3;
use plotters::prelude::*;
use std::collections::BTreeMap;

/// Per-time RMS of gap vectors.
fn rms_by_time(times: &[f64], gaps: &[Vector3<f64>]) -> Vec<(f64, f64)> {
    let mut acc: BTreeMap<u64, (f64, f64, usize)> = BTreeMap::new();
    for (t, g) in times.iter().zip(gaps) {
        let e = acc
            .entry((t * 1e6).round().max(0.0) as u64)
            .or_insert((*t, 0.0, 0));
        e.1 += g.norm_squared();
        e.2 += 1;
    }
    acc.into_values()
        .map(|(t, s, n)| (t, (s / n as f64).sqrt()))
        .collect()
}

/// The gap over time: each row's gap size (dots) and the RMS per
/// measurement time (line), before and after.
pub fn gap_over_time_svg(prepared: &Prepared, d: &Diagnosis) -> Result<String> {
    let times: Vec<f64> = prepared.problem.rows.iter().map(|r| r.time_min).collect();
    let before = rms_by_time(&times, &d.gaps_before);
    let after = rms_by_time(&times, &d.gaps_after);
    let tmax = times.iter().copied().fold(1e-9, f64::max);
    let ymax = d
        .gaps_before
        .iter()
        .chain(&d.gaps_after)
        .map(|g| g.norm())
        .fold(1e-6, f64::max)
        * 1.05;
    crate::plot::svg((800, 480), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Gap over the warm-up (red: current model, blue: with the diagnosed effects)",
                (FONT, 16),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..tmax, 0.0..ymax)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("minutes since the cold start")
            .y_desc("gap (mm)")
            .draw()
            .map_err(plot_err)?;
        let dots = |gaps: &[Vector3<f64>], color: RGBColor| {
            times
                .iter()
                .zip(gaps)
                .map(move |(t, g)| Circle::new((*t, g.norm()), 2, color.mix(0.35).filled()))
                .collect::<Vec<_>>()
        };
        chart
            .draw_series(dots(&d.gaps_before, RED))
            .map_err(plot_err)?;
        chart
            .draw_series(dots(&d.gaps_after, BLUE))
            .map_err(plot_err)?;
        chart
            .draw_series(LineSeries::new(before, RED.stroke_width(2)))
            .map_err(plot_err)?;
        chart
            .draw_series(LineSeries::new(after, BLUE.stroke_width(2)))
            .map_err(plot_err)?;
        Ok(())
    })
}

/// Top and side views of the measured poses with their mean gap vector
/// (magnified), before and after.
pub fn gap_vectors_svg(prepared: &Prepared, d: &Diagnosis) -> Result<String> {
    let rows = &prepared.problem.rows;
    // Per pose: sums of position, gap before, gap after; count.
    type Sums = (Vector3<f64>, Vector3<f64>, Vector3<f64>, usize);
    let mut per_pose: BTreeMap<usize, Sums> = BTreeMap::new();
    for (i, r) in rows.iter().enumerate() {
        let (Some(gb), Some(ga)) = (d.gaps_before.get(i), d.gaps_after.get(i)) else {
            continue;
        };
        let e = per_pose.entry(r.pose).or_insert((
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
            0,
        ));
        e.0 += r.position;
        e.1 += gb;
        e.2 += ga;
        e.3 += 1;
    }
    let poses: Vec<(Vector3<f64>, Vector3<f64>, Vector3<f64>)> = per_pose
        .into_values()
        .map(|(p, b, a, n)| {
            let n = n as f64;
            (p / n, b / n, a / n)
        })
        .collect();
    let biggest = poses.iter().map(|p| p.1.norm()).fold(1e-6, f64::max);
    let reach = poses
        .iter()
        .map(|p| p.0.x.abs().max(p.0.y.abs()))
        .fold(100.0, f64::max)
        * 1.15;
    // Arrows a tenth of the plot wide at most.
    let scale = (0.1 * reach / biggest).max(1.0).round();
    // Side view: reach from axis 1 against height, gaps projected on the
    // radial direction and z (the top view hides vertical gaps).
    let side = |p: &Vector3<f64>, g: &Vector3<f64>| -> ((f64, f64), (f64, f64)) {
        let r = (p.x * p.x + p.y * p.y).sqrt();
        let (ux, uy) = if r > 1e-9 {
            (p.x / r, p.y / r)
        } else {
            (1.0, 0.0)
        };
        ((r, p.z), (g.x * ux + g.y * uy, g.z))
    };
    let rmax = poses
        .iter()
        .map(|p| (p.0.x * p.0.x + p.0.y * p.0.y).sqrt())
        .fold(100.0, f64::max)
        * 1.15;
    let zmax = poses.iter().map(|p| p.0.z).fold(100.0, f64::max) * 1.15;
    let zmin = poses.iter().map(|p| p.0.z).fold(0.0, f64::min) * 1.15;
    crate::plot::svg((1200, 620), |root| {
        let root = root
            .titled(
                &format!("Mean gap per pose, magnified ×{scale:.0} (red: before, blue: after)"),
                (FONT, 18),
            )
            .map_err(plot_err)?;
        let (left, right) = root.split_horizontally(600);
        let mut top = ChartBuilder::on(&left)
            .caption("top view", (FONT, 14))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(-reach..reach, -reach..reach)
            .map_err(plot_err)?;
        top.configure_mesh()
            .x_desc("x (mm)")
            .y_desc("y (mm)")
            .draw()
            .map_err(plot_err)?;
        top.draw_series(
            poses
                .iter()
                .map(|p| Circle::new((p.0.x, p.0.y), 3, BLACK.filled())),
        )
        .map_err(plot_err)?;
        let mut elevation = ChartBuilder::on(&right)
            .caption("side view (reach from axis 1, height)", (FONT, 14))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..rmax, zmin..zmax)
            .map_err(plot_err)?;
        elevation
            .configure_mesh()
            .x_desc("reach (mm)")
            .y_desc("z (mm)")
            .draw()
            .map_err(plot_err)?;
        elevation
            .draw_series(poses.iter().map(|p| {
                let (at, _) = side(&p.0, &p.1);
                Circle::new(at, 3, BLACK.filled())
            }))
            .map_err(plot_err)?;
        for (color, pick) in [(RED, 1usize), (BLUE, 2)] {
            top.draw_series(poses.iter().map(|p| {
                let g = if pick == 1 { p.1 } else { p.2 };
                PathElement::new(
                    vec![(p.0.x, p.0.y), (p.0.x + scale * g.x, p.0.y + scale * g.y)],
                    color.stroke_width(2),
                )
            }))
            .map_err(plot_err)?;
            elevation
                .draw_series(poses.iter().map(|p| {
                    let g = if pick == 1 { p.1 } else { p.2 };
                    let ((r, z), (dr, dz)) = side(&p.0, &g);
                    PathElement::new(
                        vec![(r, z), (r + scale * dr, z + scale * dz)],
                        color.stroke_width(2),
                    )
                }))
                .map_err(plot_err)?;
        }
        Ok(())
    })
}

/// The files [`plots`] names, known before the diagnosis is made.
pub const FILES: [&str; 2] = ["gap_over_time.svg", "gap_vectors.svg"];

/// The diagnosis's plots as (file name, SVG text); the caller writes them.
pub fn plots(prepared: &Prepared, d: &Diagnosis) -> Result<Vec<(&'static str, String)>> {
    Ok(vec![
        (FILES[0], gap_over_time_svg(prepared, d)?),
        (FILES[1], gap_vectors_svg(prepared, d)?),
    ])
}
