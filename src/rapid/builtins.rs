//! What RAPID itself defines, as opposed to what a program declares: the
//! functions that return a robtarget, the instructions that take no motion
//! time, the predefined speeddata, and the pose arithmetic of `Offs` and
//! `RelTool`. Poses are nalgebra isometries (translation in mm, rotation
//! as a unit quaternion); nothing here knows a robot.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::sync::OnceLock;

/// RAPID functions that return a robtarget (lower case).
pub const ROBTARGET_FUNCTIONS: [&str; 6] =
    ["offs", "reltool", "crobt", "calcrobt", "mirpos", "orobt"];

/// Whether `name` is a RAPID function returning a robtarget (any case).
pub fn returns_robtarget(name: &str) -> bool {
    ROBTARGET_FUNCTIONS
        .iter()
        .any(|f| f.eq_ignore_ascii_case(name))
}

/// Built-in instructions that take no time worth counting (I/O, messages,
/// settings, interrupts), lower case.
pub const INSTANT_INSTRUCTIONS: &[&str] = &[
    "tpwrite",
    "tperase",
    "tpshow",
    "errwrite",
    "setdo",
    "setao",
    "setgo",
    "set",
    "reset",
    "pulsedo",
    "invertdo",
    "incr",
    "decr",
    "add",
    "clear",
    "confl",
    "confj",
    "singarea",
    "accset",
    "pathacclim",
    "worldacclim",
    "gripload",
    "stopmove",
    "startmove",
    "startmoveretry",
    "stopmovereset",
    "clearpath",
    "isignaldi",
    "isignaldo",
    "isignalai",
    "isignalao",
    "isignalgi",
    "isignalgo",
    "itimer",
    "idelete",
    "isleep",
    "iwatch",
    "ienable",
    "idisable",
    "ierror",
    "ipers",
    "triggio",
    "triggequip",
    "triggint",
    "triggcheckio",
    "triggspeed",
    "movelsync",
    "tunereset",
    "pdispoff",
    "pdispon",
    "pdispset",
    "eoffsoff",
    "eoffson",
    "eoffsset",
    "cornerpathwarning",
    "skipwarn",
    "errlog",
    "raisetouser",
    "close",
    "open",
    "write",
    "writebin",
    "writestrbin",
    "rewind",
    "load",
    "unload",
    "startload",
    "waitload",
    "erase",
    "setsysdata",
    "tpreadfk",
    "tpreadnum",
    "stoptrigg",
    "resetretrycount",
    "bookerrno",
    "errraise",
    "velset",
    "softact",
    "softdeact",
    "activateunit",
    "deactunit",
    "mechunitload",
    "ccwtimeout",
    "setdataval",
    "getdataval",
    "stpathfollow",
    "arcrefresh",
];

/// Instructions that read robtargets or jointtargets without moving to
/// them: the tool and work object calibrations (their positions are
/// taught, not moved to by the program) and the joint world zones.
const READ_TARGETS_WITHOUT_MOVING: &[&str] = &[
    "wzhomejointdef",
    "wzlimjointdef",
    "stooltcpcalib",
    "stoolrotcalib",
    "mtooltcpcalib",
    "mtoolrotcalib",
];

/// Whether `name` is a built-in instruction that reads targets without
/// moving to them (any case).
pub fn reads_targets_without_moving(name: &str) -> bool {
    READ_TARGETS_WITHOUT_MOVING
        .iter()
        .any(|i| i.eq_ignore_ascii_case(name))
}

/// Whether `name` is a built-in instruction that takes no motion time
/// (any case).
pub fn is_instant_instruction(name: &str) -> bool {
    INSTANT_INSTRUCTIONS
        .iter()
        .any(|i| i.eq_ignore_ascii_case(name))
}

/// The four speeds of a `speeddata`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Speed {
    /// TCP speed, mm/s.
    pub v_tcp: f64,
    /// Reorientation speed, degrees/s.
    pub v_ori: f64,
    /// Linear external axes, mm/s.
    pub v_leax: f64,
    /// Rotating external axes, degrees/s.
    pub v_reax: f64,
}

/// The predefined speeddata table, from the reference manual's values
/// kept in `data/rapid/speeddata.toml`.
fn speed_table() -> &'static HashMap<String, [f64; 4]> {
    static TABLE: OnceLock<HashMap<String, [f64; 4]>> = OnceLock::new();
    TABLE.get_or_init(|| {
        #[derive(serde::Deserialize)]
        struct File {
            speeddata: HashMap<String, [f64; 4]>,
        }
        let text = include_str!("../../data/rapid/speeddata.toml");
        // The file is part of the build, checked by the tests below.
        toml::from_str::<File>(text)
            .map(|f| f.speeddata)
            .unwrap_or_default()
    })
}

/// A predefined speeddata by name (`v5` … `v7000`, `vmax`; any case).
/// `v0100` names `v100`, as the number is what is read.
pub fn predefined_speed(name: &str) -> Option<Speed> {
    let lower = name.to_ascii_lowercase();
    let key = if lower == "vmax" {
        lower
    } else {
        let n: u32 = lower.strip_prefix('v')?.parse().ok()?;
        format!("v{n}")
    };
    let [v_tcp, v_ori, v_leax, v_reax] = *speed_table().get(&key)?;
    Some(Speed {
        v_tcp,
        v_ori,
        v_leax,
        v_reax,
    })
}

