//! When each target is reached: a fixed time (`--at`), the user's schedule
//! file (`--schedule`), or an estimate from the program itself (walking
//! the entry routine and timing each move). Times are minutes since the
//! robot's cold start; target identifiers are those of
//! `shared/spec/formats.md`.

use crate::csv_table::CsvTable;
use crate::error::{Error, Result};
use crate::robot::Joints;
use nalgebra::Isometry3;
use std::collections::BTreeMap;

/// RAPID `speeddata`: TCP speed (mm/s), reorientation speed (°/s), linear
/// and rotational external-axis speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedData {
    pub v_tcp: f64,
    pub v_ori: f64,
    pub v_leax: f64,
    pub v_reax: f64,
}

/// The predefined speeddata of the RAPID reference manual: `v5` … `v7000`
/// are `[n, 500, 5000, 1000]`; `vmax` is the robot's maximum TCP speed,
/// taken as 5000 mm/s for this family.
pub fn predefined_speed(name: &str) -> Option<SpeedData> {
    const NAMED: [u32; 25] = [
        5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000, 1500, 2000,
        2500, 3000, 4000, 5000, 6000, 7000,
    ];
    let lower = name.to_ascii_lowercase();
    let v_tcp = if lower == "vmax" {
        5000.0
    } else {
        let n: u32 = lower.strip_prefix('v')?.parse().ok()?;
        if !NAMED.contains(&n) {
            return None;
        }
        f64::from(n)
    };
    Some(SpeedData {
        v_tcp,
        v_ori: 500.0,
        v_leax: 5000.0,
        v_reax: 1000.0,
    })
}

/// Seconds for a linear move (MoveL, MoveC approximated by its chord
/// unless the caller passes the arc length): the slower of the TCP path at
/// `v_tcp` and the reorientation at `v_ori`, as the controller does.
/// Acceleration phases are ignored: at the minute scale of a warm-up they
/// shift times by well under a second per move.
pub fn linear_move_seconds(from: &Isometry3<f64>, to: &Isometry3<f64>, speed: &SpeedData) -> f64 {
    let dist = (to.translation.vector - from.translation.vector).norm();
    let angle = from.rotation.angle_to(&to.rotation).to_degrees();
    seconds_for(dist, speed.v_tcp).max(seconds_for(angle, speed.v_ori))
}

/// Seconds for a joint move (MoveJ, MoveAbsJ): the axis that needs longest
/// at its maximum speed sets the time, and the TCP may not exceed `v_tcp`
/// along the straight line between the two poses (a lower bound of its
/// true path).
pub fn joint_move_seconds(
    from: &Joints,
    to: &Joints,
    max_speed_deg_s: &[f64; 6],
    tcp_distance_mm: f64,
    speed: &SpeedData,
) -> f64 {
    let axes = (0..6)
        .map(|i| seconds_for((to[i] - from[i]).abs().to_degrees(), max_speed_deg_s[i]))
        .fold(0.0, f64::max);
    axes.max(seconds_for(tcp_distance_mm, speed.v_tcp))
}

fn seconds_for(amount: f64, rate: f64) -> f64 {
    if rate > 0.0 {
        amount / rate
    } else {
        0.0
    }
}

/// Which of a target's several visits its correction is computed for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Visit {
    First,
    #[default]
    Mean,
    Last,
}

impl Visit {
    /// The time chosen among `times` (which must not be empty).
    pub fn pick(self, times: &[f64]) -> f64 {
        match self {
            Visit::First => times.iter().copied().fold(f64::INFINITY, f64::min),
            Visit::Last => times.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Visit::Mean => times.iter().sum::<f64>() / times.len() as f64,
        }
    }
}

/// When each target is reached: every visit of every target, in minutes.
/// Keys are target identifiers as written (lookups ignore case, as RAPID
/// does).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Schedule {
    visits: BTreeMap<String, Vec<f64>>,
    /// Identifiers in first-visit order, for stable output.
    order: Vec<String>,
}

impl Schedule {
    pub fn new() -> Schedule {
        Schedule::default()
    }

    /// Record one visit of `target` at `time_min`.
    pub fn visit(&mut self, target: &str, time_min: f64) {
        let key = target.to_ascii_lowercase();
        let entry = self.visits.entry(key).or_default();
        if entry.is_empty() {
            self.order.push(target.to_string());
        }
        entry.push(time_min);
    }

    /// All visit times of a target, in the order recorded.
    pub fn times(&self, target: &str) -> Option<&[f64]> {
        self.visits
            .get(&target.to_ascii_lowercase())
            .map(Vec::as_slice)
    }

