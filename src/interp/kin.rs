//! The robot's side of the interpreter: RAPID's robot data as values and
//! back, and `CalcJointT`/`CalcRobT` on the project's own kinematics
//! (closed-form or numeric IK in the target's robconf, the tool and work
//! object frames as `correct` takes them).

use super::value::Value;
use crate::error::{Error, ErrorKind, Result};
use crate::rapid;
use crate::robot::frames::{flange_of_target, pose_from_rapid, pose_to_rapid, target_of_flange};
use crate::robot::{RobConf, Robot, ToolFrame, WobjFrames};
use nalgebra::Isometry3;

/// The arm `CalcJointT` and `CalcRobT` compute with, and where its base
/// frame stands in the world.
#[derive(Debug, Clone)]
pub struct Kinematics {
    pub robot: Robot,
    pub base: Isometry3<f64>,
    /// How far (rad) an axis may stand outside the quadrant a robtarget
    /// writes and still count as in it, for CalcJointT: the arithmetic's
    /// noise ([`QUADRANT_EDGE`]) as on the controller; the static path's
    /// half a degree (`ik_conf`) to run a module as it corrects.
    pub quadrant_edge: f64,
}

/// An axis on a quadrant's edge within the arithmetic's noise (rad; a
/// controller in single precision resolves no finer) is on either side:
/// a joint taught at exactly 0° is in cf 0 and cf -1 alike.
pub const QUADRANT_EDGE: f64 = 1e-6;

impl Kinematics {
    pub fn new(robot: Robot) -> Kinematics {
        Kinematics {
            robot,
            base: Isometry3::identity(),
            quadrant_edge: QUADRANT_EDGE,
        }
    }

    /// `CalcJointT`: the joints (degrees, with the target's external axes
    /// and `eoffs` added) that put `tool` at `target` in `wobj` (its
    /// object frame displaced already: [`Interp::displaced`]), in the
    /// target's configuration.
    ///
    /// As the RAPID reference (CalcJointT) says, the configuration written
    /// in the robtarget is the one used, whatever ConfL/ConfJ say: a
    /// solution with axes 1, 4 and 6 in the cf1, cf4, cf6 quadrants and
    /// the cfx case, exactly (the project's `ik_conf` takes a solution a
    /// half a degree outside a quadrant too, which the controller does
    /// not; an axis on a quadrant's edge, to the arithmetic's noise, counts
    /// for both quadrants); none
    /// there is ERR_ROBLIMIT, a pose out of reach ERR_OUTSIDE_REACH (the
    /// error's kind and words tell which: [`Interp::raise_from_robot`]).
    /// Stationary tools (tool robhold FALSE, wobj robhold TRUE) as the
    /// frames take them ([`flange_of_target`]).
    ///
    /// [`Interp::displaced`]: super::Interp
    /// [`Interp::raise_from_robot`]: super::Interp
    pub fn calc_joint_t_in(
        &self,
        target: &Value,
        tool: &ToolFrame,
        wobj: &WobjFrames,
        eoffs: &[f64; 6],
    ) -> Result<Value> {
        let (pose, conf, extax) = robtarget_parts(target)?;
        let flange = flange_of_target(&pose, tool, wobj)?;
        let q = self.robot.ik_conf(&(self.base.inverse() * flange), &conf)?;
        let got = self.robot.conf_of(&q);
        if !in_quadrants(&q, &got, &conf, self.quadrant_edge) {
            return Err(Error::new(
                ErrorKind::Unreachable,
                format!(
                    "no solution in the robtarget's configuration {conf} (the nearest has {got})"
                ),
            ));
        }
        let extax = std::array::from_fn(|i| offset(extax[i], eoffs[i]));
        Ok(jointtarget(q.map(f64::to_degrees), extax))
    }

    /// `CalcJointT` without a program displacement.
    pub fn calc_joint_t(&self, target: &Value, tool: &Value, wobj: &Value) -> Result<Value> {
        self.calc_joint_t_in(target, &tool_of(tool)?, &wobj_of(wobj)?, &[0.0; 6])
    }

