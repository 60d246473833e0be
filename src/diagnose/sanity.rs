//! Whether a measurement set can mean anything to a diagnosis: copied
//! rows, one pose label on different joints, and measured positions whose
//! spread is not the arm's (every point the same, metres read as
//! millimetres, another arm's data). A fit on such a set still returns
//! numbers, and the verdict would sell them as physics; so the set is
//! refused, each problem named at its line.

use super::measurements::Measurements;
use super::prepare::Prepared;
use crate::error::{Error, Result};
use nalgebra::Vector3;
use std::collections::{HashMap, HashSet};

/// Two rows with the same pose label whose joints differ by more than
/// this (degrees) do not measure one pose. A controller repeats a taught
/// pose to its encoders' resolution (thousandths of a degree); a tenth is
/// far above that and far below two poses anyone would label alike.
pub const SAME_POSE_DEG: f64 = 0.1;

/// Below this spread of the model's positions about their centre (mm),
/// the poses are too close together to judge the measured spread by.
pub const MIN_JUDGED_SPREAD_MM: f64 = 5.0;

/// The measured spread may differ from the model's by this factor either
/// way. A real arm's geometry is right to a fraction of a percent; the
/// wide band leaves room for a measured point off the flange that the
/// model does not know (a reflector on a tool), while a unit mistake
/// (factor 10, 25.4 or 1000) or a constant column lies far outside it.
pub const SPREAD_FACTOR: f64 = 2.0;

/// Rows copied from one another, and pose labels used for different
/// joints: every problem, each at its line.
pub fn check_rows(meas: &Measurements) -> Result<()> {
    let mut errors = Vec::new();
    // Exact copies: time, joints and position equal to the last bit. A
    // tracker's noise makes that impossible for two real measurements.
    let mut first_of: HashMap<[u64; 10], usize> = HashMap::new();
    // The copied rows of each original, in the order the originals were
    // first copied (a map from original to its place: linear in the rows
    // however many are copied).
    let mut copies: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut copied_at: HashMap<usize, usize> = HashMap::new();
    for (k, m) in meas.rows.iter().enumerate() {
        let mut key = [0u64; 10];
        key[0] = m.time_min.to_bits();
        for i in 0..6 {
            key[1 + i] = m.joints[i].to_bits();
        }
        for i in 0..3 {
            key[7 + i] = m.position[i].to_bits();
        }
        match first_of.get(&key) {
            Some(&orig) => match copied_at.get(&orig) {
                Some(&i) => copies[i].1.push(k),
                None => {
                    copied_at.insert(orig, copies.len());
                    copies.push((orig, vec![k]));
                }
            },
            None => {
                first_of.insert(key, k);
            }
        }
    }
    for (orig, repeats) in &copies {
        let line = meas.rows[*orig].line;
        let first = &meas.rows[repeats[0]];
        let message = if repeats.len() == 1 {
            format!("this row repeats line {line} exactly (time, joints and position): a copied row is not a second measurement")
        } else {
            format!(
                "this row and {} more repeat line {line} exactly (time, joints and position): copied rows are not new measurements",
                repeats.len() - 1
            )
        };
        errors.push(Error::input_at(&meas.file, first.line, 1, message));
    }
    // One label, one pose: the noise is estimated from a label's repeats.
    let mut by_label: HashMap<&str, usize> = HashMap::new();
    let mut reported: HashSet<&str> = HashSet::new();
    for (k, m) in meas.rows.iter().enumerate() {
        let Some(label) = m.pose.as_deref() else {
            continue;
        };
        let Some(&first) = by_label.get(label) else {
            by_label.insert(label, k);
            continue;
        };
        let a = &meas.rows[first];
        let worst = (0..6)
            .map(|i| (i, (m.joints[i] - a.joints[i]).abs().to_degrees()))
            .fold((0, 0.0), |w, c| if c.1 > w.1 { c } else { w });
        if worst.1 > SAME_POSE_DEG && reported.insert(label) {
            errors.push(Error::input_at(
                &meas.file,
                m.line,
                1,
                format!(
                    "pose `{label}` has other joints here than at line {} (axis {}: {:.3}° against {:.3}°): a pose label names one pose, and its repeats give the noise",
                    a.line,
                    worst.0 + 1,
                    m.joints[worst.0].to_degrees(),
                    a.joints[worst.0].to_degrees()
                ),
            ));
        }
    }
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The measured positions against the model's: their spread about their
/// centres (a rigid instrument frame keeps it) must be the arm's.
pub fn check_spread(prepared: &Prepared, file: &str) -> Result<()> {
    let problem = &prepared.problem;
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