/// `Offs(p, dx, dy, dz)`: `p` displaced by `d` (mm) along the axes of the
/// work object it is given in; its orientation unchanged.
pub fn offs(p: &Isometry3<f64>, d: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(p.translation.vector + Vector3::from(d)),
        p.rotation,
    )
}

/// `RelTool(p, dx, dy, dz \Rx \Ry \Rz)`: `p` displaced by `d` (mm) along
/// the tool's own axes and turned by `rot_deg` (degrees; 0 for an absent
/// argument) about them: first about x, then about the new y, then about
/// the new z.
pub fn reltool(p: &Isometry3<f64>, d: [f64; 3], rot_deg: [f64; 3]) -> Isometry3<f64> {
    let [rx, ry, rz] = rot_deg.map(f64::to_radians);
    let turn = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), rx)
        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), ry)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), rz);
    p * Isometry3::from_parts(Translation3::from(Vector3::from(d)), turn)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn pose(t: [f64; 3], axis_angle_deg: (Vector3<f64>, f64)) -> Isometry3<f64> {
        let (axis, deg) = axis_angle_deg;
        Isometry3::from_parts(
            Translation3::new(t[0], t[1], t[2]),
            UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), deg.to_radians()),
        )
    }

    #[test]
    fn speed_table_reads_every_predefined_speed() {
        assert_eq!(speed_table().len(), 26);
        let v100 = predefined_speed("v100").unwrap();
        assert_eq!(
            [v100.v_tcp, v100.v_ori, v100.v_leax, v100.v_reax],
            [100.0, 500.0, 5000.0, 1000.0]
        );
        assert_eq!(predefined_speed("V7000").unwrap().v_tcp, 7000.0);
        assert_eq!(predefined_speed("vMax").unwrap().v_tcp, 5000.0);
        assert_eq!(predefined_speed("v0050").unwrap().v_tcp, 50.0);
        assert!(predefined_speed("v123").is_none());
        assert!(predefined_speed("v").is_none());
        assert!(predefined_speed("z10").is_none());
    }

    #[test]
    fn offs_adds_in_the_work_object_whatever_the_orientation() {
        // Tool pointing down (180° about x): Offs still moves +z up.
        let p = pose([400.0, 0.0, 300.0], (Vector3::x(), 180.0));
        let q = offs(&p, [10.0, -20.0, 50.0]);
        assert_relative_eq!(q.translation.vector, Vector3::new(410.0, -20.0, 350.0));
        assert_eq!(q.rotation, p.rotation);
    }

    #[test]
    fn reltool_moves_along_the_tool_axes() {
        // Tool pointing down: its +z is the world's -z, its +y the
        // world's -y.
        let p = pose([400.0, 0.0, 300.0], (Vector3::x(), 180.0));
        let q = reltool(&p, [0.0, 10.0, 50.0], [0.0; 3]);
        assert_relative_eq!(
            q.translation.vector,
            Vector3::new(400.0, -10.0, 250.0),
            epsilon = 1e-9
        );
        assert_relative_eq!(q.rotation.angle_to(&p.rotation), 0.0, epsilon = 1e-12);
    }

    #[test]
    fn reltool_turns_x_then_y_then_z_about_the_moving_axes() {
        let p = Isometry3::identity();
        // Rx 90, then Ry 90 about the turned y: R = Rx(90) * Ry(90), so
        // R * x = Rx(90) * (0,0,-1) = (0,1,0).
        let q = reltool(&p, [0.0; 3], [90.0, 90.0, 0.0]);
        assert_relative_eq!(q.rotation * Vector3::x(), Vector3::y(), epsilon = 1e-12);
        // R * z = Rx(90) * (1,0,0) = (1,0,0).
        assert_relative_eq!(q.rotation * Vector3::z(), Vector3::x(), epsilon = 1e-12);
        // Rz alone, with a displacement: the displacement is in the tool
        // frame before the turn.
        let p = pose([100.0, 0.0, 0.0], (Vector3::z(), 90.0));
        let q = reltool(&p, [10.0, 0.0, 0.0], [0.0, 0.0, 45.0]);
        assert_relative_eq!(
            q.translation.vector,
            Vector3::new(100.0, 10.0, 0.0),
            epsilon = 1e-9
        );
        let half = std::f64::consts::FRAC_1_SQRT_2;
        assert_relative_eq!(
            q.rotation * Vector3::x(),
            Vector3::new(-half, half, 0.0),
            epsilon = 1e-12
        );
    }

    #[test]
    fn instant_instructions_and_robtarget_functions_ignore_case() {
        assert!(is_instant_instruction("TPWrite"));
        assert!(is_instant_instruction("setdo"));
        assert!(!is_instant_instruction("MoveL"));
        assert!(!is_instant_instruction("WaitTime"));
        assert!(returns_robtarget("CRobT"));
        assert!(!returns_robtarget("CJointT"));
    }
}