    /// `CalcRobT`: the robtarget of `tool` in `wobj` (displaced already)
    /// at joints `j`, with the robconf of those joints and the external
    /// axes less `eoffs`.
    pub fn calc_rob_t_in(
        &self,
        j: &Value,
        tool: &ToolFrame,
        wobj: &WobjFrames,
        eoffs: &[f64; 6],
    ) -> Result<Value> {
        let n = j.numbers();
        if n.len() != 12 {
            return Err(Error::input("CalcRobT of a value that is no jointtarget"));
        }
        let q: [f64; 6] = std::array::from_fn(|i| n[i].to_radians());
        let flange = self.base * self.robot.fk(&q);
        let target = target_of_flange(&flange, tool, wobj)?;
        let c = self.robot.conf_of(&q);
        let conf = [c.cf1, c.cf4, c.cf6, c.cfx].map(f64::from);
        let (trans, rot) = pose_to_rapid(&target);
        Ok(robtarget(
            trans,
            rot,
            conf,
            std::array::from_fn(|i| offset(n[6 + i], -eoffs[i])),
        ))
    }

    /// `CalcRobT` without a program displacement.
    pub fn calc_rob_t(&self, j: &Value, tool: &Value, wobj: &Value) -> Result<Value> {
        self.calc_rob_t_in(j, &tool_of(tool)?, &wobj_of(wobj)?, &[0.0; 6])
    }
}

/// Whether joints `q` (robconf `got`) lie in the quadrants of `want`:
/// cfx the same, axes 1, 4 and 6 each in its cf's quadrant (to `edge`).
fn in_quadrants(q: &[f64; 6], got: &RobConf, want: &RobConf, edge: f64) -> bool {
    use crate::robot::conf::quadrant_distance;
    got == want
        || (got.cfx == want.cfx
            && quadrant_distance(q[0], want.cf1) <= edge
            && quadrant_distance(q[3], want.cf4) <= edge
            && quadrant_distance(q[5], want.cf6) <= edge)
}

/// An external axis offset by `by`; an axis not in use (9E9) stays so.
fn offset(axis: f64, by: f64) -> f64 {
    if axis.abs() >= 9e8 {
        axis
    } else {
        axis + by
    }
}

fn nums(v: impl IntoIterator<Item = f64>) -> Vec<Value> {
    v.into_iter().map(Value::Num).collect()
}

fn rec(ty: &str, items: Vec<Value>) -> Value {
    Value::Rec(ty.into(), items)
}

pub fn pos(p: [f64; 3]) -> Value {
    rec("pos", nums(p))
}

pub fn orient(q: [f64; 4]) -> Value {
    rec("orient", nums(q))
}

pub fn pose(trans: [f64; 3], rot: [f64; 4]) -> Value {
    rec("pose", vec![pos(trans), orient(rot)])
}

/// A robtarget from its numbers.
pub fn robtarget(trans: [f64; 3], rot: [f64; 4], conf: [f64; 4], extax: [f64; 6]) -> Value {
    rec(
        "robtarget",
        vec![
            pos(trans),
            orient(rot),
            rec("confdata", nums(conf)),
            rec("extjoint", nums(extax)),
        ],
    )
}

/// A jointtarget from its axes (degrees).
pub fn jointtarget(robax: [f64; 6], extax: [f64; 6]) -> Value {
    rec(
        "jointtarget",
        vec![rec("robjoint", nums(robax)), rec("extjoint", nums(extax))],
    )
}

pub(super) fn literal_robtarget(v: &rapid::RobTargetValue) -> Value {
    robtarget(
        v.trans_values(),
        v.rot_values(),
        v.robconf_values(),
        v.extax_values(),
    )
}

pub(super) fn literal_jointtarget(j: &rapid::JointTarget) -> Value {
    jointtarget(
        j.robax.each_ref().map(|n| n.value),
        j.extax.each_ref().map(|n| n.value),
    )
}

fn no_load() -> Value {
    rec(
        "loaddata",
        vec![
            Value::Num(0.0),
            pos([0.0; 3]),
            orient([1.0, 0.0, 0.0, 0.0]),
            Value::Num(0.0),
            Value::Num(0.0),
            Value::Num(0.0),
        ],
    )
}

/// A tooldata of the robot's frames (no load).
pub fn tool_value(t: &ToolFrame) -> Value {
    let (trans, rot) = pose_to_rapid(&t.tframe);
    rec(
        "tooldata",
        vec![Value::Bool(t.robhold), pose(trans, rot), no_load()],
    )
}

