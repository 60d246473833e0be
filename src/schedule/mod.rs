//! When each target is reached: a fixed time (`--at`), the user's schedule
//! file (`--schedule`), or an estimate from the program itself (walking
//! the entry routine and timing each move). Times are minutes since the
//! robot's cold start; target identifiers are those of
//! `docs/formats.md`.
//!
//! - [`SpeedData`], [`predefined_speed`], [`linear_move_seconds`],
//!   [`joint_move_seconds`]: timing one move.
//! - [`Schedule`]: every visit of every target; [`Schedule::read`] and
//!   [`Schedule::to_csv`] are the `target,time_min` file.
//! - [`Visit`]: which of a target's visits its correction is for.
//! - [`estimate`] with [`EstimateOptions`] → [`Estimate`]: walk the program
//!   (see its docs for every choice made where run-time values decide),
//!   the moves of the fast lane's runs among the program's statements.
//!
//! Owns timing. May import `rapid`, `robot`, `resolve` and the shared
//! `error` and `csv_table`; never `model`, `correct` or `diagnose`.

mod bounds;
mod cold_joints;
mod estimate;
mod file;
mod names;
mod timing;
mod walk;

pub use cold_joints::ColdJoints;
pub use estimate::{estimate, estimate_with_joints, Estimate, EstimateOptions};
pub use file::{encode_visits, IdleSpan, Schedule, ScheduleFile, WhichVisit, SCHEDULE_ENCODING};
pub use names::{ProgramNames, TargetType};
pub use timing::{joint_move_seconds, linear_move_seconds, predefined_speed, MoveSpeed};

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

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
        let slow_ori = MoveSpeed { v_ori: 9.0, ..v100 };
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
        assert_eq!(WhichVisit::First.pick(&t), 40.0);
        assert_eq!(WhichVisit::Last.pick(&t), 70.0);
        assert_relative_eq!(WhichVisit::Mean.pick(&t), 55.0);
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
        let mut grid = Schedule::new();
        grid.visit("pGrid{2,1}", 1.5);
        assert_eq!(grid.to_csv(), "target,time_min\n\"pGrid{2,1}\",1.5000\n");
        let grid_back = Schedule::read("s.csv", grid.to_csv().as_bytes()).unwrap();
        assert_eq!(grid_back.times("pgrid{2,1}").unwrap(), &[1.5]);
        let ids: Vec<&str> = back.targets().collect();
        assert_eq!(ids, ["p10", "main#3"]);
    }

    #[test]
    fn idle_spans_are_read_checked_and_written_back() {
        let csv =
            "target,time_min,kind,end_min\np10,40\n,120,idle,180\np20,180,,\nj1,200,jointtarget,\n";
        let s = Schedule::read("s.csv", csv.as_bytes()).unwrap();
        assert_eq!(
            s.idle_spans(),
            &[IdleSpan {
                from_min: 120.0,
                to_min: 180.0
            }]
        );
        assert_eq!(s.times("p20").unwrap(), &[180.0]);
        assert_eq!(s.times("j1").unwrap(), &[200.0]);
        let back = Schedule::read("s.csv", s.to_csv().as_bytes()).unwrap();
        assert_eq!(back, s);
        // Each mistake named where it is.
        for (bad, line, says) in [
            (
                "target,time_min,kind,end_min\np10,150\n,120,idle,180\n",
                2,
                "while the robot stands",
            ),
            ("target,time_min,kind\n,120,idle\n", 2, "needs its end"),
            (
                "target,time_min,kind,end_min\n,120,idle,100\n",
                2,
                "not after its start",
            ),
            (
                "target,time_min,kind,end_min\np10,120,idle,180\n",
                2,
                "names no target",
            ),
            (
                "target,time_min,kind,end_min\n,100,idle,180\n,150,idle,200\n",
                3,
                "overlaps",
            ),
            (
                "target,time_min,kind,end_min\np10,1,,5\n",
                2,
                "belongs to idle spans",
            ),
            ("target,time_min,kind\np10,1,stop\n", 2, "unknown kind"),
        ] {
            let e = Schedule::read("s.csv", bad.as_bytes()).unwrap_err();
            assert!(e.message.contains(says), "{bad}: {}", e.message);
            assert_eq!(e.location.unwrap().line, line, "{bad}");
        }
        // A visit at a span's ends is the last before the stop or the
        // first after it.
        let edge = "target,time_min,kind,end_min\np10,120\n,120,idle,180\np20,180\n";
        assert!(Schedule::read("s.csv", edge.as_bytes()).is_ok());
    }

    #[test]
    fn schedule_errors_are_located() {
        let e = Schedule::read("s.csv", b"target,time_min\np10,-1\n").unwrap_err();
        assert_eq!(e.location.unwrap().line, 2);
        let e = Schedule::read("s.csv", b"target\np10\n").unwrap_err();
        assert!(e.message.contains("time_min"));
    }
}
