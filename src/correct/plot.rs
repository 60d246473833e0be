//! Pictures of a correction (SVG): the program's targets seen from above
//! and from the side in the world frame, each coloured by how far it is
//! corrected, and the correction against the minute each target is
//! reached. The library draws; the caller writes the files.
//!
//! One frame for every target: the world frame ([`Correction::world_mm`]),
//! which is the robot's base frame unless the backup stands the robot
//! elsewhere, so the views compare with the cell in RobotStudio whatever
//! work object a target is written in. Both views scale their axes
//! equally: a circle on the part is a circle in the picture.

use super::{Correction, LeftAlone, Outcome};
use crate::error::Result;
use crate::plot::{error as plot_error, svg, FONT};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::ops::Range;

/// The pictures' file names: top view, side view, correction over time.
pub const FILES: [&str; 3] = ["top.svg", "side.svg", "drift.svg"];

/// Colours of the correction scale, smallest to largest: cold to hot, each
/// dark enough to read as a small dot on white.
const SCALE: [RGBColor; 6] = [
    RGBColor(49, 54, 149),
    RGBColor(40, 110, 190),
    RGBColor(0, 150, 140),
    RGBColor(110, 160, 30),
    RGBColor(235, 140, 0),
    RGBColor(205, 20, 20),
];
/// The line joining the targets in program order.
const PATH: RGBColor = RGBColor(175, 175, 175);
const WIDTH: u32 = 1100;
const HEIGHT: u32 = 820;
const MARGIN: u32 = 12;
const X_LABELS: u32 = 46;
const Y_LABELS: u32 = 72;
/// Room for the colour scale right of a view.
const BAR: u32 = 150;
/// Room for the legend under a picture.
const LEGEND: u32 = 58;

/// A picture: its file name (one of [`FILES`]) and its SVG text.
#[derive(Debug, Clone)]
pub struct Picture {
    pub name: &'static str,
    pub svg: String,
}

/// The colour of a correction at `fraction` (0 smallest, 1 largest) of
/// the run's range.
pub fn scale_colour(fraction: f64) -> RGBColor {
    let f = if fraction.is_finite() {
        fraction.clamp(0.0, 1.0)
    } else {
        0.0
    };
    DerivedColorMap::new(&SCALE).get_color(f)
}

/// The three pictures of a run's outcome; `name` says whose (a file, a
/// task) in their titles.
pub fn pictures(outcome: &Outcome, name: &str) -> Result<Vec<Picture>> {
    let data = Data::of(outcome);
    let [top, side, drift] = FILES;
    let horizontal = data.side_axis();
    let side_title = match horizontal {
        0 => "Side view (x-z, seen from -y)",
        _ => "Side view (y-z, seen from +x)",
    };
    Ok(vec![
        Picture {
            name: top,
            svg: view(&data, name, "Top view (x-y, seen from above)", [0, 1])?,
        },
        Picture {
            name: side,
            svg: view(&data, name, side_title, [horizontal, 2])?,
        },
        Picture {
            name: drift,
            svg: drift_svg(&data, name)?,
        },
    ])
}

/// What the pictures show of an outcome.
struct Data<'a> {
    /// Corrected targets with a place in the world, in program order.
    placed: Vec<&'a Correction>,
    /// Every corrected target, in program order.
    all: Vec<&'a Correction>,
    left: &'a [LeftAlone],
    /// Derived targets (`Offs(p10, ...)`): not drawn, their bases are.
    derived: usize,
    /// The colour scale's range (mm).
    range: (f64, f64),
    /// The minutes the targets are corrected for vary (a schedule).
    timed: bool,
}

