//! What the command line names, as tasks: files one by one, program files
//! (`.pgf`), task folders and whole controller backups
//! (`rapidtherm::rapid::task`), `--task` to pick some, and the arm each
//! task moves.

use super::messages::{info, note};
use super::{read_input, Inputs};
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid::task::{self, Task};
use rapidtherm::rapid::Program;
use rapidtherm::robot::abb::{self, AbbArm};
use rapidtherm::robot::{irb140_opw, Robot};
use std::path::{Path, PathBuf};

/// `--task`: the tasks of a backup (or of several task folders) to work
/// on.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct TaskPick {
    /// With a controller backup, task folders or program files: only this
    /// task (its controller name, e.g. T_ROB1, or its folder, e.g. TASK1);
    /// may be given several times. Default: every task.
    #[arg(long = "task", value_name = "NAME")]
    pub tasks: Vec<String>,
}

/// The tasks `paths` stand for, narrowed to those `pick` names.
pub fn select(paths: &[PathBuf], pick: &TaskPick) -> Result<Vec<Task>> {
    let all = task::discover(paths)?;
    if pick.tasks.is_empty() {
        return Ok(all);
    }
    let named = |t: &Task, want: &str| {
        t.name
            .as_deref()
            .is_some_and(|n| n.eq_ignore_ascii_case(want))
            || t.origin
                .as_deref()
                .and_then(Path::file_name)
                .is_some_and(|f| f.to_string_lossy().eq_ignore_ascii_case(want))
    };
    for want in &pick.tasks {
        if !all.iter().any(|t| named(t, want)) {
            let names: Vec<String> = all.iter().map(Task::label).collect();
            return Err(Error::usage(format!(
                "--task {want}: no such task here (tasks: {})",
                names.join(", ")
            )));
        }
    }
    Ok(all
        .into_iter()
        .filter(|t| pick.tasks.iter().any(|w| named(t, w)))
        .collect())
}

/// Read a task's modules and parse them as one program; the reader's
/// warnings and the task's notes go to stderr.
pub fn read(task: &Task) -> Result<(Inputs, Program)> {
    announce(task);
    super::read_program(&task.modules)
}

/// What reading a task says before it reads: its notes, and with `-v`
/// its files.
pub fn announce(task: &Task) {
    for note in &task.notes {
        note!("{note}");
    }
    let modules: Vec<String> = task
        .modules
        .iter()
        .map(|m| m.display().to_string())
        .collect();
    info!("task {}: reads {}", task.label(), modules.join(", "));
}

/// The arm a task moves, and how the marker of a corrected file names it.
pub struct Arm {
    pub robot: Robot,
    /// For the marker: "embedded IRB 140", or a URDF file's fingerprint.
    pub label: String,
    /// Whether the arm is the IRB 140 the embedded thermal defaults were
    /// calibrated on (its geometry, whatever file it came from).
    pub is_irb140: bool,
    /// What it is (`the catalogue`, `URDF file X`) and what chose it
    /// (`--robot`, the backup's MOC.cfg, the default), for `-v`.
    pub provenance: String,
}

/// The `--robot` given for all tasks and the one given for `task`
/// (`T_ROB2=SPEC`).
fn specs_for<'a>(task: &Task, specs: &'a [String]) -> (Option<&'a str>, Option<&'a str>) {
    let mut general = None;
    let mut own = None;
    for s in specs {
        match s.split_once('=') {
            Some((t, spec)) if !Path::new(s).exists() => {
                if task
                    .name
                    .as_deref()
                    .is_some_and(|n| n.eq_ignore_ascii_case(t))
                {
                    own = Some(spec);
                }
            }
            _ => general = Some(s.as_str()),
        }
    }
    (general, own)
}

