//! SVG plot of measured and fitted heating curves, one panel per axis.
//!
//! plotters' SVG backend without its font features writes text as `<text>`
//! elements (layout estimated from the string length), so the file renders
//! anywhere without system fonts, and the same input gives the same bytes.

use super::fit::AxisFit;
use super::record::HeatingRecord;
use crate::error::{Error, Result};
use plotters::prelude::*;

const WIDTH: u32 = 1200;
const HEIGHT: u32 = 760;
/// Measured points drawn per axis at most (every k-th row beyond that):
/// keeps the file small; the curve shape and the noise band stay visible.
const MAX_MEASURED_POINTS: usize = 700;
/// Points per fitted curve.
const CURVE_POINTS: usize = 300;

/// Colours of the fitted models, in the order they are given.
const PALETTE: [RGBColor; 6] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];
const MEASURED: RGBColor = RGBColor(170, 170, 170);

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::new(
        crate::error::ErrorKind::Io,
        format!("drawing the plot failed: {e}"),
    )
}

/// Render the recording and the fitted curves (any axes, any models) as SVG.
/// Each axis that has at least one fit gets a panel.
pub fn plot_fits(record: &HeatingRecord, fits: &[AxisFit]) -> Result<String> {
    let mut axes: Vec<usize> = fits.iter().map(|f| f.axis).collect();
    axes.sort_unstable();
    axes.dedup();
    let mut models: Vec<String> = Vec::new();
    for f in fits {
        let name = f.model_name();
        if !models.contains(&name) {
            models.push(name);
        }
    }
    let (t_lo, t_hi) = (
        record.times.first().copied().unwrap_or(0.0),
        record.times.last().copied().unwrap_or(1.0),
    );
    let t_hi = if t_hi > t_lo { t_hi } else { t_lo + 1.0 };
    let step = record.len().div_ceil(MAX_MEASURED_POINTS).max(1);

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let root = root
            .titled(
                &format!("Heating curves: {} (measured and fitted)", record.file()),
                ("sans-serif", 22),
            )
            .map_err(plot_error)?;
        let cols = if axes.len() > 3 { 3 } else { axes.len().max(1) };
        let rows = axes.len().div_ceil(cols).max(1);
        let panels = root.split_evenly((rows, cols));
        for (panel, &axis) in panels.iter().zip(&axes) {
            let Some(y) = axis.checked_sub(1).and_then(|a| record.temps.get(a)) else {
                continue;
            };
            // The range covers the data and every fitted curve drawn.
            let curves: Vec<(usize, Vec<(f64, f64)>)> = fits
                .iter()
                .filter(|f| f.axis == axis)
                .map(|f| {
                    let index = models
                        .iter()
                        .position(|m| *m == f.model_name())
                        .unwrap_or(0);
                    let points = (0..=CURVE_POINTS)
                        .map(|i| {
                            let t = t_lo + (t_hi - t_lo) * i as f64 / CURVE_POINTS as f64;
                            (t, f.curve.eval(t))
                        })
                        .collect();
                    (index, points)
                })
                .collect();
            let (lo, hi) = y
                .iter()
                .chain(curves.iter().flat_map(|(_, c)| c.iter().map(|(_, v)| v)))
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            if !(lo.is_finite() && hi.is_finite()) {
                continue;
            }
            let pad = ((hi - lo) * 0.08).max(0.5);
            let mut chart = ChartBuilder::on(panel)
                .margin(8)
                .caption(format!("axis {axis}"), ("sans-serif", 18))
                .x_label_area_size(36)
                .y_label_area_size(44)
                .build_cartesian_2d(t_lo..t_hi, (lo - pad)..(hi + pad))
                .map_err(plot_error)?;
            chart
                .configure_mesh()
                .x_desc("minutes since cold start")
                .y_desc("motor temperature (°C)")
                .x_labels(6)
                .y_labels(6)
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| format!("{v:.0}"))
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(plot_error)?;
            let measured = record
                .times
                .iter()
                .zip(y)
                .step_by(step)
                .map(|(&t, &v)| (t, v));
            chart
                .draw_series(LineSeries::new(measured, MEASURED.stroke_width(5)))
                .map_err(plot_error)?
                .label("measured")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], MEASURED.stroke_width(5))
                });
            for (index, points) in curves {
                let color = PALETTE[index % PALETTE.len()];
                let name = models.get(index).cloned().unwrap_or_default();
                chart
                    .draw_series(LineSeries::new(points, color.stroke_width(2)))
                    .map_err(plot_error)?
                    .label(name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                    });
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::LowerRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 13))
                .draw()
                .map_err(plot_error)?;
        }
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}
