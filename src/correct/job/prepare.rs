//! What a task's correction needs before its targets are solved: the
//! model, the arm (refused where its thermal behaviour would be guessed),
//! when each target is reached, the warm robot up to the last of those
//! moments, and the run's options.

use super::host::{Event, Host};
use crate::correct::plan::{Action, ArmChoice, CorrectPlan, ModelSource, TimeBasis};
use crate::correct::{OnUntrusted, Options, ScheduleSource, When};
use crate::digest::fingerprint;
use crate::error::{Error, Remedy, Result};
use crate::model::{Model, Moment, WarmRobot};
use crate::rapid::task::Task;
use crate::rapid::Program;
use crate::resolve::arm::{
    arm_for, arm_of, base_frame, check_placement, same_chain, ArmSource, ChosenBy, TaskArm,
};
use crate::robot::Robot;
use crate::schedule::{self, ColdJoints, EstimateOptions, Schedule};
use crate::thermal::duty::DutyProfile;

/// The model a plan names.
pub fn load_model(source: &ModelSource) -> Result<Model> {
    match source {
        ModelSource::Default => Ok(Model::default()),
        ModelSource::Named(name) => {
            Model::named(name).ok_or_else(|| Error::usage(format!("no embedded model `{name}`")))
        }
        ModelSource::File(path) => Model::load(path),
    }
}

/// The model and arm a run uses, as the marker of a corrected file names
/// them: the embedded ones by name, files by their fingerprint.
/// The model and arm as the marker names them.
pub fn model_label(source: &ModelSource, arm: &str) -> Result<String> {
    let model = match source {
        ModelSource::Named(name) => format!("embedded {}", name.to_ascii_lowercase()),
        ModelSource::File(path) => {
            fingerprint(&std::fs::read(path).map_err(|e| Error::io(path, &e))?)
        }
        ModelSource::Default => "embedded default".to_string(),
    };
    Ok(format!("{model} model, {arm} arm"))
}

/// The arm of a task under the plan's model, said; refused where the
/// thermal defaults would be guessed (an arm other than the IRB 140
/// without a model of its own).
pub fn checked_arm(
    plan: &ArmChoice,
    task: &Task,
    model: &Model,
    host: &mut dyn Host,
) -> Result<TaskArm> {
    let arm = arm_for_model(plan, task, model)?;
    check_placement(task, &arm, plan.placing)?;
    host.event(Event::Arm {
        task: &task.label(),
        arm: &arm,
        not_a_backup: task.not_a_backup.as_deref(),
    });
    if plan.model == ModelSource::Default && !arm.is_irb140 && !plan.irb140_thermal {
        let whose = match &task.name {
            Some(n) => format!("task {n}: "),
            None => String::new(),
        };
        return Err(Error::usage(format!(
            "{whose}{} is not an IRB 140, and how it warms up and expands is unknown: the embedded thermal defaults were measured on an IRB 140",
            arm.robot.name
        ))
        .with_note("")
        .with_remedy(Remedy::ModelOfTheArm));
    }
    Ok(arm)
}

/// The arm of `task` under a model file. A model fitted on a URDF arm
/// names it: that arm where nothing else says which arm the task moves,
/// else the arm said, which must be the same (the effects are written on
/// that arm's joints: on another, they would move targets wrongly).
fn arm_for_model(plan: &ArmChoice, task: &Task, model: &Model) -> Result<TaskArm> {
    let Some(source) = model_arm_source(model)? else {
        return arm_for(task, &plan.specs);
    };
    let said = plan.specs.iter().any(|s| {
        s.task.is_none()
            || s.task
                .as_deref()
                .zip(task.name.as_deref())
                .is_some_and(|(t, n)| t.eq_ignore_ascii_case(n))
    });
    let mut fitted = arm_of(&source)?;
    if !said && task.robot_type.is_none() {
        fitted.chosen_by = ChosenBy::ModelUrdf;
        return Ok(fitted);
    }
    let arm = arm_for(task, &plan.specs)?;
    if !same_chain(&arm.robot, &fitted.robot) {
        return Err(Error::usage(format!(
            "task {}: the model was fitted on {} ({}), whose joints its effects are written on; the task moves {}",
            task.label(),
            fitted.robot.name,
            fitted.urdf.as_deref().unwrap_or(&fitted.label),
            arm.robot.name
        ))
        .with_note("")
        .with_remedy(Remedy::ArmOfTheModel));
    }
    Ok(arm)
}

/// The arm a model file names, as an arm source: its URDF (a path or the
/// text it embeds) or a catalogue arm; `None` for OPW lengths alone,
/// which name no arm.
fn model_arm_source(model: &Model) -> Result<Option<ArmSource>> {
    let r = &model.robot;
    if let Some(text) = &r.urdf_text {
        // The same check of the joint convention as every reader's.
        model.arm()?;
        return Ok(Some(ArmSource::UrdfText {
            name: format!("the URDF in the model's [robot] ({})", r.name),
            text: text.clone(),
        }));
    }
    if let Some(name) = &r.catalogue {
        let arm = crate::robot::abb::find(name)
            .map_err(|e| e.with_note("the arm named by the model's [robot] catalogue"))?;
        return Ok(Some(ArmSource::Catalogue(arm)));
    }
    Ok(model.urdf_path().map(ArmSource::Urdf))
}