/// The arm of `task` under a model file. A model fitted on a URDF arm
/// names it: that arm where nothing else says which arm the task moves,
/// else the arm said, which must be the same (the effects are written on
/// that arm's joints: on another, they would move targets wrongly).
pub fn arm_for_model(
    task: &Task,
    specs: &[String],
    model: &rapidtherm::model::Model,
) -> Result<Arm> {
    let Some(urdf) = model.urdf_path() else {
        return arm_for(task, specs);
    };
    let (general, own) = specs_for(task, specs);
    if general.is_none() && own.is_none() && task.robot_type.is_none() {
        let mut arm = arm_of_spec(&urdf.display().to_string())?;
        arm.provenance = format!("{}, named by the model file's [robot] urdf", arm.provenance);
        say_arm(task, &arm);
        return Ok(arm);
    }
    let arm = arm_for(task, specs)?;
    let fitted = Robot::from_urdf_file(&urdf)?;
    if !same_chain(&arm.robot, &fitted) {
        return Err(Error::usage(format!(
            "task {}: the model was fitted on {} ({}), whose joints its effects are written on; the task moves {}",
            task.label(),
            fitted.name,
            urdf.display(),
            arm.robot.name
        ))
        .with_note("give a model diagnosed on this arm, or leave out --robot to use the model's"));
    }
    Ok(arm)
}

/// Whether two arms have the same chain (joint origins and axes within
/// 1e-6 mm and rad, the same tool0), whatever their names.
fn same_chain(a: &Robot, b: &Robot) -> bool {
    let close = |x: &nalgebra::Isometry3<f64>, y: &nalgebra::Isometry3<f64>| {
        (x.translation.vector - y.translation.vector).norm() < 1e-6
            && x.rotation.angle_to(&y.rotation) < 1e-6
    };
    a.chain.coupling == b.chain.coupling
        && close(&a.chain.tip, &b.chain.tip)
        && a.chain.joints.iter().zip(&b.chain.joints).all(|(x, y)| {
            close(&x.origin, &y.origin) && (x.axis.into_inner() - y.axis.into_inner()).norm() < 1e-6
        })
}

/// The arm of `task`: the `--robot` given for it (`T_ROB2=SPEC`), else the
/// `--robot` given for all, else the robot type the backup's MOC.cfg
/// names, else the embedded IRB 140.
pub fn arm_for(task: &Task, specs: &[String]) -> Result<Arm> {
    let (general, own) = specs_for(task, specs);
    let (mut arm, chosen_by) = match own.or(general) {
        Some(spec) if own.is_some() => (arm_of_spec(spec)?, format!("--robot {}={spec}", task.label())),
        Some(spec) => (arm_of_spec(spec)?, format!("--robot {spec}")),
        None => match &task.robot_type {
            Some(rt) => (arm_of_robot_type(rt).ok_or_else(|| {
                Error::usage(format!(
                    "task {}: the backup's SYSPAR/MOC.cfg says it moves a {rt}, which rapidtherm has no description of; give the arm with --robot {}=NAME|FILE.urdf",
                    task.label(),
                    task.label()
                ))
            })??, format!("the robot type {rt} of the backup's SYSPAR/MOC.cfg")),
            None => (embedded_irb140()?, "default (no --robot, no robot type in a MOC.cfg)".to_string()),
        },
    };
    arm.provenance = format!("{}, chosen by {chosen_by}", arm.provenance);
    say_arm(task, &arm);
    Ok(arm)
}

/// Which arm a task moves and why, for `-v`.
fn say_arm(task: &Task, arm: &Arm) {
    info!(
        "task {}: arm {} ({}), {}",
        task.label(),
        arm.robot.name,
        arm.label,
        arm.provenance
    );
}

/// The embedded IRB 140, the arm the thermal defaults were measured on.
fn embedded_irb140() -> Result<Arm> {
    abb::find("irb140").map(catalogue_arm)
}

