//! The module's table: for each target the program names directly, how
//! its correction grows with each link's growth, worked out here so that
//! the move's call on the controller is a lookup and four products (no
//! `CalcJointT`, no trigonometry inside the motion's look-ahead).
//!
//! The drift at fixed joints is linear in the four link growths (base,
//! lower arm, upper arm, wrist): `drift = Σ e_l · D_l(q)`. A robtarget's
//! row is its four `D_l` at its cold joints, in the world frame (the
//! module turns it into the target's frame at run time, where a work
//! object or a program displacement may have moved). A jointtarget's row
//! is the change of its joints per unit growth, `G_l = −J(q)⁻¹·[D_l; 0]`,
//! the first-order step of the static path's solve (the same pose on the
//! warm arm, joints nearest the written ones): at a wrist singularity
//! (axis 5 written 0), axis 4 is held and the other five are solved in
//! the least-squares sense, as the static path does. No configuration is
//! involved, so a warm solution across a quadrant boundary is no matter.

use super::mirror::drift_base;
use super::rewrite::Route;
use super::spec::RuntimeSpec;
use crate::model::warm::pose_error;
use crate::rapid::Program;
use crate::resolve::{frames_named_in, target_pose, Frames, Move, Through};
use crate::robot::frames::flange_of_target;
use crate::robot::{Joints, Robot};
use nalgebra::{Isometry3, Matrix6, Matrix6x5, UnitQuaternion, Vector3, Vector6};
use std::collections::HashMap;

/// The most rows of each kind the module carries: beyond them (a CAM
/// program's hundred thousand points) the moves take the slower path,
/// counted. 10,000 rows are about 1.5 MB of module text.
pub const MAX_ROWS: usize = 10_000;

/// Axis 5 closer to 0 than this (degrees): the wrist singularity, where
/// the static path holds axis 4 (correct/joints.rs).
const SINGULAR_DEG: f64 = 1e-3;

/// Orientation's weight in the singular solve (mm per radian), the static
/// path's.
const ORIENTATION_MM_PER_RAD: f64 = 1.0;

/// A robtarget's row: mm of drift per unit growth of each link, world
/// frame.
pub type DriftRow = [[f64; 3]; 4];

/// A jointtarget's row: degrees of change of each axis per unit growth of
/// each link.
pub type JointRow = [[f64; 6]; 4];

/// The module's rows: robtargets' and jointtargets', numbered from 1 in
/// the order the rewrite asked for them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TableRows {
    pub robtargets: Vec<DriftRow>,
    pub jointtargets: Vec<JointRow>,
}

/// The rows, built as the rewrite asks for them.
pub struct Table<'p> {
    program: &'p Program,
    robot: &'p Robot,
    spec: &'p RuntimeSpec,
    base: UnitQuaternion<f64>,
    frames: Option<Frames>,
    pub rows: TableRows,
    /// Row (from 1) of each (target, tool, work object) already asked.
    rob_rows: HashMap<(usize, String, String), Option<usize>>,
    joint_rows: HashMap<usize, Option<usize>>,
}

