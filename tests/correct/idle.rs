//! Idle spans in a schedule (`kind` `idle`): the arm cools while it
//! stands and warms again after, by the exact update of `thermal::duty`;
//! `correct --schedule` corrects for the temperatures that gives.

use super::rapidtherm;
use rapidtherm::correct::job::warm_robot;
use rapidtherm::correct::{correct, Options, ScheduleSource, When};
use rapidtherm::error::Result;
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use rapidtherm::schedule::Schedule;
use rapidtherm::thermal::{default_profile, HeatingProfile, MotorTemps};
use std::path::PathBuf;

/// The same temperatures at every minute: the closed form's, given to the
/// warm robot directly.
struct Fixed(MotorTemps);

impl HeatingProfile for Fixed {
    fn temps_at(&self, _t_min: f64) -> Result<MotorTemps> {
        Ok(self.0)
    }
}

/// The motor temperatures after 120 min running, 60 standing and 30
/// running again, by hand: each term's rise x grows as Δ(1 − e^(−t/τ))
/// from a cold start, decays as x·e^(−t/τ) while the robot stands, and
/// tends to Δ again as Δ + (x − Δ)·e^(−t/τ) while it runs.
fn closed_form_210() -> MotorTemps {
    let curves = &default_profile().axes;
    std::array::from_fn(|a| {
        let c = &curves[a];
        c.t0 + c
            .terms
            .iter()
            .map(|t| {
                let x120 = t.delta * (1.0 - (-120.0 / t.tau).exp());
                let x180 = x120 * (-60.0 / t.tau).exp();
                t.delta + (x180 - t.delta) * (-30.0 / t.tau).exp()
            })
            .sum::<f64>()
    })
}

fn sample(name: &str) -> Vec<u8> {
    std::fs::read(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(name)).unwrap()
}

const IDLE_SCHEDULE: &str = "target,time_min,kind,end_min\n,120,idle,180\n";

#[test]
fn a_stop_cools_the_arm_as_the_closed_form_says_on_every_sample() {
    let model = Model::default();
    let closed = closed_form_210();
    let (mut checked, mut cooled_by) = (0, 0.0f64);
    for name in [
        "samples/fixtures.mod",
        "samples/weld_cell_latin1.mod",
        "samples/cam_contour.mod",
        "samples/control_flow.mod",
        "tests/cmd/correct_data/cell.mod",
    ] {
        let program = rapid::parse(name, &sample(name)).unwrap();
        // Every target reached at minute 210, after a stop from 120 to 180.
        let when = When::Schedule {
            schedule: Schedule::read("idle.csv", IDLE_SCHEDULE.as_bytes()).unwrap(),
            joints: None,
            default: Some(Moment::Minute(210.0)),
            source: ScheduleSource::File,
        };
        let warm = warm_robot(Robot::irb140(), &model, &when, 210.0).unwrap();
        assert_eq!(
            warm.state(Moment::Minute(210.0))
                .unwrap()
                .temps
                .map(|t| (t * 1e9).round()),
            closed.map(|t| (t * 1e9).round()),
            "the warm robot's temperatures are the closed form's"
        );
        let got = correct(&program, &warm, &Options::new(when), &mut |_, _| {}).unwrap();
        let fixed =
            WarmRobot::with_profile(Robot::irb140(), &model, Box::new(Fixed(closed)), 210.0)
                .unwrap();
        let at = Options::new(When::At(Moment::Minute(210.0)));
        let want = correct(&program, &fixed, &at, &mut |_, _| {}).unwrap();
        let hot = WarmRobot::new(Robot::irb140(), &model, 210.0).unwrap();
        let no_stop = correct(&program, &hot, &at, &mut |_, _| {}).unwrap();
        assert_eq!(got.corrections.len(), want.corrections.len(), "{name}");
        for ((g, w), h) in got
            .corrections
            .iter()
            .zip(&want.corrections)
            .zip(&no_stop.corrections)
        {
            assert_eq!(g.id, w.id);
            let (Some(g), Some(w), Some(h)) = (g.exact, w.exact, h.exact) else {
                continue;
            };
            let miss = (g.translation.vector - w.translation.vector).norm();
            assert!(miss < 1e-9, "{name} {}: {miss} mm", w.translation.vector);
            cooled_by = cooled_by.max((h.translation.vector - g.translation.vector).norm());
            checked += 1;
        }
    }
    assert!(checked > 50, "{checked} targets");
    // The stop matters: ignoring it would miss by more than a micrometre.
    assert!(
        cooled_by > 1e-3,
        "the stop changed a correction by {cooled_by} mm"
    );
}

#[test]
fn correct_schedule_reads_the_idle_spans_and_the_marker_records_them() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("cell.mod"),
        sample("tests/cmd/correct_data/cell.mod"),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("idle.csv"),
        "target,time_min,kind,end_min\np10,120,,\n,120,idle,180\np20,210\nmain#1,210\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("busy.csv"),
        "target,time_min\np10,120\np20,210\nmain#1,210\n",
    )
    .unwrap();
    let run = |schedule: &str, out: &str| {
        let o = rapidtherm(
            &["correct", "cell.mod", "--schedule", schedule, "-o", out],
            dir.path(),
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(dir.path().join(out)).unwrap()
    };
    let idle = run("idle.csv", "idle.mod");
    let busy = run("busy.csv", "busy.mod");
    // p10 is reached before the stop: the same either way; p20 after it,
    // cooler with the stop.
    let line = |text: &str, name: &str| {
        text.lines()
            .find(|l| l.contains(&format!("robtarget {name}:=")))
            .unwrap()
            .to_string()
    };
    assert_eq!(line(&idle, "p10"), line(&busy, "p10"));
    assert_ne!(line(&idle, "p20"), line(&busy, "p20"));
    // A second run with the same schedule recognises its own output.
    let again = rapidtherm(
        &["correct", "idle.mod", "--schedule", "idle.csv", "--check"],
        dir.path(),
    );
    super::assert_exit(&again, 0);
}

#[test]
fn idle_spans_need_curves_that_cool() {
    let dir = tempfile::tempdir().unwrap();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    std::fs::write(dir.path().join("idle.csv"), IDLE_SCHEDULE).unwrap();
    let o = rapidtherm(
        &[
            "correct".as_ref(),
            root.join("tests/cmd/correct_data/cell.mod").as_os_str(),
            "--schedule".as_ref(),
            "idle.csv".as_ref(),
            "--default-time".as_ref(),
            "200".as_ref(),
            "--model".as_ref(),
            root.join("tests/cmd/correct_data/recorded.toml")
                .as_os_str(),
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("idle spans need a heating model that cools"),
        "{err}"
    );
}