    /// Target identifiers in the order they were first visited.
    pub fn targets(&self) -> &[String] {
        &self.order
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// Read a schedule file (`target,time_min`). Several rows may name one
    /// target: each is a visit.
    pub fn read(file: &str, bytes: &[u8]) -> Result<Schedule> {
        let table = CsvTable::parse(file, bytes)?;
        let target = table.require("target")?;
        let time = table.require("time_min")?;
        let mut schedule = Schedule::new();
        for row in &table.rows {
            let name = table.text(row, target)?;
            if name.is_empty() {
                return Err(
                    Error::input("empty target identifier").at(table.field_location(row, target))
                );
            }
            let t = table.number(row, time)?;
            if t < 0.0 {
                return Err(Error::input(format!(
                    "time {t} min is before the cold start (times are minutes since it)"
                ))
                .at(table.field_location(row, time)));
            }
            schedule.visit(name, t);
        }
        Ok(schedule)
    }

    /// The schedule as CSV, one row per visit in time order: the format
    /// [`Schedule::read`] takes back.
    pub fn to_csv(&self) -> String {
        let mut rows: Vec<(f64, usize, &str)> = Vec::new();
        for (i, name) in self.order.iter().enumerate() {
            if let Some(times) = self.times(name) {
                rows.extend(times.iter().map(|&t| (t, i, name.as_str())));
            }
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut out = String::from("target,time_min\n");
        for (t, _, name) in rows {
            out.push_str(&format!("{name},{t:.4}\n"));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    #[test]
    fn predefined_speeds() {
        assert_eq!(predefined_speed("v100").unwrap().v_tcp, 100.0);
        assert_eq!(predefined_speed("V1000").unwrap().v_ori, 500.0);
        assert_eq!(predefined_speed("vmax").unwrap().v_tcp, 5000.0);
        assert!(predefined_speed("v123").is_none());
        assert!(predefined_speed("fine").is_none());
    }

    #[test]
    fn linear_move_takes_the_slower_of_path_and_reorientation() {
        let a = Isometry3::identity();
        let b = Isometry3::from_parts(
            Translation3::new(300.0, 400.0, 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 90f64.to_radians()),
        );
        let v100 = predefined_speed("v100").unwrap();
        assert_relative_eq!(linear_move_seconds(&a, &b, &v100), 5.0, epsilon = 1e-12);
        let slow_ori = SpeedData { v_ori: 9.0, ..v100 };
        assert_relative_eq!(linear_move_seconds(&a, &b, &slow_ori), 10.0, epsilon = 1e-9);
    }

    #[test]
    fn joint_move_is_limited_by_the_slowest_axis() {
        let from = [0.0; 6];
        let to = [90f64.to_radians(), 0.0, 0.0, 0.0, 0.0, 0.0];
        let max = [200.0, 200.0, 260.0, 360.0, 360.0, 450.0];
        let v = predefined_speed("v5000").unwrap();
        assert_relative_eq!(
            joint_move_seconds(&from, &to, &max, 0.0, &v),
            0.45,
            epsilon = 1e-12
        );
        let v5 = predefined_speed("v5").unwrap();
        assert_relative_eq!(
            joint_move_seconds(&from, &to, &max, 100.0, &v5),
            20.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn visits_pick_first_mean_last() {
        let t = [40.0, 70.0, 55.0];
        assert_eq!(Visit::First.pick(&t), 40.0);
        assert_eq!(Visit::Last.pick(&t), 70.0);
        assert_relative_eq!(Visit::Mean.pick(&t), 55.0);
    }

    #[test]
    fn schedule_round_trips_through_csv() {
        let mut s = Schedule::new();
        s.visit("p10", 40.0);
        s.visit("main#3", 41.5);
        s.visit("P10", 70.0);
        let csv = s.to_csv();
        assert_eq!(
            csv,
            "target,time_min\np10,40.0000\nmain#3,41.5000\np10,70.0000\n"
        );
        let back = Schedule::read("s.csv", csv.as_bytes()).unwrap();
        assert_eq!(back.times("p10").unwrap(), &[40.0, 70.0]);
        assert_eq!(back.targets(), &["p10".to_string(), "main#3".to_string()]);
    }

    #[test]
    fn schedule_errors_are_located() {
        let e = Schedule::read("s.csv", b"target,time_min\np10,-1\n").unwrap_err();
        assert_eq!(e.location.unwrap().line, 2);
        let e = Schedule::read("s.csv", b"target\np10\n").unwrap_err();
        assert!(e.message.contains("time_min"));
    }
}
