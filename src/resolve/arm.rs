//! The arm a task moves and where it stands: the arm named for the task
//! (a URDF file or an arm of the catalogue), else the robot type its
//! backup's MOC.cfg names, else the embedded IRB 140; and its base frame
//! in the world. Which arm was chosen, and why, is returned as data
//! ([`ChosenBy`]) for the caller to say.

use crate::digest::fingerprint;
use crate::error::{Error, ErrorKind, Remedy, Result};
use crate::rapid::task::placement::Unknown;
use crate::rapid::task::Task;
use crate::robot::abb::{self, AbbArm};
use crate::robot::{irb140_opw, Robot};
use std::path::{Path, PathBuf};

/// Where an arm named by the user comes from.
#[derive(Debug, Clone)]
pub enum ArmSource {
    /// A URDF file, read when the arm is resolved.
    Urdf(PathBuf),
    /// An arm of the catalogue.
    Catalogue(&'static AbbArm),
    /// A URDF's text, as a model file embeds it; `name` names it in
    /// messages.
    UrdfText { name: String, text: String },
}

/// An arm named for every task (`task` `None`) or for one task of a
/// backup, and how it was written (for messages).
#[derive(Debug, Clone)]
pub struct ArmSpec {
    pub task: Option<String>,
    pub source: ArmSource,
    pub written: String,
}

/// Whether an arm's name is a URDF file's (a file that exists, or a path
/// ending in `.urdf`) rather than a catalogue name.
pub fn names_a_file(spec: &Path) -> bool {
    spec.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
        || spec.is_file()
}

/// What chose a task's arm.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ChosenBy {
    /// The arm named for every task, as written.
    Spec(String),
    /// The arm named for this task (`TASK=ARM`), as written after the `=`.
    TaskSpec { task: String, spec: String },
    /// The robot type of the backup's MOC.cfg.
    RobotType(String),
    /// The robot type of the backup's MOC.cfg, a variant of a catalogue
    /// arm (`ROB1_1200_0.9_5_TypeB`) taken as that arm: `variants` are the
    /// type's words the catalogue has no arm of (`TypeB`), which the
    /// caller must say were assumed not to change the geometry.
    RobotTypeVariant {
        robot_type: String,
        variants: Vec<String>,
    },
    /// Nothing named one: the embedded IRB 140.
    Default,
    /// The URDF file a model file names (its effects are written on that
    /// arm's joints).
    ModelUrdf,
}

/// The arm a task moves, and how the marker of a corrected file names it.
#[derive(Debug, Clone)]
pub struct TaskArm {
    pub robot: Robot,
    /// For the marker: "embedded IRB 140", a catalogue name, or a URDF
    /// file's fingerprint.
    pub label: String,
    /// Whether the arm is the IRB 140 the embedded thermal defaults were
    /// calibrated on (its geometry, whatever file it came from).
    pub is_irb140: bool,
    /// The URDF file it was read from; `None`: the catalogue.
    pub urdf: Option<String>,
    pub chosen_by: ChosenBy,
}

/// Every arm named for a task (`TASK=ARM`) names a task of the run: a
/// misspelt task, or a task name given for single files (which have no
/// task names), would otherwise leave the arm silently unused.
pub fn check_task_specs(specs: &[ArmSpec], tasks: &[Task]) -> Result<()> {
    let names: Vec<&str> = tasks.iter().filter_map(|t| t.name.as_deref()).collect();
    let mut errors = Vec::new();
    for s in specs {
        let Some(t) = s.task.as_deref() else { continue };
        if names.iter().any(|n| n.eq_ignore_ascii_case(t)) {
            continue;
        }
        let why = if names.is_empty() {
            "the files of this run are one program, not a backup's tasks: name the arm alone"
                .to_string()
        } else {
            format!("its tasks are {}", names.join(", "))
        };
        errors.push(Error::usage(format!(
            "`{t}={}` names task {t}, which this run does not have ({why})",
            s.written
        )));
    }
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Whether a task whose backup does not say what its robot is, or where
/// it stands, may take the default: the arm named (else the IRB 140) at
/// the world origin. A backup copied by hand or cut short must not move a
/// correction by where the robot happens not to be: only the user says so.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Placing {
    /// The backup places the robot, or the run is refused.
    #[default]
    FromBackup,
    /// The user accepted the default placement (`--accept-default-placement`).
    AcceptDefault,
}