impl<'a> Data<'a> {
    fn of(outcome: &'a Outcome) -> Data<'a> {
        let mut all: Vec<&Correction> = outcome.corrections.iter().collect();
        let mut minutes: Vec<f64> = all.iter().filter_map(|c| c.time_min).collect();
        minutes.sort_by(f64::total_cmp);
        minutes.dedup();
        let timed = minutes.len() > 1;
        // Program order is the order the robot reaches the targets: by
        // time where a schedule says when, else by where the program first
        // moves to each.
        all.sort_by(|a, b| {
            let minute = |c: &Correction| c.time_min.unwrap_or(f64::INFINITY);
            let by_time = if timed {
                minute(a).total_cmp(&minute(b))
            } else {
                std::cmp::Ordering::Equal
            };
            by_time.then(a.order.cmp(&b.order))
        });
        let sizes = all.iter().map(|c| c.correction_norm_mm);
        let lo = sizes.clone().fold(f64::INFINITY, f64::min);
        let hi = sizes.fold(f64::NEG_INFINITY, f64::max);
        let range = if !(lo.is_finite() && hi.is_finite()) {
            (0.0, 0.001)
        } else if hi - lo < 1e-4 {
            // One size for all: a range a written number resolves.
            let lo = (lo - 5e-5).max(0.0);
            (lo, lo + 1e-4)
        } else {
            (lo, hi)
        };
        Data {
            placed: all
                .iter()
                .copied()
                .filter(|c| c.world_mm.is_some())
                .collect(),
            all,
            left: &outcome.left_alone,
            derived: outcome.derived.len(),
            range,
            timed,
        }
    }

    fn colour(&self, mm: f64) -> RGBColor {
        scale_colour((mm - self.range.0) / (self.range.1 - self.range.0))
    }

    /// The horizontal axis of the side view: x or y, whichever the targets
    /// spread over more (the view that shows the part's length).
    fn side_axis(&self) -> usize {
        let spread = |k: usize| {
            let v = self.placed.iter().filter_map(|c| c.world_mm.map(|p| p[k]));
            let lo = v.clone().fold(f64::INFINITY, f64::min);
            let hi = v.fold(f64::NEG_INFINITY, f64::max);
            hi - lo
        };
        if spread(1) > spread(0) {
            1
        } else {
            0
        }
    }

    /// Left alone targets that have a place, and the count of those that
    /// have none.
    fn left_placed(&self) -> (Vec<[f64; 3]>, usize) {
        let placed: Vec<[f64; 3]> = self.left.iter().filter_map(|l| l.world_mm).collect();
        let without = self.left.len() - placed.len();
        (placed, without)
    }

    /// When the targets are corrected for, in words.
    fn basis(&self) -> String {
        let minutes: Vec<f64> = self.all.iter().filter_map(|c| c.time_min).collect();
        let lo = minutes.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = minutes.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        match (minutes.is_empty(), self.timed) {
            (true, _) if self.all.is_empty() => "no target corrected".to_string(),
            (true, _) => "corrected for the steady state".to_string(),
            (false, false) => format!("corrected for minute {}", short(lo, 10.0)),
            (false, true) => format!(
                "reached at minutes {}–{}",
                short(lo, hi - lo),
                short(hi, hi - lo)
            ),
        }
    }
}

/// A minute as a person writes it (`120`, `12.5`), to the decimals a
/// span of `span` minutes needs.
fn short(v: f64, span: f64) -> String {
    let d = decimals(span).max(1);
    let text = format!("{v:.d$}");
    let text = text.trim_end_matches('0');
    text.strip_suffix('.').unwrap_or(text).to_string()
}

/// Decimals that tell apart labels about `span / 10` apart (the ticks
/// plotters picks for ten labels are at least that far apart).
fn decimals(span: f64) -> usize {
    let step = span / 10.0;
    if step.is_finite() && step > 0.0 {
        (-step.log10()).ceil().clamp(0.0, 6.0) as usize
    } else {
        0
    }
}

/// Dots small enough that thousands of targets stay apart.
fn dot_radius(n: usize) -> u32 {
    match n {
        0..=100 => 5,
        101..=1000 => 3,
        _ => 2,
    }
}

/// Ranges around `points` with one scale on both axes for a plotting area
/// of `pixels`: the larger of the two extents decides, the other is
/// widened about its middle.
fn equal_ranges(points: &[(f64, f64)], (width, height): (u32, u32)) -> (Range<f64>, Range<f64>) {
    let extent = |k: usize| {
        let v = points.iter().map(|p| if k == 0 { p.0 } else { p.1 });
        let lo = v.clone().fold(f64::INFINITY, f64::min);
        let hi = v.fold(f64::NEG_INFINITY, f64::max);
        if lo.is_finite() && hi.is_finite() {
            (lo, hi)
        } else {
            (-100.0, 100.0)
        }
    };
    let (x, y) = (extent(0), extent(1));
    let pad = ((x.1 - x.0).max(y.1 - y.0) * 0.06).max(10.0);
    let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
    let mm_per_pixel = ((x.1 - x.0 + 2.0 * pad) / w).max((y.1 - y.0 + 2.0 * pad) / h);
    let around = |(lo, hi): (f64, f64), pixels: f64| {
        let middle = (lo + hi) / 2.0;
        let half = mm_per_pixel * pixels / 2.0;
        (middle - half)..(middle + half)
    };
    (around(x, w), around(y, h))
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A chart on `area` with the label areas every picture has.
fn chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    x: Range<f64>,
    y: Range<f64>,
) -> Result<Chart<'a, 'b>> {
    ChartBuilder::on(area)
        .margin(MARGIN)
        .x_label_area_size(X_LABELS)
        .y_label_area_size(Y_LABELS)
        .build_cartesian_2d(x, y)
        .map_err(plot_error)
}

/// The mesh with labels in mm at the decimals the ranges need.
fn mesh(chart: &mut Chart, x_desc: &str, y_desc: &str, x_span: f64, y_span: f64) -> Result<()> {
    let (dx, dy) = (decimals(x_span), decimals(y_span));
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(10)
        .y_labels(10)
        .x_label_formatter(&|v| format!("{v:.dx$}"))
        .y_label_formatter(&|v| format!("{v:.dy$}"))
        .axis_desc_style((FONT, 16))
        .label_style((FONT, 14))
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(220, 220, 220))
        .draw()
        .map_err(plot_error)?;
    Ok(())
}

