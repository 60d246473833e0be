//! The measurements CSV of `docs/formats.md`: joints, measured flange
//! position (and optionally orientation, motor temperatures, ambient, pose
//! label), read with the shared CSV dialect and written back by `simulate`.
//! A set whose rows copy one another, or that gives one pose label to
//! different joints, cannot mean anything to a diagnosis: it is refused as
//! it is read, each problem at its line.

use crate::csv_table::CsvTable;
use crate::error::{Error, Result};
use crate::robot::Joints;
use crate::thermal::{plausible, MotorTemps};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

/// IRB 140 joint limits in degrees: the embedded URDF's (one source for
/// the numbers, `data/irb140/irb140.urdf`), rounded to 1e-9° so that the
/// degrees written there come back exactly through radians.
pub static IRB140_LIMITS_DEG: std::sync::LazyLock<[(f64, f64); 6]> =
    std::sync::LazyLock::new(|| {
        let deg = |r: f64| (r.to_degrees() * 1e9).round() / 1e9;
        crate::robot::Robot::irb140()
            .limits
            .map(|(lo, hi)| (deg(lo), deg(hi)))
    });

/// Largest plausible measured coordinate, mm.
pub const MAX_POSITION_MM: f64 = 100_000.0;
/// Longest plausible time since the cold start: a year, in minutes.
pub const MAX_TIME_MIN: f64 = 525_600.0;

/// One measured pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// Line in the source file (0 for generated rows).
    pub line: usize,
    pub time_min: f64,
    /// Radians.
    pub joints: Joints,
    /// Measured flange position, mm.
    pub position: Vector3<f64>,
    pub orientation: Option<UnitQuaternion<f64>>,
    pub temps: Option<MotorTemps>,
    pub ambient: Option<f64>,
    pub pose: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Measurements {
    pub file: String,
    pub rows: Vec<Measurement>,
    /// Things the user should know (ignored columns).
    pub warnings: Vec<String>,
}

const JOINT_COLS: [&str; 6] = ["j1_deg", "j2_deg", "j3_deg", "j4_deg", "j5_deg", "j6_deg"];
const TEMP_COLS: [&str; 6] = ["t1_c", "t2_c", "t3_c", "t4_c", "t5_c", "t6_c"];
const QUAT_COLS: [&str; 4] = ["qw", "qx", "qy", "qz"];

