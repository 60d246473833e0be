//! The robot's own position, as the interpreter knows it: the target the
//! last move instruction sent the robot to (with its tool, work object
//! and the displacement then active), read back by `CRobT` and `CJointT`;
//! and the robot's functions `CalcJointT` and `CalcRobT` with the active
//! program displacement.
//!
//! The interpreter moves no robot: a move is taken as done, the robot at
//! the (corrected) target it was given. A search instruction (SearchL,
//! SearchC, SearchJ) has no sensor here either: its found point is the
//! commanded end point (the robot reached it without the signal).

use super::commanded::Commanded;
use super::kin::{self, tool_of, wobj_of};
use super::state::Interp;
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::Call;
use nalgebra::Isometry3;

impl Interp {
    /// A move instruction `c` executed to `targets` (its robtargets, or
    /// jointtarget, evaluated): the robot's position remembered; a search's
    /// found point written.
    pub(super) fn command(&mut self, c: &Call, targets: &[Value]) -> Result<()> {
        let Some(motion) = c.motion() else {
            return Ok(());
        };
        let Some(target) = targets.last() else {
            return Ok(());
        };
        let tool = match motion.tool {
            Some(e) => self.eval(e)?,
            None => self.predefined_value("tool0")?,
        };
        let wobj = match motion.wobj {
            Some(e) if !self.absent_argument(e) => self.eval(e)?,
            _ => self.predefined_value("wobj0")?,
        };
        if c.name.to_ascii_lowercase().starts_with("search") {
            // The found point (SearchPoint, the second positional argument):
            // the commanded end point (no sensor).
            if let Some(found) = c.positional().nth(1) {
                let p = self.place_of(found)?;
                self.write(&p, target.clone())?;
            }
        }
        self.commanded = Some(Commanded {
            target: target.clone(),
            tool,
            wobj,
            pdisp: self.pdisp()?,
            eoffs: self.eoffs()?,
        });
        Ok(())
    }

    pub(super) fn predefined_value(&self, name: &str) -> Result<Value> {
        self.global(name)
            .cloned()
            .ok_or_else(|| Error::input(format!("`{name}` is not declared")))
    }

    fn commanded(&self, what: &str) -> Result<&Commanded> {
        self.commanded.as_ref().ok_or_else(|| {
            self.unsupported(format!(
                "{what} before a move: the interpreter knows the robot's position only from the moves it ran"
            ))
        })
    }

    /// The flange pose (world) where the last move sent the robot, and its
    /// joints where the move gave them.
    fn commanded_flange(&self) -> Result<(Isometry3<f64>, Option<Value>)> {
        let c = self.commanded("the robot's position")?;
        match &c.target {
            Value::Rec(t, _) if &**t == "jointtarget" => {
                let n = c.target.numbers();
                let q: [f64; 6] = std::array::from_fn(|i| n[i].to_radians());
                Ok((
                    self.kin.base * self.kin.robot.fk(&q),
                    Some(c.target.clone()),
                ))
            }
            _ => {
                let (pose, _, _) = kin::robtarget_parts(&c.target)?;
                let mut w = wobj_of(&c.wobj)?;
                w.oframe *= c.pdisp;
                let f = crate::robot::frames::flange_of_target(&pose, &tool_of(&c.tool)?, &w)?;
                Ok((f, None))
            }
        }
    }

    /// `CJointT()`: the joints the robot was sent to.
    pub(super) fn c_joint_t(&mut self) -> Result<Value> {
        let c = self.commanded("CJointT")?.clone();
        if let Value::Rec(t, _) = &c.target {
            if &**t == "jointtarget" {
                return Ok(c.target);
            }
        }
        let mut w = wobj_of(&c.wobj)?;
        w.oframe *= c.pdisp;
        self.kin
            .calc_joint_t_in(&c.target, &tool_of(&c.tool)?, &w, &c.eoffs)
            .map_err(|e| self.raise_from_robot(e))
    }

    /// `CRobT(\Tool \WObj)`: where the robot was sent, as the TCP of `tool`
    /// in `wobj` (the last move's where not given), in the frame of the
    /// displacement active now (the RAPID reference, CRobT: the position
    /// in the ProgDisp coordinate system).
    pub(super) fn c_rob_t(&mut self, tool: Option<Value>, wobj: Option<Value>) -> Result<Value> {
        let (flange, joints) = self.commanded_flange()?;
        let c = self.commanded("CRobT")?.clone();
        let tool = tool.unwrap_or(c.tool.clone());
        let wobj = wobj.unwrap_or(c.wobj.clone());
        let w = self.displaced(&wobj_of(&wobj)?)?;
        let target = crate::robot::frames::target_of_flange(&flange, &tool_of(&tool)?, &w)?;
        let (trans, rot) = crate::robot::frames::pose_to_rapid(&target);
        let (conf, extax) = match joints {
            Some(j) => {
                let n = j.numbers();
                let q: [f64; 6] = std::array::from_fn(|i| n[i].to_radians());
                let k = self.kin.robot.conf_of(&q);
                let conf = [k.cf1, k.cf4, k.cf6, k.cfx].map(f64::from);
                (conf, std::array::from_fn(|i| n[6 + i]))
            }
            None => {
                // A robtarget: the configuration it was sent in.
                let n = c.target.numbers();
                (
                    std::array::from_fn(|i| n[7 + i]),
                    std::array::from_fn(|i| n[11 + i]),
                )
            }
        };
        Ok(kin::robtarget(trans, rot, conf, extax))
    }

    /// `CalcJointT(p, tool \WObj)` and `CalcRobT(j, tool \WObj)` with the
    /// active displacement; their failures RAPID errors.
    pub(super) fn calc(
        &mut self,
        name: &str,
        arg: &Value,
        tool: &Value,
        wobj: &Value,
    ) -> Result<Value> {
        let w = self.displaced(&wobj_of(wobj)?)?;
        let tool = tool_of(tool)?;
        let eoffs = self.eoffs()?;
        let out = if name == "calcjointt" {
            self.kin.calc_joint_t_in(arg, &tool, &w, &eoffs)
        } else {
            self.kin.calc_rob_t_in(arg, &tool, &w, &eoffs)
        };
        out.map_err(|e| self.raise_from_robot(e))
    }
}
