//! Where a backup's robot stands and what it is, and every reason a
//! backup's configuration could not say it.
//!
//! A backup copied by hand or cut short still reads; but a run that
//! corrects its targets must not quietly put its robot at the world origin
//! as the default arm. Each thing missing is a [`Gap`] with the file and
//! line it concerns; the layer that picks arms refuses a task with gaps
//! unless the user accepts the default placement explicitly.

use crate::error::{Error, Location};
use std::fmt;
use std::path::PathBuf;

/// A backup's file that rapidtherm reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BackupPart {
    /// `BACKINFO/backinfo.txt`: task names and load order.
    BackInfo,
    /// `SYSPAR/SYS.cfg`: which tasks move which mechanical unit group.
    Sys,
    /// `SYSPAR/MOC.cfg`: the robot type and base frame of each robot.
    Moc,
}

impl BackupPart {
    /// Its path inside the backup.
    pub fn path(self) -> &'static str {
        match self {
            BackupPart::BackInfo => "BACKINFO/backinfo.txt",
            BackupPart::Sys => "SYSPAR/SYS.cfg",
            BackupPart::Moc => "SYSPAR/MOC.cfg",
        }
    }
}

/// Why a backup does not say where a task's robot is, or what it is.
#[derive(Debug, Clone, PartialEq)]
pub enum GapKind {
    /// The file is not in the backup.
    Missing(BackupPart),
    /// The file is there but is not a configuration file.
    Unreadable(BackupPart),
    /// backinfo.txt does not list the task's folder (its name and load
    /// order are then unknown).
    FolderNotListed { folder: String },
    /// SYS.cfg has no `CAB_TASKS` entry of this name.
    TaskNotInSys { task: String },
    /// SYS.cfg's motion task uses a group it does not define, or a group
    /// without a robot.
    GroupWithoutRobot { group: String },
    /// MOC.cfg has no `ROBOT` entry of this name (or, with no name, not
    /// exactly one).
    RobotNotInMoc { robot: Option<String> },
    /// MOC.cfg's robot entry names no `use_robot_type`.
    NoRobotType { robot: String },
    /// A base-frame value that is not a finite number.
    BadNumber { key: String, value: String },
    /// A base-frame orientation that is not a unit quaternion.
    BadOrientation { norm: f64 },
}

/// What a gap leaves unknown: the arm's type, where it stands, or both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unknown {
    /// Which arm it is (an arm named by the user makes up for it).
    Type,
    /// Where the arm stands in the world (nothing but the backup says).
    Place,
    /// Both.
    TypeAndPlace,
}

impl GapKind {
    /// What the gap leaves unknown.
    pub fn unknown(&self) -> Unknown {
        match self {
            GapKind::NoRobotType { .. } => Unknown::Type,
            GapKind::BadNumber { .. } | GapKind::BadOrientation { .. } => Unknown::Place,
            GapKind::Missing(_)
            | GapKind::Unreadable(_)
            | GapKind::FolderNotListed { .. }
            | GapKind::TaskNotInSys { .. }
            | GapKind::GroupWithoutRobot { .. }
            | GapKind::RobotNotInMoc { .. } => Unknown::TypeAndPlace,
        }
    }
}

/// One gap, with where it was found: the file, and the line and column
/// where the file has them.
#[derive(Debug, Clone, PartialEq)]
pub struct Gap {
    pub kind: GapKind,
    pub file: PathBuf,
    pub location: Option<Location>,
}

impl fmt::Display for GapKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GapKind::Missing(part) => write!(f, "the backup has no {}", part.path()),
            GapKind::Unreadable(part) => {
                write!(f, "{} is not a controller configuration file", part.path())
            }
            GapKind::FolderNotListed { folder } => {
                write!(f, "backinfo.txt does not list the task folder {folder}")
            }
            GapKind::TaskNotInSys { task } => {
                write!(f, "SYS.cfg has no CAB_TASKS entry for task {task}")
            }
            GapKind::GroupWithoutRobot { group } => write!(
                f,
                "SYS.cfg's mechanical unit group {group} is not defined or has no robot"
            ),
            GapKind::RobotNotInMoc { robot: Some(r) } => {
                write!(f, "MOC.cfg has no ROBOT entry named {r}")
            }
            GapKind::RobotNotInMoc { robot: None } => write!(
                f,
                "SYS.cfg names no robot for the task and MOC.cfg does not have exactly one"
            ),
            GapKind::NoRobotType { robot } => {
                write!(f, "MOC.cfg's robot {robot} has no use_robot_type")
            }
            GapKind::BadNumber { key, value } => {
                write!(
                    f,
                    "MOC.cfg's {key} is {}, not a number",
                    crate::error::quoted(value)
                )
            }
            GapKind::BadOrientation { norm } => write!(
                f,
                "MOC.cfg's base frame orientation is not a unit quaternion (norm {norm:.6})"
            ),
        }
    }
}

impl Gap {
    /// The gap as an input error of `task`, at its place.
    pub fn to_error(&self, task: &str) -> Error {
        let unknown = match self.kind.unknown() {
            Unknown::Type => "type is",
            Unknown::Place => "place in the world is",
            Unknown::TypeAndPlace => "type and place are",
        };
        let e = Error::input(format!(
            "task {task}: {} ({}), so its robot's {unknown} unknown",
            self.kind,
            self.file.display()
        ));
        match &self.location {
            Some(loc) => e.at(loc.clone()),
            None => e,
        }
    }
}

/// What a backup's configuration says of one task's robot.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Placement {
    /// Whether the task moves a robot (`None`: the backup does not say).
    pub motion: Option<bool>,
    /// The robot type, as MOC.cfg writes it (`ROB1_140_0.81_6`).
    pub robot_type: Option<String>,
    /// The base frame: mm, quaternion w x y z. `None`: the world origin.
    pub base_frame: Option<([f64; 3], [f64; 4])>,
    /// The mechanical unit the base moves with (a track).
    pub base_moved_by: Option<String>,
    /// Everything the backup should have said and did not.
    pub gaps: Vec<Gap>,
}
