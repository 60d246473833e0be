//! The robot's geometry: a six-axis serial arm (any URDF chain; closed-form
//! IK where it has an offset shoulder and a spherical wrist, the OPW form,
//! numeric IK elsewhere),
//! robconf, and the tool and work-object frames RAPID targets are written
//! in. A warm arm is the same arm with its segments scaled
//! ([`LinkScales`]); what scales them is the `model`'s business.
//!
//! Owns geometry only. May import the shared `error` and `csv_table`;
//! never `thermal`, `model` or anything above.
//!
//! Joint angles are radians inside the library, degrees in files and on the
//! command line; lengths are millimetres.
//!
//! - [`Robot`] (`arm`): the robot with its model; `Robot::irb140()`, `fk`,
//!   `ik`, `ik_conf`, `conf_of`. What later code calls.
//! - `urdf`: the embedded IRB 140 URDF (`data/irb140/irb140.urdf`) and the
//!   reader for other arms; [`irb140_opw`] is its nominal OPW geometry.
//! - `abb`: ABB's arms by name (`data/arms/*.toml`), `Robot::abb`.
//! - `chain`: forward kinematics of any serial chain, the chain of OPW
//!   lengths, OPW extraction.
//! - `ik`: the closed-form OPW solution, turns, limits, singularities.
//! - `ik_conf`: IK for one robconf, the requested branch computed directly
//!   (the enumeration of `ik` as its fallback and reference).
//! - `ik_chain`: numeric IK (and robconf) for the arms without the OPW
//!   form.
//! - `conf`: robconf (confdata) and the cfx table.
//! - `frames`: tooldata / wobjdata, robtarget ↔ flange.
//! - `euler`: a rotation as RobotStudio's Euler ZYX angles (RX, RY, RZ).
//! - `joints`: [`Joints`], the six angles; `opw`: [`Opw`], the lengths of
//!   the closed form, and [`LinkScales`], the scale of each segment.

pub mod abb;
pub mod arm;
pub mod chain;
pub mod conf;
pub mod euler;
pub mod frames;
pub mod ik;
mod ik_chain;
mod ik_conf;
mod joints;
mod lanes;
mod opw;
pub mod urdf;
pub mod urdf_scan;

pub use arm::{degrees_text, describe_violation, irb140_opw, Robot};
pub use conf::RobConf;
pub use frames::{ToolFrame, WobjFrames};
pub use ik::{DroppedBranch, Solution, Solutions, Violation};
pub use joints::Joints;
pub use opw::{LinkScales, Opw, OPW_OFFSET_Q3};