/// A top or side view: `axes` are the world coordinates (0 x, 1 y, 2 z)
/// across and up.
fn view(data: &Data, name: &str, what: &str, axes: [usize; 2]) -> Result<String> {
    let names = ["x", "y", "z"];
    let at = |p: &[f64; 3]| (p[axes[0]], p[axes[1]]);
    let (left, left_unplaced) = data.left_placed();
    let points: Vec<(f64, f64)> = data
        .placed
        .iter()
        .filter_map(|c| c.world_mm.as_ref().map(at))
        .chain(left.iter().map(at))
        .collect();
    svg((WIDTH, HEIGHT), |root| {
        let root = root
            .titled(
                &format!("{what}, world frame: {name}, {}", data.basis()),
                (FONT, 20),
            )
            .map_err(plot_error)?;
        let (upper, legend) = root.split_vertically(root.dim_in_pixel().1 - LEGEND);
        let (main, bar) = upper.split_horizontally(upper.dim_in_pixel().0 - BAR);
        // The plotting area's size decides the ranges that scale both axes
        // alike: measured on a chart that draws nothing.
        let pixels = chart(&main, 0.0..1.0, 0.0..1.0)?
            .plotting_area()
            .dim_in_pixel();
        let (x, y) = equal_ranges(&points, pixels);
        let (x_span, y_span) = (x.end - x.start, y.end - y.start);
        let mut c = chart(&main, x, y)?;
        mesh(
            &mut c,
            &format!("{} (mm)", names[axes[0]]),
            &format!("{} (mm)", names[axes[1]]),
            x_span,
            y_span,
        )?;
        c.draw_series(LineSeries::new(
            data.placed
                .iter()
                .filter_map(|c| c.world_mm.as_ref().map(at)),
            PATH.stroke_width(1),
        ))
        .map_err(plot_error)?;
        // Largest last, on top: where the correction is large stays seen.
        let mut dots = data.placed.clone();
        dots.sort_by(|a, b| a.correction_norm_mm.total_cmp(&b.correction_norm_mm));
        let r = dot_radius(dots.len());
        c.draw_series(dots.iter().filter_map(|k| {
            let p = k.world_mm.as_ref().map(at)?;
            Some(Circle::new(
                p,
                r,
                data.colour(k.correction_norm_mm).filled(),
            ))
        }))
        .map_err(plot_error)?;
        c.draw_series(
            left.iter()
                .map(|p| Cross::new(at(p), 6, BLACK.stroke_width(2))),
        )
        .map_err(plot_error)?;
        colour_bar(&bar, data)?;
        let unplaced = data.all.len() - data.placed.len();
        let mut first = format!(
            "dots: {} corrected target(s), coloured by the size of the correction (scale at the right)",
            data.placed.len()
        );
        if unplaced > 0 {
            first.push_str(&format!(
                "; {unplaced} without a place in the world not drawn"
            ));
        }
        legend_strip(&legend, &first, data, left_unplaced, true)
    })
}