fn catalogue_arm(arm: &AbbArm) -> Arm {
    let is_irb140 = arm.is_embedded_irb140();
    Arm {
        robot: arm.robot(),
        label: if is_irb140 {
            "embedded IRB 140".to_string()
        } else {
            arm.name.clone()
        },
        is_irb140,
        provenance: "from the catalogue".to_string(),
    }
}

/// `--robot`'s value: a URDF file or an arm of the catalogue by name
/// (`rapidtherm arms`), as every command's `--robot` reads it
/// (`arms::is_file`).
pub fn arm_of_spec(spec: &str) -> Result<Arm> {
    let path = Path::new(spec);
    if !super::arms::is_file(path) {
        return super::arms::find_arm(spec).map(catalogue_arm);
    }
    // Read once: the same bytes are the arm and its fingerprint.
    let (name, bytes) = read_input(path)?;
    let text = std::str::from_utf8(&bytes)
        .map_err(|_| Error::input(format!("{name}: a URDF file must be UTF-8")))?;
    let robot = Robot::from_urdf_str(&name, text)?;
    let is_irb140 = same_geometry_as_irb140(&robot);
    Ok(Arm {
        robot,
        label: rapidtherm::correct::marker::fingerprint(&bytes),
        is_irb140,
        provenance: format!("from the URDF file {name}"),
    })
}

/// The catalogue arm of a controller robot type, as MOC.cfg writes it:
/// `ROB1_140_0.81_6` is robot 1, an IRB 140 of 0.81 m reach and 6 kg;
/// `ROB1_6700_LeanID_2.65_220` has a variant word. `None` when no arm of
/// the catalogue has that family, payload and reach (within 0.05 m: types
/// write the reach to two decimals, designations to one or two).
fn arm_of_robot_type(robot_type: &str) -> Option<Result<Arm>> {
    let parts: Vec<&str> = robot_type.split('_').skip(1).collect();
    let family = parts.first()?;
    let numbers: Vec<f64> = parts[1..].iter().filter_map(|p| p.parse().ok()).collect();
    let words: Vec<&str> = parts[1..]
        .iter()
        .filter(|p| p.parse::<f64>().is_err())
        .copied()
        .collect();
    let [reach, payload] = numbers[..] else {
        return None;
    };
    let squash = |s: &str| -> String {
        s.chars()
            .filter(char::is_ascii_alphanumeric)
            .flat_map(|c| c.to_lowercase())
            .collect()
    };
    let want_family = squash(&format!("irb{family}"));
    let fits: Vec<&AbbArm> = abb::catalogue()
        .iter()
        .filter(|a| squash(&a.family) == want_family)
        .filter(|a| (a.payload_kg - payload).abs() < 0.5 && (a.reach_m - reach).abs() < 0.05)
        .filter(|a| words.iter().all(|w| squash(&a.name).contains(&squash(w))))
        .collect();
    match fits.as_slice() {
        [one] => Some(Ok(catalogue_arm(one))),
        // Some designations name a payload class, not the rated payload
        // (the IRB 2400-10 carries 12 kg): try the designation itself.
        [] if words.is_empty() => [
            format!("irb{family}-{payload}/{reach}"),
            format!("irb{family}-{payload}"),
        ]
        .iter()
        .find_map(|name| abb::find(name).ok())
        .map(|arm| Ok(catalogue_arm(arm))),
        _ => None,
    }
}

/// The embedded thermal defaults were calibrated on the IRB 140: an arm of
/// the same geometry (within a micrometre) can use them.
fn same_geometry_as_irb140(robot: &Robot) -> bool {
    let Ok(arm) = &robot.opw else { return false };
    let (a, b) = (arm.geom, irb140_opw());
    [
        (a.c1, b.c1),
        (a.a1, b.a1),
        (a.c2, b.c2),
        (a.c3, b.c3),
        (a.c4, b.c4),
        (a.a2, b.a2),
        (a.b, b.b),
    ]
    .iter()
    .all(|(x, y)| (x - y).abs() < 1e-3)
}