impl<'p> Table<'p> {
    /// An empty table for `program` on `robot` (its base frame turned by
    /// `base` in the world; `base_pose` places its frames).
    pub fn new(
        program: &'p Program,
        robot: &'p Robot,
        spec: &'p RuntimeSpec,
        base_pose: &Isometry3<f64>,
    ) -> Table<'p> {
        // Frames that cannot be read: every move takes the slower path,
        // where the controller reads them.
        let frames = Frames::of_program(program)
            .ok()
            .map(|f| f.placed(base_pose));
        Table {
            program,
            robot,
            spec,
            base: base_pose.rotation,
            frames,
            rows: TableRows::default(),
            rob_rows: HashMap::new(),
            joint_rows: HashMap::new(),
        }
    }

    /// How point `k` of move `m` is found in the table: its row (from 1),
    /// or an array's first row where the move indexes it at run time;
    /// `None` where the move's target is not one the program names
    /// directly with its frames (a run-time target, `Offs(...)`, a
    /// parameter) or the table is full.
    pub fn row(&mut self, m: &Move, k: usize) -> Option<Route> {
        let point = m.points.get(k)?;
        if m.joints {
            return match point.jointtargets[..] {
                [j] => self.jointtarget_row(j).map(Route::Table),
                [] => None,
                ref all => self
                    .consecutive(all.len(), &mut |t, n| t.jointtarget_row(all[n]))
                    .map(Route::TableArray),
            };
        }
        // The targets the argument names directly, in order: one, or an
        // array's elements one after another (indexed at run time).
        let mut targets = Vec::new();
        for (range, through) in &point.robtargets {
            if *through != Through::Direct {
                return None;
            }
            targets.extend(range.clone());
        }
        let (tool, wobj) = (m.tool.as_deref(), m.wobj.as_deref());
        match targets[..] {
            [] => None,
            [i] => self.robtarget_row(i, tool, wobj).map(Route::Table),
            _ if targets.windows(2).all(|w| w[1] == w[0] + 1) => self
                .consecutive(targets.len(), &mut |t, n| {
                    t.robtarget_row(targets[n], tool, wobj)
                })
                .map(Route::TableArray),
            _ => None,
        }
    }

    /// The first of `n` rows that `row` makes one after another (element
    /// by element); `None` where one cannot be made or they do not follow
    /// each other (an element asked before, alone).
    fn consecutive(
        &mut self,
        n: usize,
        row: &mut dyn FnMut(&mut Self, usize) -> Option<usize>,
    ) -> Option<usize> {
        let first = row(self, 0)?;
        for k in 1..n {
            if row(self, k)? != first + k {
                return None;
            }
        }
        Some(first)
    }

    /// The row of robtarget `i` of the program moved to in `tool` and
    /// `wobj` (`tool0`, `wobj0` where `None`), made at the first asking.
    pub fn robtarget_row(
        &mut self,
        i: usize,
        tool: Option<&str>,
        wobj: Option<&str>,
    ) -> Option<usize> {
        let key = (
            i,
            tool.unwrap_or("tool0").to_ascii_lowercase(),
            wobj.unwrap_or("wobj0").to_ascii_lowercase(),
        );
        if let Some(r) = self.rob_rows.get(&key) {
            return *r;
        }
        let r = self
            .drift_row(i, tool, wobj)
            .and_then(|row| push(&mut self.rows.robtargets, row));
        self.rob_rows.insert(key, r);
        r
    }

    /// The row of jointtarget `j` of the program, made at the first asking.
    pub fn jointtarget_row(&mut self, j: usize) -> Option<usize> {
        if let Some(r) = self.joint_rows.get(&j) {
            return *r;
        }
        let r = self
            .joint_row(j)
            .and_then(|row| push(&mut self.rows.jointtargets, row));
        self.joint_rows.insert(j, r);
        r
    }

    /// Target `i`'s row in `tool` and `wobj`: its cold joints as the
    /// controller solves them (its own robconf), and the drift per unit
    /// growth there.
    fn drift_row(&self, i: usize, tool: Option<&str>, wobj: Option<&str>) -> Option<DriftRow> {
        let frames = self.frames.as_ref()?;
        let target = self.program.targets().get(i)?;
        let (pose, conf) = target_pose(self.program, &target).ok()??;
        let (tool, wobj) = frames_named_in(self.program, frames, &target, tool, wobj).ok()?;
        let flange = flange_of_target(&pose, tool, wobj).ok()?;
        let q = self.robot.ik_conf(&flange, &conf).ok()?;
        let q_deg = q.map(f64::to_degrees);
        Some(std::array::from_fn(|l| {
            let d = self.base * drift_base(self.spec, &q_deg, &unit(l));
            [d.x, d.y, d.z]
        }))
    }

    /// Jointtarget `j`'s row: `G_l = −J⁻¹·[D_l; 0]` at its written joints.
    fn joint_row(&self, j: usize) -> Option<JointRow> {
        let jt = self.program.jointtargets().get(j)?;
        let degrees: [f64; 6] = jt.robax.each_ref().map(|n| n.value);
        // A positioner's jointtarget (9E+09) or no angle: nothing to move.
        if degrees.iter().any(|v| !v.is_finite() || v.abs() >= 1e6) {
            return None;
        }
        let q: Joints = degrees.map(f64::to_radians);
        let jac = jacobian(self.robot, &q);
        let singular = degrees[4].abs() < SINGULAR_DEG;
        let mut row = [[0.0; 6]; 4];
        for (l, out) in row.iter_mut().enumerate() {
            let d = drift_base(self.spec, &degrees, &unit(l));
            let r = Vector6::new(-d.x, -d.y, -d.z, 0.0, 0.0, 0.0);
            let dq: [f64; 6] = if singular {
                held_axis_4(&jac, &r)?
            } else {
                let v = jac.lu().solve(&r)?;
                std::array::from_fn(|a| v[a])
            };
            *out = std::array::from_fn(|a| dq[a].to_degrees());
        }
        Some(row)
    }
}

fn push<T>(rows: &mut Vec<T>, row: T) -> Option<usize> {
    if rows.len() >= MAX_ROWS {
        return None;
    }
    rows.push(row);
    Some(rows.len())
}

/// A unit growth of link `l` alone.
fn unit(l: usize) -> [f64; 4] {
    std::array::from_fn(|k| if k == l { 1.0 } else { 0.0 })
}

/// d(flange pose)/dq of the nominal arm, by central differences (as the
/// warm model's Newton takes it).
fn jacobian(robot: &Robot, q: &Joints) -> Matrix6<f64> {
    const H: f64 = 1e-6;
    let mut jac = Matrix6::zeros();
    for i in 0..6 {
        let (mut p, mut m) = (*q, *q);
        p[i] += H;
        m[i] -= H;
        let d = pose_error(&robot.fk(&p), &robot.fk(&m)) / (2.0 * H);
        jac.set_column(i, &d);
    }
    jac
}

/// The step of axes 1, 2, 3, 5 and 6 (axis 4 held) that best makes up
/// `r`, orientation weighted as the static path weighs it.
fn held_axis_4(jac: &Matrix6<f64>, r: &Vector6<f64>) -> Option<[f64; 6]> {
    const FREE: [usize; 5] = [0, 1, 2, 4, 5];
    let mut w = Matrix6x5::zeros();
    for (col, &axis) in FREE.iter().enumerate() {
        w.set_column(col, &jac.column(axis));
    }
    let mut rw = *r;
    for i in 3..6 {
        for c in 0..5 {
            w[(i, c)] *= ORIENTATION_MM_PER_RAD;
        }
        rw[i] *= ORIENTATION_MM_PER_RAD;
    }
    let step = w.svd(true, true).solve(&rw, 1e-12).ok()?;
    let mut dq = [0.0; 6];
    for (col, &axis) in FREE.iter().enumerate() {
        dq[axis] = step[col];
    }
    Some(dq)
}

/// The drift a row gives at growths `e` (mm, world frame): what the
/// module's lookup computes.
pub fn drift_of(row: &DriftRow, e: &[f64; 4]) -> Vector3<f64> {
    (0..4).fold(Vector3::zeros(), |acc, l| {
        acc + Vector3::from(row[l]) * e[l]
    })
}
