//! What the library's jobs tell as they run, said on standard error
//! through `messages` (`-q`, `-v`, `--color` apply), and the progress bar
//! of long corrections.

use super::messages::{self, info, note, warning};
use rapidtherm::correct::job::{Event, Host};
use rapidtherm::rapid::LaneTally;
use rapidtherm::resolve::arm::{ChosenBy, TaskArm};

/// Says each event as the command line words it.
#[derive(Default)]
pub struct EventMessages {
    bar: Option<indicatif::ProgressBar>,
}

impl Host for EventMessages {
    fn event(&mut self, e: Event<'_>) {
        match e {
            Event::TaskNote(n) | Event::Note(n) => note!("{n}"),
            Event::Reads { task, files } => {
                let files: Vec<String> = files.iter().map(|m| m.display().to_string()).collect();
                info!("task {task}: reads {}", files.join(", "));
            }
            Event::Arm {
                task,
                arm,
                not_a_backup,
            } => say_arm(task, arm, not_a_backup),
            Event::Warning(w) => messages::warning_at(w),
            Event::Lane { task, files, tally } => say_lane(task, files, tally),
            Event::ThermalModel {
                task,
                label,
                on_lengths,
            } => {
                let on = if on_lengths {
                    " on this arm's lengths"
                } else {
                    ""
                };
                info!("task {task}: thermal model: {label}{on}");
            }
            Event::InstrumentLeftOut { task } => note!(
                "task {task}: the model's tracker-frame is the frame of the instrument it was diagnosed with, not the robot's: left out of the correction"
            ),
            Event::NotMotion { task, moves: 0 } => {
                note!("task {task} is not a motion task (SYSPAR/SYS.cfg): left alone")
            }
            Event::NotMotion { task, moves } => warning!(
                "task {task} holds {moves} move instruction(s), but SYSPAR/SYS.cfg does not mark it as a motion task (-MotionTask): its targets are left cold"
            ),
            Event::Took { what, elapsed } => messages::took_for(what, elapsed),
            Event::Progress { done, total } => self.progress(done, total),
        }
    }
}

impl EventMessages {
    /// The bar of a correction: shown for long runs to a person only; the
    /// time left is estimated from the pace of the targets alone (what
    /// ran before the first, reading and the schedule, would make it many
    /// times too long).
    fn progress(&mut self, done: usize, total: usize) {
        if self.bar.is_none() && done == 0 && total >= 50_000 && messages::progress_shown() {
            let bar = indicatif::ProgressBar::new(total as u64);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "correcting {bar:40} {pos}/{len} targets ({eta} left)",
            ) {
                bar.set_style(style);
            }
            self.bar = Some(bar);
        }
        let Some(b) = &self.bar else { return };
        if done == 0 {
            b.reset_eta();
        }
        b.set_length(total as u64);
        b.set_position(done as u64);
        if done >= total {
            b.finish_and_clear();
            self.bar = None;
        }
    }
}

/// The statements the parse's fast lane began and left to the grammar,
/// one line per reason, for `-v` (a program that reads slowly says why).
fn say_lane(task: &str, files: &[String], tally: &LaneTally) {
    for (why, d) in &tally.declined {
        let file = files.get(d.file).map_or("", String::as_str);
        info!(
            "task {task}: the fast lane left {} statement(s) to the grammar: {why} (first at {file}:{})",
            d.count, d.line
        );
    }
}

/// Which arm a task moves and why, for `-v`.
pub fn say_arm(task: &str, arm: &TaskArm, not_a_backup: Option<&std::path::Path>) {
    let from = match &arm.urdf {
        Some(file) => format!("from the URDF file {file}"),
        None => "from the catalogue".to_string(),
    };
    let why = match &arm.chosen_by {
        ChosenBy::Spec(spec) => format!("chosen by --robot {spec}"),
        ChosenBy::TaskSpec { task, spec } => format!("chosen by --robot {task}={spec}"),
        ChosenBy::RobotType(rt) => {
            format!("chosen by the robot type {rt} of the backup's SYSPAR/MOC.cfg")
        }
        ChosenBy::RobotTypeVariant { robot_type, .. } => {
            format!("chosen by the robot type {robot_type} of the backup's SYSPAR/MOC.cfg")
        }
        ChosenBy::Default => {
            "chosen by default (no --robot, and no backup configuration names a robot type)"
                .to_string()
        }
        ChosenBy::ModelUrdf => "named by the model file's [robot] urdf".to_string(),
    };
    info!(
        "task {task}: arm {} ({}), {from}, {why}",
        arm.robot.name, arm.label
    );
    // A task folder under `RAPID/` without the backup's configuration is
    // read as modules (issue 49); a user who copied part of a backup would
    // otherwise not know that the arm and its place are defaults. Said
    // only where an arm is taken, and only when nothing named it.
    if let (ChosenBy::Default, Some(root)) = (&arm.chosen_by, not_a_backup) {
        note!(
            "task {task}: read as a task folder, not a controller backup ({} holds neither BACKINFO nor SYSPAR): its arm is the {} at the world origin, by default; another arm: --robot {task}=NAME|FILE.urdf",
            root.display(),
            arm.robot.name
        );
    }
    if let ChosenBy::RobotTypeVariant {
        robot_type,
        variants,
    } = &arm.chosen_by
    {
        note!(
            "task {task}: the robot type {robot_type} of SYSPAR/MOC.cfg is taken as the {} ({} assumed not to change its geometry); another arm: --robot {task}=NAME|FILE.urdf",
            arm.robot.name,
            variants.join(", ")
        );
    }
}