/// Renderings of several tasks as one output: as it is when `labels` is
/// `None` (files given one by one: one unnamed task); otherwise a heading
/// before each table, a leading `task` column in CSV, and a JSON array of
/// `{"task": …, key: …}` (plus `extra` fields per task).
pub fn join(
    format: super::Format,
    labels: Option<&[String]>,
    texts: Vec<String>,
    key: &str,
    extra: &[Vec<(&str, String)>],
) -> Result<String> {
    let Some(labels) = labels else {
        return Ok(texts.concat());
    };
    let mut out = String::new();
    match format {
        super::Format::Table => {
            for (label, text) in labels.iter().zip(&texts) {
                out.push_str(&format!("task {label}:\n{text}"));
            }
        }
        super::Format::Csv => {
            let mut header_done = false;
            for (label, text) in labels.iter().zip(&texts) {
                for (n, line) in text.lines().enumerate() {
                    if n == 0 {
                        if !header_done {
                            out.push_str(&format!("task,{line}\n"));
                            header_done = true;
                        }
                    } else {
                        out.push_str(&format!("{label},{line}\n"));
                    }
                }
            }
        }
        super::Format::Json => {
            let mut all = Vec::new();
            for (k, (label, text)) in labels.iter().zip(&texts).enumerate() {
                let value: serde_json::Value =
                    serde_json::from_str(text).map_err(|e| Error::input(e.to_string()))?;
                let mut entry = serde_json::Map::new();
                entry.insert("task".into(), label.clone().into());
                for (name, v) in extra.get(k).into_iter().flatten() {
                    entry.insert((*name).into(), v.clone().into());
                }
                entry.insert(key.into(), value);
                all.push(serde_json::Value::Object(entry));
            }
            out =
                serde_json::to_string_pretty(&all).map_err(|e| Error::input(e.to_string()))? + "\n";
        }
    }
    Ok(out)
}

/// The labels of tasks when they are named (a backup, task folders,
/// program files), `None` for files given one by one.
pub fn labels(tasks: &[&Task]) -> Option<Vec<String>> {
    (tasks.len() > 1 || tasks.iter().any(|t| t.name.is_some()))
        .then(|| tasks.iter().map(|t| t.label()).collect())
}

/// The one motion task a command that times a single robot works on.
pub fn one_motion_task(paths: &[PathBuf], pick: &TaskPick, command: &str) -> Result<Task> {
    let mut motion: Vec<Task> = select(paths, pick)?
        .into_iter()
        .filter(|t| t.motion != Some(false))
        .collect();
    match motion.len() {
        1 => Ok(motion.remove(0)),
        0 => Err(Error::usage(format!(
            "{command}: no motion task here (SYSPAR/SYS.cfg marks none)"
        ))),
        _ => {
            let names: Vec<String> = motion.iter().map(Task::label).collect();
            Err(Error::usage(format!(
                "{command} times one robot: pick one of the motion tasks {} with --task",
                names.join(", ")
            )))
        }
    }
}

/// Where a task's robot stands in the world, from the backup's MOC.cfg; a
/// robot whose base rides on another unit (a track) is refused: its base
/// is somewhere else at every target.
pub fn base_frame(task: &Task) -> Result<Option<nalgebra::Isometry3<f64>>> {
    if let Some(unit) = &task.base_moved_by {
        return Err(Error::new(
            rapidtherm::error::ErrorKind::Unsupported,
            format!(
                "task {}: its robot's base frame moves with {unit} (SYSPAR/MOC.cfg, a track or a carrier): rapidtherm cannot place the arm for its targets",
                task.label()
            ),
        ));
    }
    task.base_frame
        .map(|(pos, rot)| rapidtherm::robot::frames::pose_from_rapid(pos, rot))
        .transpose()
        .map_err(|e| {
            Error::input(format!(
                "task {}: the base frame in SYSPAR/MOC.cfg: {}",
                task.label(),
                e.message
            ))
        })
}