impl Measurements {
    /// Parse a measurements file. Joints outside `limits` (degrees) are an
    /// error: the controller cannot have reported them.
    pub fn parse(file: &str, bytes: &[u8], limits: &[(f64, f64); 6]) -> Result<Measurements> {
        let table = CsvTable::parse(file, bytes)?;
        let time = table.require("time_min")?;
        let mut joints = [0usize; 6];
        for (i, name) in JOINT_COLS.iter().enumerate() {
            joints[i] = table.require(name)?;
        }
        let xyz = [
            table.require("x_mm")?,
            table.require("y_mm")?,
            table.require("z_mm")?,
        ];
        let quat = optional_group(&table, &QUAT_COLS)?;
        let temps = optional_group(&table, &TEMP_COLS)?;
        let ambient = table.column("ambient_c");
        let pose = table.column("pose");
        table.check_increasing(time)?;
        let mut known: Vec<&str> = vec!["time_min", "x_mm", "y_mm", "z_mm", "ambient_c", "pose"];
        known.extend(JOINT_COLS);
        known.extend(TEMP_COLS);
        known.extend(QUAT_COLS);
        let mut warnings = table.warnings.clone();
        warnings.extend(
            table
                .unknown_columns(&known)
                .into_iter()
                .map(|c| format!("{file}: column `{c}` ignored")),
        );
        let mut rows = Vec::with_capacity(table.rows.len());
        for row in &table.rows {
            let mut q = [0.0; 6];
            for i in 0..6 {
                let deg = table.number(row, joints[i])?;
                let (lo, hi) = limits[i];
                if deg < lo - 1e-9 || deg > hi + 1e-9 {
                    return Err(Error::input(format!(
                        "axis {} at {deg}° is outside its limits {lo}..{hi}°",
                        i + 1
                    ))
                    .at(table.field_location(row, joints[i])));
                }
                q[i] = deg.to_radians();
            }
            let mut xyz_v = [0.0; 3];
            for (k, &c) in xyz.iter().enumerate() {
                let v = table.number(row, c)?;
                // Even a tracker's own frame is not kilometres away: such a
                // value is a unit or column mistake.
                if v.abs() > MAX_POSITION_MM {
                    return Err(Error::input(format!(
                        "`{}` = {v:e} mm is not a plausible position (more than {} m from the origin)",
                        table.header[c],
                        MAX_POSITION_MM / 1000.0
                    ))
                    .at(table.field_location(row, c)));
                }
                xyz_v[k] = v;
            }
            let position = Vector3::from(xyz_v);
            let orientation = match &quat {
                Some(c) => {
                    let v = [
                        table.number(row, c[0])?,
                        table.number(row, c[1])?,
                        table.number(row, c[2])?,
                        table.number(row, c[3])?,
                    ];
                    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if (norm - 1.0).abs() > 1e-3 {
                        return Err(Error::input(format!(
                            "orientation quaternion has norm {norm:.6}, not 1"
                        ))
                        .at(table.field_location(row, c[0])));
                    }
                    Some(UnitQuaternion::from_quaternion(Quaternion::new(
                        v[0], v[1], v[2], v[3],
                    )))
                }
                None => None,
            };
            let temps = match &temps {
                Some(c) => {
                    let mut t = [0.0; 6];
                    for i in 0..6 {
                        let v = table.number(row, c[i])?;
                        t[i] = plausible::check(v, || table.field_location(row, c[i]))?;
                    }
                    Some(t)
                }
                None => None,
            };
            let pose = match pose {
                Some(c) => Some(table.text(row, c)?.to_string()).filter(|s| !s.is_empty()),
                None => None,
            };
            let time_min = table.number(row, time)?;
            if !(0.0..=MAX_TIME_MIN).contains(&time_min) {
                return Err(Error::input(format!(
                    "time {time_min} min is outside 0..{MAX_TIME_MIN} (minutes since the cold start)"
                ))
                .at(table.field_location(row, time)));
            }
            rows.push(Measurement {
                line: row.line,
                time_min,
                joints: q,
                position,
                orientation,
                temps,
                ambient: match ambient {
                    Some(c) => {
                        let v = table.number(row, c)?;
                        Some(plausible::check_room(v, || table.field_location(row, c))?)
                    }
                    None => None,
                },
                pose,
            });
        }
        let meas = Measurements {
            file: file.to_string(),
            rows,
            warnings,
        };
        check_rows(&meas)?;
        Ok(meas)
    }

    pub fn has_orientation(&self) -> bool {
        !self.rows.is_empty() && self.rows.iter().all(|r| r.orientation.is_some())
    }

    pub fn has_temps(&self) -> bool {
        !self.rows.is_empty() && self.rows.iter().all(|r| r.temps.is_some())
    }