/// A wobjdata of the robot's frames.
pub fn wobj_value(w: &WobjFrames) -> Value {
    let (ut, ur) = pose_to_rapid(&w.uframe);
    let (ot, or) = pose_to_rapid(&w.oframe);
    rec(
        "wobjdata",
        vec![
            Value::Bool(w.robhold),
            Value::Bool(w.ufprog),
            Value::Str(w.ufmec.clone()),
            pose(ut, ur),
            pose(ot, or),
        ],
    )
}

/// A program's tooldata as written (its numbers, not normalised).
pub fn declared_tool(t: &rapid::ToolData) -> Value {
    let v = |n: &[rapid::Number]| n.iter().map(|x| x.value).collect::<Vec<_>>();
    let (tt, tr) = (v(&t.tframe_trans), v(&t.tframe_rot));
    rec(
        "tooldata",
        vec![
            Value::Bool(t.robhold.value),
            rec("pose", vec![rec("pos", nums(tt)), rec("orient", nums(tr))]),
            rec(
                "loaddata",
                vec![
                    Value::Num(t.mass.value),
                    rec("pos", nums(v(&t.cog))),
                    rec("orient", nums(v(&t.aom))),
                    Value::Num(t.inertia[0].value),
                    Value::Num(t.inertia[1].value),
                    Value::Num(t.inertia[2].value),
                ],
            ),
        ],
    )
}

/// A program's wobjdata as written.
pub fn declared_wobj(w: &rapid::WobjData) -> Value {
    let v = |n: &[rapid::Number]| nums(n.iter().map(|x| x.value));
    rec(
        "wobjdata",
        vec![
            Value::Bool(w.robhold.value),
            Value::Bool(w.ufprog.value),
            Value::Str(w.ufmec.clone()),
            rec(
                "pose",
                vec![
                    rec("pos", v(&w.uframe_trans)),
                    rec("orient", v(&w.uframe_rot)),
                ],
            ),
            rec(
                "pose",
                vec![
                    rec("pos", v(&w.oframe_trans)),
                    rec("orient", v(&w.oframe_rot)),
                ],
            ),
        ],
    )
}

fn field<'v>(v: &'v Value, ty: &str, i: usize) -> Result<&'v Value> {
    match v {
        Value::Rec(t, f) if &**t == ty => f
            .get(i)
            .ok_or_else(|| Error::input(format!("a {ty} without component {i}"))),
        _ => Err(Error::input(format!(
            "a {} where a {ty} is expected",
            v.kind()
        ))),
    }
}

fn array<const N: usize>(v: &Value) -> Result<[f64; N]> {
    let n = v.numbers();
    n.try_into().map_err(|_| {
        Error::input(format!(
            "a value of the wrong size where {N} numbers are expected"
        ))
    })
}

/// A pose record's isometry (its quaternion normalised, as the
/// controller does).
pub fn pose_of(v: &Value) -> Result<Isometry3<f64>> {
    pose_from_rapid(array(field(v, "pose", 0)?)?, array(field(v, "pose", 1)?)?)
}

/// A robtarget's pose, robconf and external axes.
pub fn robtarget_parts(v: &Value) -> Result<(Isometry3<f64>, RobConf, [f64; 6])> {
    let pose = pose_from_rapid(
        array(field(v, "robtarget", 0)?)?,
        array(field(v, "robtarget", 1)?)?,
    )?;
    let c: [f64; 4] = array(field(v, "robtarget", 2)?)?;
    let conf = RobConf::new(c[0] as i32, c[1] as i32, c[2] as i32, c[3] as i32);
    Ok((pose, conf, array(field(v, "robtarget", 3)?)?))
}

pub fn tool_of(v: &Value) -> Result<ToolFrame> {
    let robhold = field(v, "tooldata", 0)?
        .boolean()
        .ok_or_else(|| Error::input("tooldata robhold is no bool"))?;
    Ok(ToolFrame {
        robhold,
        tframe: pose_of(field(v, "tooldata", 1)?)?,
    })
}

pub fn wobj_of(v: &Value) -> Result<WobjFrames> {
    let flag = |i| {
        field(v, "wobjdata", i)?
            .boolean()
            .ok_or_else(|| Error::input("wobjdata robhold/ufprog is no bool"))
    };
    Ok(WobjFrames {
        robhold: flag(0)?,
        ufprog: flag(1)?,
        ufmec: field(v, "wobjdata", 2)?.string().unwrap_or("").to_string(),
        uframe: pose_of(field(v, "wobjdata", 3)?)?,
        oframe: pose_of(field(v, "wobjdata", 4)?)?,
    })
}