/// The colour scale: the range of the run's corrections, in mm.
fn colour_bar(area: &DrawingArea<SVGBackend<'_>, Shift>, data: &Data) -> Result<()> {
    let (lo, hi) = data.range;
    let mut c = ChartBuilder::on(area)
        .margin(MARGIN)
        .margin_left(8)
        .margin_right(4)
        .x_label_area_size(X_LABELS)
        .set_label_area_size(LabelAreaPosition::Right, 100)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(plot_error)?;
    let d = decimals(hi - lo);
    c.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(8)
        .y_desc("correction (mm)")
        .y_label_formatter(&|v| format!("{v:.d$}"))
        .axis_desc_style((FONT, 16))
        .label_style((FONT, 14))
        .draw()
        .map_err(plot_error)?;
    const STEPS: usize = 100;
    let step = (hi - lo) / STEPS as f64;
    c.draw_series((0..STEPS).map(|i| {
        let v = lo + step * i as f64;
        Rectangle::new(
            [(0.0, v), (1.0, v + step)],
            scale_colour(i as f64 / (STEPS - 1) as f64).filled(),
        )
    }))
    .map_err(plot_error)?;
    Ok(())
}

/// The legend under a picture: what the dots are, the targets left as
/// written (and why), and the line of program order.
fn legend_strip(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    first: &str,
    data: &Data,
    left_unplaced: usize,
    crosses: bool,
) -> Result<()> {
    let style = TextStyle::from((FONT, 14).into_font());
    let x0 = (MARGIN + Y_LABELS) as i32;
    area.draw(&Text::new(first.to_string(), (x0, 4), style.clone()))
        .map_err(plot_error)?;
    let mut reasons: BTreeMap<&str, usize> = BTreeMap::new();
    for l in data.left {
        *reasons.entry(l.reason.code()).or_default() += 1;
    }
    let why: Vec<String> = reasons.iter().map(|(r, n)| format!("{r} {n}")).collect();
    let mut left = if data.left.is_empty() {
        "no target left as written".to_string()
    } else {
        format!("{} left as written ({})", data.left.len(), why.join(", "))
    };
    if !data.left.is_empty() && left_unplaced > 0 {
        left.push_str(&format!(
            "; {left_unplaced} not drawn: no place known (see the report)"
        ));
    }
    let y = 32;
    let mut x = x0;
    if crosses && !data.left.is_empty() {
        area.draw(&Cross::new((x + 6, y + 8), 6, BLACK.stroke_width(2)))
            .map_err(plot_error)?;
        x += 20;
    }
    if data.derived > 0 {
        left.push_str(&format!(
            "; {} derived (Offs, RelTool) not drawn: they move with their bases",
            data.derived
        ));
    }
    if crosses {
        left.push(';');
    }
    area.draw(&Text::new(left.clone(), (x, y), style.clone()))
        .map_err(plot_error)?;
    if crosses {
        // Text width as plotters estimates it for the SVG.
        let (w, _) = area.estimate_text_size(&left, &style).map_err(plot_error)?;
        x += w as i32 + 14;
        area.draw(&PathElement::new(
            vec![(x, y + 8), (x + 24, y + 8)],
            PATH.stroke_width(2),
        ))
        .map_err(plot_error)?;
        let order = if data.timed {
            "the targets in the order they are reached"
        } else {
            "the targets in program order"
        };
        area.draw(&Text::new(order.to_string(), (x + 30, y), style))
            .map_err(plot_error)?;
    }
    Ok(())
}