/// When the targets are reached, from the plan's time basis, the notes
/// of the estimate (none for the others), not yet said, and the cold
/// joints its walk found.
pub fn when_and_notes(
    plan: &CorrectPlan,
    program: &Program,
    robot: &Robot,
    base_frame: Option<nalgebra::Isometry3<f64>>,
) -> Result<(When, Vec<String>, Option<ColdJoints>)> {
    Ok(match &plan.when {
        TimeBasis::At(moment) => (When::At(*moment), Vec::new(), None),
        TimeBasis::Schedule { file, default } => {
            let (name, bytes) = read_named(file)?;
            // Every row checked against this program's targets of its
            // kind, at its line: a row of a jointtarget the program does
            // not have is not a robtarget's visit.
            let names = schedule::ProgramNames::of(program);
            let read = Schedule::read_file(&name, &bytes, Some(&names))?;
            let when = When::Schedule {
                schedule: read.schedule,
                joints: read.joints,
                default: *default,
                source: ScheduleSource::File,
            };
            (when, read.warnings, None)
        }
        TimeBasis::Start { default, .. } => {
            let opts = estimate_options(plan, base_frame).unwrap_or_default();
            let (estimate, joints) = schedule::estimate_with_joints(program, robot, &opts)?;
            let when = When::Schedule {
                schedule: estimate.schedule,
                joints: Some(estimate.joint_schedule),
                default: *default,
                source: ScheduleSource::Estimate(Box::new(opts)),
            };
            (when, estimate.notes, Some(joints))
        }
    })
}

/// A file's name in messages and its bytes (`-`: standard input).
pub fn read_named(path: &std::path::Path) -> Result<(String, Vec<u8>)> {
    if path == std::path::Path::new("-") {
        let mut buf = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin(), &mut buf)
            .map_err(|e| Error::io(std::path::Path::new("<stdin>"), &e))?;
        Ok(("<stdin>".to_string(), buf))
    } else {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, &e))?;
        Ok((path.display().to_string(), bytes))
    }
}

/// The walk of the plan's estimate; `None` where it has none.
pub fn estimate_options(
    plan: &CorrectPlan,
    base_frame: Option<nalgebra::Isometry3<f64>>,
) -> Option<EstimateOptions> {
    match &plan.when {
        TimeBasis::Start {
            start_min,
            entry,
            cycles,
            ..
        } => Some(EstimateOptions {
            entry: entry.clone(),
            start_min: *start_min,
            cycles: *cycles,
            base_frame,
        }),
        _ => None,
    }
}

/// The warm robot of `model` on `robot` for a run `when`, until minute
/// `horizon`: where a schedule has idle spans, the model's heating curves
/// driven through them, cooling in each (the exact update of
/// `thermal::duty`, the one the controller module runs); an error where
/// the curves cannot cool (a polynomial, a recording).
pub fn warm_robot(robot: Robot, model: &Model, when: &When, horizon: f64) -> Result<WarmRobot> {
    match when {
        When::Schedule { schedule, .. } if !schedule.idle_spans().is_empty() => {
            let changes = DutyProfile::spans_to_changes(
                schedule.idle_spans().iter().map(|s| (s.from_min, s.to_min)),
            );
            let duty = DutyProfile::over(model.profile()?.as_ref(), &changes)?;
            WarmRobot::with_profile(robot, model, Box::new(duty), horizon)
        }
        _ => WarmRobot::new(robot, model, horizon),
    }
}

/// The warm robot a task's run needs until `when`'s last minute, and the
/// run's options: (arm name, warm robot, options).
pub fn warm_run(
    plan: &CorrectPlan,
    model: &Model,
    task: &Task,
    arm: TaskArm,
    when: When,
    host: &mut dyn Host,
) -> Result<(String, WarmRobot, Options)> {
    let horizon = match &when {
        When::At(Moment::Minute(t)) => *t,
        When::At(Moment::Steady) => 0.0,
        When::Schedule {
            schedule,
            joints,
            default,
            ..
        } => {
            let latest = std::iter::once(schedule)
                .chain(joints)
                .flat_map(Schedule::all_times)
                .fold(0.0, f64::max);
            match default {
                Some(Moment::Minute(t)) => latest.max(*t),
                _ => latest,
            }
        }
    };
    let arm_name = arm.robot.name.clone();
    let label = task.label();
    let warm = warm_robot(arm.robot, model, &when, horizon)?;
    if warm.instrument_left_out() {
        host.event(Event::InstrumentLeftOut { task: &label });
    }
    let model_label = model_label(&plan.arms.model, &arm.label)?;
    host.event(Event::ThermalModel {
        task: &label,
        label: &model_label,
        on_lengths: plan.arms.model == ModelSource::Default && !arm.is_irb140,
    });
    let options = Options {
        when,
        visit: plan.visit,
        expand_expressions: plan.expand_expressions,
        model_label,
        base_frame: base_frame(task)?,
        split_shared: plan.split_shared,
        // A run that writes would correct corrected numbers again; one
        // that only looks takes them as cold and says why.
        untrusted: match plan.action {
            Action::Write(_) => OnUntrusted::Refuse,
            Action::Check(_) | Action::Diff { .. } | Action::Report => OnUntrusted::AsCold,
        },
    };
    Ok((arm_name, warm, options))
}
