//! RAPID frames: from a robtarget (a TCP pose in a work object) to the
//! flange pose in the robot base frame, through `wobjdata` and `tooldata`,
//! and back (to write corrected targets in the program's own frames).
//!
//! The world frame is taken as the robot base frame (no base frame
//! calibration offset). Two set-ups exist in RAPID:
//!
//! * robot holds the tool (`tool.robhold = TRUE`, `wobj.robhold = FALSE`):
//!   TCP in base = uframe · oframe · target, flange = TCP · tframe⁻¹;
//! * stationary tool (`tool.robhold = FALSE`, `wobj.robhold = TRUE`):
//!   tframe is the stationary TCP in world, uframe is given in the flange
//!   (wrist) frame, the target is the TCP in the object frame:
//!   tframe = flange · uframe · oframe · target, so
//!   flange = tframe · (uframe · oframe · target)⁻¹.
//!
//! A user frame moved by a mechanical unit (`ufprog = FALSE`, coordinated
//! motion with `ufmec`) depends on that unit's position at run time and is
//! refused as unsupported rather than computed wrongly.

use crate::error::{Error, ErrorKind, Result};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

/// A pose from RAPID numbers: `trans` (mm) and quaternion `[q1, q2, q3,
/// q4]` = (w, x, y, z). The quaternion is normalised, as the controller
/// does; a zero or non-finite one is an input error.
pub fn pose_from_rapid(trans: [f64; 3], rot: [f64; 4]) -> Result<Isometry3<f64>> {
    if !trans.iter().chain(rot.iter()).all(|v| v.is_finite()) {
        return Err(Error::input("pose has a value that is not a finite number"));
    }
    let q = Quaternion::new(rot[0], rot[1], rot[2], rot[3]);
    if q.norm() < 1e-6 {
        return Err(Error::input(format!(
            "quaternion [{},{},{},{}] is zero and cannot be normalised",
            rot[0], rot[1], rot[2], rot[3]
        )));
    }
    Ok(Isometry3::from_parts(
        Translation3::new(trans[0], trans[1], trans[2]),
        UnitQuaternion::from_quaternion(q),
    ))
}

/// RAPID numbers of a pose: trans (mm) and quaternion (w, x, y, z), with
/// q1 ≥ 0 (q and −q are the same rotation; ABB prints q1 ≥ 0 mostly).
pub fn pose_to_rapid(pose: &Isometry3<f64>) -> ([f64; 3], [f64; 4]) {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    ([t.x, t.y, t.z], [s * q.w, s * q.i, s * q.j, s * q.k])
}

/// RAPID `tooldata` (the kinematic part; the load does not move the TCP
/// in this model).
#[derive(Debug, Clone, PartialEq)]
pub struct ToolFrame {
    /// TRUE: the robot holds the tool.
    pub robhold: bool,
    /// TCP in the flange frame (robot-held), or in world (stationary).
    pub tframe: Isometry3<f64>,
}

impl ToolFrame {
    /// `tool0`: the flange itself.
    pub fn tool0() -> ToolFrame {
        ToolFrame {
            robhold: true,
            tframe: Isometry3::identity(),
        }
    }

    pub fn new(robhold: bool, trans: [f64; 3], rot: [f64; 4]) -> Result<ToolFrame> {
        Ok(ToolFrame {
            robhold,
            tframe: pose_from_rapid(trans, rot)?,
        })
    }
}

impl Default for ToolFrame {
    fn default() -> Self {
        ToolFrame::tool0()
    }
}

/// RAPID `wobjdata`.
#[derive(Debug, Clone, PartialEq)]
pub struct WobjFrames {
    /// TRUE: the robot holds the work object (stationary tool).
    pub robhold: bool,
    /// TRUE: fixed user frame. FALSE: moved by a mechanical unit.
    pub ufprog: bool,
    /// The mechanical unit moving the user frame (with ufprog FALSE).
    pub ufmec: String,
    pub uframe: Isometry3<f64>,
    pub oframe: Isometry3<f64>,
}

impl WobjFrames {
    /// `wobj0`: the world (= base) frame.
    pub fn wobj0() -> WobjFrames {
        WobjFrames {
            robhold: false,
            ufprog: true,
            ufmec: String::new(),
            uframe: Isometry3::identity(),
            oframe: Isometry3::identity(),
        }
    }

    pub fn new(
        robhold: bool,
        ufprog: bool,
        ufmec: &str,
        uframe: ([f64; 3], [f64; 4]),
        oframe: ([f64; 3], [f64; 4]),
    ) -> Result<WobjFrames> {
        Ok(WobjFrames {
            robhold,
            ufprog,
            ufmec: ufmec.to_string(),
            uframe: pose_from_rapid(uframe.0, uframe.1)?,
            oframe: pose_from_rapid(oframe.0, oframe.1)?,
        })
    }

    /// The object frame: uframe · oframe.
    pub fn object_frame(&self) -> Isometry3<f64> {
        self.uframe * self.oframe
    }
}

impl Default for WobjFrames {
    fn default() -> Self {
        WobjFrames::wobj0()
    }
}

/// Which set-up a tool and work object describe.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Setup {
    RobotHeldTool,
    StationaryTool,
}

/// Whether `tool` and `wobj` make a set-up the frames can be solved in:
/// the error [`flange_of_target`] gives, without its pose.
pub fn check_setup(tool: &ToolFrame, wobj: &WobjFrames) -> Result<()> {
    setup(tool, wobj).map(|_| ())
}

fn setup(tool: &ToolFrame, wobj: &WobjFrames) -> Result<Setup> {
    if !wobj.ufprog {
        let unit = if wobj.ufmec.is_empty() {
            String::new()
        } else {
            format!(" by `{}`", wobj.ufmec)
        };
        return Err(Error::new(
            ErrorKind::Unsupported,
            format!("work object with a moving user frame (ufprog FALSE, moved{unit}): coordinated motion is not modelled"),
        ));
    }
    match (tool.robhold, wobj.robhold) {
        (true, false) => Ok(Setup::RobotHeldTool),
        (false, true) => Ok(Setup::StationaryTool),
        (true, true) => Err(Error::input(
            "the robot cannot hold both the tool and the work object (tooldata and wobjdata robhold are both TRUE)",
        )),
        (false, false) => Err(Error::input(
            "a stationary tool needs a work object held by the robot (tooldata and wobjdata robhold are both FALSE)",
        )),
    }
}

/// Flange (tool0) pose in the base frame that puts `tool` at `target` in
/// `wobj`.
pub fn flange_of_target(
    target: &Isometry3<f64>,
    tool: &ToolFrame,
    wobj: &WobjFrames,
) -> Result<Isometry3<f64>> {
    Ok(match setup(tool, wobj)? {
        Setup::RobotHeldTool => wobj.object_frame() * target * tool.tframe.inverse(),
        Setup::StationaryTool => tool.tframe * (wobj.object_frame() * target).inverse(),
    })
}

/// The target, in the program's own `tool` and `wobj`, that a flange pose
/// reaches (the inverse of [`flange_of_target`]).
pub fn target_of_flange(
    flange: &Isometry3<f64>,
    tool: &ToolFrame,
    wobj: &WobjFrames,
) -> Result<Isometry3<f64>> {
    Ok(match setup(tool, wobj)? {
        Setup::RobotHeldTool => wobj.object_frame().inverse() * flange * tool.tframe,
        Setup::StationaryTool => wobj.object_frame().inverse() * flange.inverse() * tool.tframe,
    })
}