/// The correction of each target against the minute it is reached (or
/// its place in program order, when all are corrected for one moment).
fn drift_svg(data: &Data, name: &str) -> Result<String> {
    let n = data.all.len();
    let xs: Vec<Option<f64>> = data
        .all
        .iter()
        .enumerate()
        .map(|(i, c)| {
            if data.timed {
                c.time_min
            } else {
                Some(i as f64 + 1.0)
            }
        })
        .collect();
    let lo = xs.iter().flatten().copied().fold(f64::INFINITY, f64::min);
    let hi = xs
        .iter()
        .flatten()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else if lo.is_finite() {
        (lo - 1.0, lo + 1.0)
    } else {
        (0.0, 1.0)
    };
    let pad = (hi - lo) * 0.03;
    let top = data
        .all
        .iter()
        .map(|c| c.correction_norm_mm)
        .fold(0.0, f64::max);
    let top = if top > 0.0 { top * 1.08 } else { 0.001 };
    let x_desc = if data.timed {
        "minute the target is reached (since the cold start)".to_string()
    } else {
        format!("target in program order ({})", data.basis())
    };
    svg((WIDTH, HEIGHT - 120), |root| {
        let root = root
            .titled(
                &format!("Correction along the program: {name}, {}", data.basis()),
                (FONT, 20),
            )
            .map_err(plot_error)?;
        let (upper, legend) = root.split_vertically(root.dim_in_pixel().1 - LEGEND);
        let mut c = chart(&upper, (lo - pad)..(hi + pad), 0.0..top)?;
        let x_span = if data.timed { hi - lo } else { 100.0 };
        mesh(&mut c, &x_desc, "correction (mm)", x_span, top)?;
        let r = dot_radius(n);
        c.draw_series(data.all.iter().zip(&xs).filter_map(|(k, x)| {
            let at = ((*x)?, k.correction_norm_mm);
            Some(Circle::new(
                at,
                r,
                data.colour(k.correction_norm_mm).filled(),
            ))
        }))
        .map_err(plot_error)?;
        let missing = xs.iter().filter(|x| x.is_none()).count();
        let mut first = format!(
            "dots: {} corrected target(s), coloured as in the top and side views",
            n - missing
        );
        if missing > 0 {
            first.push_str(&format!("; {missing} at the steady state not drawn"));
        }
        legend_strip(&legend, &first, data, 0, false)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_scale_both_axes_alike_and_hold_every_point() {
        let points = [(0.0, 0.0), (400.0, 50.0), (200.0, -30.0)];
        for pixels in [(800, 600), (300, 900)] {
            let (x, y) = equal_ranges(&points, pixels);
            let sx = (x.end - x.start) / f64::from(pixels.0);
            let sy = (y.end - y.start) / f64::from(pixels.1);
            assert!((sx - sy).abs() < 1e-9 * sx, "{sx} {sy}");
            for p in points {
                assert!(x.contains(&p.0) && y.contains(&p.1), "{p:?}");
            }
        }
        // No point: a range all the same.
        let (x, y) = equal_ranges(&[], (100, 100));
        assert!(x.end > x.start && y.end > y.start);
    }

    #[test]
    fn the_scale_runs_cold_to_hot_and_ignores_nonsense() {
        assert_eq!(scale_colour(0.0), SCALE[0]);
        assert_eq!(scale_colour(1.0), SCALE[SCALE.len() - 1]);
        assert_eq!(scale_colour(f64::NAN), SCALE[0]);
        assert_eq!(scale_colour(7.0), SCALE[SCALE.len() - 1]);
    }
}
