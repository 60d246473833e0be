//! Whether measured positions can be the arm's: a set whose spread is not
//! the model's (every point the same, metres read as millimetres, another
//! arm's data) still gives a fit numbers, and the verdict would sell them
//! as physics; so the set is refused. Copied rows and one pose label on
//! different joints are refused as the file is read
//! ([`super::measurements`]).

use super::fit::Problem;
use crate::error::{Error, Result};
use nalgebra::Vector3;

/// Below this spread of the model's positions about their centre (mm),
/// the poses are too close together to judge the measured spread by.
pub const MIN_JUDGED_SPREAD_MM: f64 = 5.0;

/// The measured spread may differ from the model's by this factor either
/// way. A real arm's geometry is right to a fraction of a percent; the
/// wide band leaves room for a measured point off the flange that the
/// model does not know (a reflector on a tool), while a unit mistake
/// (factor 10, 25.4 or 1000) or a constant column lies far outside it.
pub const SPREAD_FACTOR: f64 = 2.0;

/// The measured positions against the model's: their spread about their
/// centres (a rigid instrument frame keeps it) must be the arm's.
pub fn check_spread(problem: &Problem, file: &str) -> Result<()> {
    let rows: Vec<usize> = (0..problem.rows.len()).collect();
    let model: Vec<Vector3<f64>> = problem
        .predict_rows(&[], &rows)
        .iter()
        .map(|p| p.translation.vector)
        .collect();
    let measured: Vec<Vector3<f64>> = problem.rows.iter().map(|r| r.position).collect();
    let (Some(pred), Some(meas)) = (spread(&model), spread(&measured)) else {
        return Ok(());
    };
    if !pred.is_finite() || pred < MIN_JUDGED_SPREAD_MM {
        return Ok(());
    }
    let ratio = meas / pred;
    if (1.0 / SPREAD_FACTOR..=SPREAD_FACTOR).contains(&ratio) {
        return Ok(());
    }
    let n = measured.len();
    let message = if meas < 1e-6 {
        format!(
            "all {n} measured positions are the same point, while the model's spread {pred:.1} mm about their centre: the position columns hold no measurement of these poses"
        )
    } else {
        let mut m = format!(
            "the measured positions spread {meas:.4} mm about their centre, the model's {pred:.1} mm ({ratio:.4} times): these are not this arm's flange positions in millimetres"
        );
        if let Some(unit) = unit_guess(ratio) {
            m.push_str(&format!(" ({unit}?)"));
        }
        m
    };
    Err(Error::input(format!("{file}: {message}")))
}

/// RMS distance of the points from their centre; `None` for fewer than 2.
fn spread(points: &[Vector3<f64>]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let centre = points.iter().sum::<Vector3<f64>>() / n;
    Some(
        (points
            .iter()
            .map(|p| (p - centre).norm_squared())
            .sum::<f64>()
            / n)
            .sqrt(),
    )
}

/// The unit mistake a spread ratio looks like, within 15 %.
fn unit_guess(ratio: f64) -> Option<&'static str> {
    const UNITS: [(f64, &str); 5] = [
        (1e-3, "metres instead of millimetres"),
        (1e-2, "decimetres instead of millimetres"),
        (0.1, "centimetres instead of millimetres"),
        (1.0 / 25.4, "inches instead of millimetres"),
        (1e3, "micrometres instead of millimetres"),
    ];
    UNITS
        .iter()
        .find(|(r, _)| (ratio / r - 1.0).abs() < 0.15)
        .map(|(_, name)| *name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_mistakes_are_named() {
        assert_eq!(unit_guess(0.001), Some("metres instead of millimetres"));
        assert_eq!(
            unit_guess(1.0 / 25.4),
            Some("inches instead of millimetres")
        );
        assert_eq!(unit_guess(0.5), None);
    }
}