    /// The CSV text (columns present in every row are written).
    pub fn to_csv(&self) -> String {
        let ori = self.has_orientation();
        let temps = self.has_temps();
        let labels = self.rows.iter().any(|r| r.pose.is_some());
        let mut out = String::new();
        let mut header: Vec<&str> = Vec::new();
        if labels {
            header.push("pose");
        }
        header.push("time_min");
        header.extend(JOINT_COLS);
        header.extend(["x_mm", "y_mm", "z_mm"]);
        if ori {
            header.extend(QUAT_COLS);
        }
        if temps {
            header.extend(TEMP_COLS);
        }
        out.push_str(&header.join(","));
        out.push('\n');
        for r in &self.rows {
            let mut f: Vec<String> = Vec::new();
            if labels {
                f.push(csv_text(r.pose.as_deref().unwrap_or("")));
            }
            f.push(format!("{}", r.time_min));
            f.extend(r.joints.iter().map(|q| format!("{:.6}", q.to_degrees())));
            f.extend(r.position.iter().map(|v| format!("{v:.5}")));
            if let (true, Some(o)) = (ori, r.orientation) {
                let q = o.quaternion();
                let s = if q.w < 0.0 { -1.0 } else { 1.0 };
                f.extend([q.w, q.i, q.j, q.k].iter().map(|v| format!("{:.9}", s * v)));
            }
            if let (true, Some(t)) = (temps, r.temps) {
                f.extend(t.iter().map(|v| format!("{v:.3}")));
            }
            let _ = writeln!(out, "{}", f.join(","));
        }
        out
    }
}

/// Two rows with the same pose label whose joints differ by more than
/// this (degrees) do not measure one pose. A controller repeats a taught
/// pose to its encoders' resolution (thousandths of a degree); a tenth is
/// far above that and far below two poses anyone would label alike.
pub const SAME_POSE_DEG: f64 = 0.1;

/// Rows copied from one another, and pose labels used for different
/// joints: every problem, each at its line.
fn check_rows(meas: &Measurements) -> Result<()> {
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

fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// All or none of a group of columns: a partial group is an error.
fn optional_group<const N: usize>(
    table: &CsvTable,
    cols: &[&str; N],
) -> Result<Option<[usize; N]>> {
    let found: Vec<Option<usize>> = cols.iter().map(|c| table.column(c)).collect();
    if found.iter().all(Option::is_none) {
        return Ok(None);
    }
    let mut out = [0usize; N];
    for (i, c) in cols.iter().enumerate() {
        out[i] = table.require(c)?;
    }
    Ok(Some(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn irb140_limits_are_the_urdfs_in_whole_degrees() {
        // docs/model.md's limits, exactly: the URDF's radians come back as the
        // degrees docs/model.md writes.
        assert_eq!(
            *IRB140_LIMITS_DEG,
            [
                (-180.0, 180.0),
                (-90.0, 110.0),
                (-230.0, 50.0),
                (-200.0, 200.0),
                (-115.0, 115.0),
                (-400.0, 400.0),
            ]
        );
    }

    const GOOD: &str = "pose,time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm\n\
                        p1,0,0,0,0,0,0,0,515,0,712\np1,6,0,0,0,0,0,0,515.01,0,712\n";

    #[test]
    fn reads_and_writes_back() {
        let m = Measurements::parse("m.csv", GOOD.as_bytes(), &IRB140_LIMITS_DEG).unwrap();
        assert_eq!(m.rows.len(), 2);
        assert_eq!(m.rows[1].position.x, 515.01);
        assert_eq!(m.rows[0].pose.as_deref(), Some("p1"));
        let again =
            Measurements::parse("m2.csv", m.to_csv().as_bytes(), &IRB140_LIMITS_DEG).unwrap();
        assert_eq!(again.rows[1].position, m.rows[1].position);
    }

    #[test]
    fn joint_outside_limits_is_located() {
        let bad = GOOD.replace("p1,6,0,0,0", "p1,6,0,0,60");
        let e = Measurements::parse("m.csv", bad.as_bytes(), &IRB140_LIMITS_DEG).unwrap_err();
        let loc = e.location.unwrap();
        assert_eq!(loc.line, 3);
        assert!(e.message.contains("axis 3"), "{}", e.message);
    }

    #[test]
    fn partial_temperature_columns_are_an_error() {
        let bad = "time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm,t1_c\n0,0,0,0,0,0,0,515,0,712,7\n";
        let e = Measurements::parse("m.csv", bad.as_bytes(), &IRB140_LIMITS_DEG).unwrap_err();
        assert!(e.message.contains("t2_c"));
    }
}