/// Refuse `task` where its backup leaves unknown what the run needs: where
/// the robot stands, and which arm it is unless one was named (by
/// `--robot` or a model file). Every such gap is one error, at its file
/// and line.
pub fn check_placement(task: &Task, arm: &TaskArm, placing: Placing) -> Result<()> {
    if placing == Placing::AcceptDefault {
        return Ok(());
    }
    let named = !matches!(
        arm.chosen_by,
        ChosenBy::Default | ChosenBy::RobotType(_) | ChosenBy::RobotTypeVariant { .. }
    );
    let mut errors: Vec<Error> = task
        .gaps
        .iter()
        .filter(|g| !(named && g.kind.unknown() == Unknown::Type))
        .map(|g| g.to_error(&task.label()))
        .collect();
    // The remedy once, after the last gap.
    if let Some(last) = errors.pop() {
        errors.push(last.with_remedy(Remedy::AcceptDefaultPlacement));
    }
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The arm of `task`: the one named for it (`TASK=ARM`), else the one
/// named for all, else the robot type the backup's MOC.cfg names, else
/// the embedded IRB 140.
pub fn arm_for(task: &Task, specs: &[ArmSpec]) -> Result<TaskArm> {
    let own = specs.iter().rev().find(|s| {
        s.task
            .as_deref()
            .zip(task.name.as_deref())
            .is_some_and(|(t, n)| t.eq_ignore_ascii_case(n))
    });
    let general = specs.iter().rev().find(|s| s.task.is_none());
    let (mut arm, chosen_by) = match (own, general) {
        (Some(s), _) => (
            arm_of(&s.source)?,
            ChosenBy::TaskSpec {
                task: task.label(),
                spec: s.written.clone(),
            },
        ),
        (None, Some(s)) => (arm_of(&s.source)?, ChosenBy::Spec(s.written.clone())),
        (None, None) => match &task.robot_type {
            Some(rt) => arm_of_backup_type(task, rt)?,
            None => (embedded_irb140()?, ChosenBy::Default),
        },
    };
    arm.chosen_by = chosen_by;
    Ok(arm)
}

/// The arm of the robot type a task's MOC.cfg names, and how it was
/// chosen; refused, with the catalogue arms nearest by reach and payload,
/// where the catalogue has no arm of that type.
fn arm_of_backup_type(task: &Task, rt: &str) -> Result<(TaskArm, ChosenBy)> {
    match arm_of_robot_type(rt) {
        Some((arm, variants)) if variants.is_empty() => Ok((arm, ChosenBy::RobotType(rt.into()))),
        Some((arm, variants)) => Ok((
            arm,
            ChosenBy::RobotTypeVariant {
                robot_type: rt.into(),
                variants,
            },
        )),
        None => {
            let e = Error::usage(format!(
                "task {}: the backup's SYSPAR/MOC.cfg says it moves a {rt}, which rapidtherm has no description of",
                task.label()
            ));
            let e = match nearest_to_type(rt) {
                Some(near) => e.with_note(format!(
                    "nearest in the catalogue by reach and payload: {}",
                    near.join(", ")
                )),
                None => e,
            };
            Err(e.with_remedy(Remedy::NameTheArm))
        }
    }
}

/// The embedded IRB 140, the arm the thermal defaults were measured on.
fn embedded_irb140() -> Result<TaskArm> {
    abb::find("irb140").map(catalogue_arm)
}

fn catalogue_arm(arm: &AbbArm) -> TaskArm {
    let is_irb140 = arm.is_embedded_irb140();
    TaskArm {
        robot: arm.robot(),
        label: if is_irb140 {
            "embedded IRB 140".to_string()
        } else {
            arm.name.clone()
        },
        is_irb140,
        urdf: None,
        chosen_by: ChosenBy::Default,
    }
}

/// The arm of a source: a catalogue arm, or a URDF file read.
pub fn arm_of(source: &ArmSource) -> Result<TaskArm> {
    match source {
        ArmSource::Catalogue(arm) => Ok(catalogue_arm(arm)),
        ArmSource::Urdf(path) => {
            // Read once: the same bytes are the arm and its fingerprint.
            let bytes = std::fs::read(path).map_err(|e| Error::io(path, &e))?;
            let name = path.display().to_string();
            let text = std::str::from_utf8(&bytes)
                .map_err(|_| Error::input(format!("{name}: a URDF file must be UTF-8")))?;
            urdf_arm(name, text)
        }
        ArmSource::UrdfText { name, text } => urdf_arm(name.clone(), text),
    }
}

/// The arm of a URDF's text, fingerprinted by its bytes.
fn urdf_arm(name: String, text: &str) -> Result<TaskArm> {
    let robot = Robot::from_urdf_str(&name, text)?;
    let is_irb140 = same_geometry_as_irb140(&robot);
    Ok(TaskArm {
        robot,
        label: fingerprint(text.as_bytes()),
        is_irb140,
        urdf: Some(name),
        chosen_by: ChosenBy::Default,
    })
}

/// Words of a robot type that name a version of an arm's build or
/// protection rather than its lengths: ABB's Type A/B/C, Clean Room,
/// Foundry Plus/Prime. rapidtherm has no source saying that each has its
/// base arm's geometry: a type with one of these words is taken as its
/// base arm, and the caller says so ([`ChosenBy::RobotTypeVariant`]).
/// Any other word (`LeanID`, `ID`, `T`) may be another geometry and must
/// be in the arm's name.
const BUILD_VARIANTS: &[&str] = &[
    "typea",
    "typeb",
    "typec",
    "cleanroom",
    "cr",
    "foundryplus",
    "foundryprime",
    "fp",
];

/// A robot type's parts: family (`1200`), reach (m), payload (kg), and its
/// words (`TypeB`), from MOC.cfg's `ROB1_1200_0.9_5_TypeB`: robot 1, an IRB
/// 1200 of 0.9 m reach and 5 kg, type B.
fn robot_type_parts(robot_type: &str) -> Option<(&str, f64, f64, Vec<&str>)> {
    let parts: Vec<&str> = robot_type.split('_').skip(1).collect();
    let family = *parts.first()?;
    let numbers: Vec<f64> = parts[1..].iter().filter_map(|p| p.parse().ok()).collect();
    let words: Vec<&str> = parts[1..]
        .iter()
        .filter(|p| p.parse::<f64>().is_err())
        .copied()
        .collect();
    let [reach, payload] = numbers[..] else {
        return None;
    };
    Some((family, reach, payload, words))
}

fn squash(s: &str) -> String {
    s.chars()
        .filter(char::is_ascii_alphanumeric)
        .flat_map(|c| c.to_lowercase())
        .collect()
}

/// The catalogue arm of a controller robot type, as MOC.cfg writes it:
/// `ROB1_140_0.81_6` is robot 1, an IRB 140 of 0.81 m reach and 6 kg;
/// `ROB1_6700_LeanID_2.65_220` has a variant word. `None` when no arm of
/// the catalogue has that family, payload and reach (within 0.05 m: types
/// write the reach to two decimals, designations to one or two). With the
/// arm, the build variants ([`BUILD_VARIANTS`]) it was taken without.
fn arm_of_robot_type(robot_type: &str) -> Option<(TaskArm, Vec<String>)> {
    let (family, reach, payload, words) = robot_type_parts(robot_type)?;
    let (build, words): (Vec<&str>, Vec<&str>) = words
        .into_iter()
        .partition(|w| BUILD_VARIANTS.contains(&squash(w).as_str()));
    let build: Vec<String> = build.into_iter().map(str::to_string).collect();
    let want_family = squash(&format!("irb{family}"));
    let fits: Vec<&AbbArm> = abb::catalogue()
        .iter()
        .filter(|a| squash(&a.family) == want_family)
        .filter(|a| (a.payload_kg - payload).abs() < 0.5 && (a.reach_m - reach).abs() < 0.05)
        .filter(|a| words.iter().all(|w| squash(&a.name).contains(&squash(w))))
        .collect();
    match fits.as_slice() {
        [one] => Some((catalogue_arm(one), build)),
        // Some designations name a payload class, not the rated payload
        // (the IRB 2400-10 carries 12 kg): try the designation itself.
        [] if words.is_empty() => [
            format!("irb{family}-{payload}/{reach}"),
            format!("irb{family}-{payload}"),
        ]
        .iter()
        .find_map(|name| abb::find(name).ok())
        .map(|arm| (catalogue_arm(arm), build)),
        _ => None,
    }
}

/// The three catalogue arms nearest a robot type by reach and payload
/// (each as a fraction of the type's), its own family first; `None` when
/// the type has no reach and payload to compare.
fn nearest_to_type(robot_type: &str) -> Option<Vec<&'static str>> {
    let (family, reach, payload, _) = robot_type_parts(robot_type)?;
    if !(reach > 0.0 && payload > 0.0) {
        return None;
    }
    let want_family = squash(&format!("irb{family}"));
    let mut by: Vec<(bool, f64, &'static str)> = abb::catalogue()
        .iter()
        .map(|a| {
            let d =
                ((a.reach_m - reach) / reach).abs() + ((a.payload_kg - payload) / payload).abs();
            (squash(&a.family) != want_family, d, a.name.as_str())
        })
        .collect();
    by.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    Some(by.iter().take(3).map(|(_, _, n)| *n).collect())
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

/// Whether two arms have the same chain (joint origins and axes within
/// 1e-6 mm and rad, the same tool0), whatever their names.
pub fn same_chain(a: &Robot, b: &Robot) -> bool {
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

/// Where a task's robot stands in the world, from the backup's MOC.cfg; a
/// robot whose base rides on another unit (a track) is refused: its base
/// is somewhere else at every target.
pub fn base_frame(task: &Task) -> Result<Option<nalgebra::Isometry3<f64>>> {
    if let Some(unit) = &task.base_moved_by {
        return Err(Error::new(
            ErrorKind::Unsupported,
            format!(
                "task {}: its robot's base frame moves with {unit} (SYSPAR/MOC.cfg, a track or a carrier): rapidtherm cannot place the arm for its targets",
                task.label()
            ),
        ));
    }
    task.base_frame
        .map(|(pos, rot)| crate::robot::frames::pose_from_rapid(pos, rot))
        .transpose()
        .map_err(|e| {
            Error::input(format!(
                "task {}: the base frame in SYSPAR/MOC.cfg: {}",
                task.label(),
                e.message
            ))
        })
}
