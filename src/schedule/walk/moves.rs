//! Motion instructions in the walk: speeds, tools and work objects of a
//! move, its goal on the nominal robot, and the time it takes.

use super::settled::{Found, Settled, SettledSlot};
use super::value::{Rob, Value};
use super::walker::{Arm, Frame, NamesAt, Walker};
use crate::error::{Error, ErrorKind, Result};
use crate::rapid::{Call, Expr, Motion, MotionKind, MoveBatch, Statement, StatementKind};
use crate::robot::frames::{flange_of_target, target_of_flange};
use crate::robot::{Joints, ToolFrame, WobjFrames};
use crate::schedule::bounds::FALLBACK_SPEED;
use crate::schedule::timing::*;
use nalgebra::{Isometry3, Vector3};
use std::rc::Rc;
use std::sync::Arc;

/// How a move goes: its kind, speed (`\V` and VelSet applied), `\T`,
/// `\Conc`, tool and work object, and the axes' top speeds (VelSet
/// applied).
#[derive(Clone, Copy)]
pub(super) struct Goal<'a> {
    pub(super) kind: MotionKind,
    pub(super) speed: MoveSpeed,
    pub(super) t_override: Option<f64>,
    pub(super) conc: bool,
    pub(super) frames: &'a Rc<(ToolFrame, WobjFrames)>,
    pub(super) max_speed: [f64; 6],
}

impl<'p> Walker<'p> {
    /// The speed `expr` names; `settled`: where the statement keeps it
    /// (see [`settled`]), taken from there where kept.
    pub(super) fn speed_of(
        &mut self,
        expr: Option<&Expr>,
        frame: &mut Frame<'p>,
        line: u32,
        settled: Option<&mut Option<MoveSpeed>>,
    ) -> Result<MoveSpeed> {
        if let Some(Some(speed)) = settled.as_deref() {
            return Ok(*speed);
        }
        let at = NamesAt::of(frame, [expr, None]).filter(|at| self.static_names(frame, at));
        if let Some((last, speed)) = &self.last_speed {
            if at.as_ref() == Some(last) {
                if let Some(slot) = settled {
                    *slot = Some(*speed);
                }
                return Ok(*speed);
            }
        }
        let v = match expr {
            Some(e) => self.eval(e, frame)?,
            None => Value::Unknown,
        };
        let found = match &v {
            Value::Ref(name) => self.named_speed(frame.module, name),
            Value::Agg(items) => {
                let n: Option<Vec<f64>> = items.iter().map(Value::num).collect();
                match n.as_deref() {
                    Some(&[v_tcp, v_ori, v_leax, v_reax]) => Some(MoveSpeed {
                        v_tcp,
                        v_ori,
                        v_leax,
                        v_reax,
                    }),
                    _ => None,
                }
            }
            _ => None,
        };
        match found {
            Some(s) => {
                // Found without a note: the next move naming it alike
                // finds the same.
                if let Some(at) = at {
                    self.last_speed = Some((at, s));
                    if let Some(slot) = settled {
                        *slot = Some(s);
                    }
                }
                Ok(s)
            }
            None => {
                let what = match &v {
                    Value::Ref(name) => format!("speeddata `{name}` is not in the program"),
                    _ => "speed known only at run time".to_string(),
                };
                self.note(frame, line, format!("{what}: taken as {FALLBACK_SPEED}"));
                Ok(predefined_speed(FALLBACK_SPEED).unwrap_or(MoveSpeed {
                    v_tcp: 1000.0,
                    v_ori: 500.0,
                    v_leax: 5000.0,
                    v_reax: 1000.0,
                }))
            }
        }
    }

    pub(super) fn named_speed(&self, module: usize, name: &str) -> Option<MoveSpeed> {
        let module_name = self.program.modules.get(module).map(|m| m.name.clone());
        let mut matching = self
            .program
            .speeds()
            .iter()
            .filter(|s| s.name.eq_ignore_ascii_case(name));
        let own = matching
            .clone()
            .find(|s| Some(&s.origin.module) == module_name.as_ref());
        own.or_else(|| matching.next())
            .map(|s| MoveSpeed {
                v_tcp: s.v_tcp.value,
                v_ori: s.v_ori.value,
                v_leax: s.v_leax.value,
                v_reax: s.v_reax.value,
            })
            .or_else(|| predefined_speed(name))
    }

    /// The tool and work object `tool` and `wobj` name; `settled`: where
    /// the statement keeps them (see [`settled`]), taken from there where
    /// kept.
    pub(super) fn frame_names(
        &mut self,
        tool: Option<&Expr>,
        wobj: Option<&Expr>,
        frame: &mut Frame<'p>,
        line: u32,
        settled: Option<&mut Option<Rc<(ToolFrame, WobjFrames)>>>,
    ) -> Result<Rc<(ToolFrame, WobjFrames)>> {
        if let Some(Some(frames)) = settled.as_deref() {
            return Ok(frames.clone());
        }
        let at = NamesAt::of(frame, [tool, wobj]).filter(|at| self.static_names(frame, at));
        if let Some((last, frames)) = &self.last_frames {
            if at.as_ref() == Some(last) {
                if let Some(slot) = settled {
                    *slot = Some(frames.clone());
                }
                return Ok(frames.clone());
            }
        }
        let name_of =
            |w: &mut Self, e: Option<&Expr>, frame: &mut Frame<'p>| -> Result<Option<String>> {
                Ok(match e {
                    None => None,
                    Some(e) => match w.eval(e, frame)? {
                        Value::Ref(n) => Some(n),
                        _ => Some(String::from("?")),
                    },
                })
            };
        let t = name_of(self, tool, frame)?;
        let o = name_of(self, wobj, frame)?;
        let mut noted = false;
        let tool = match self.frames.tool(t.as_deref()) {
            Some(t) => t.clone(),
            None => {
                noted = true;
                self.note(
                    frame,
                    line,
                    format!(
                        "tool {} unknown here, timed with tool0",
                        t.as_deref().unwrap_or("?")
                    ),
                );
                ToolFrame::tool0()
            }
        };
        let wobj = match self.frames.wobj(o.as_deref()) {
            Some(w) => w.clone(),
            None => {
                noted = true;
                self.note(
                    frame,
                    line,
                    format!(
                        "work object {} unknown here, timed with wobj0",
                        o.as_deref().unwrap_or("?")
                    ),
                );
                WobjFrames::wobj0()
            }
        };
        let frames = Rc::new((tool, wobj));
        // Found without a note: the next move naming them alike finds the
        // same.
        if let (Some(at), false) = (at, noted) {
            self.last_frames = Some((at, frames.clone()));
            if let Some(slot) = settled {
                *slot = Some(frames.clone());
            }
        }
        Ok(frames)
    }

    /// A move's speed from its speeddata, `\V` and `\T` as written,
    /// VelSet applied: the speed, and the time `\T` sets.
    pub(super) fn move_speed(
        &mut self,
        [speed_data, v, t]: [Option<&Expr>; 3],
        frame: &mut Frame<'p>,
        line: u32,
        settled: Option<&mut Option<MoveSpeed>>,
    ) -> Result<(MoveSpeed, Option<f64>)> {
        let mut speed = self.speed_of(speed_data, frame, line, settled)?;
        if let Some(v) = v {
            match self.eval(v, frame)?.num() {
                Some(v) if !(v.is_finite() && v > 0.0) => return Err(not_positive("\\V", v)),
                Some(v) => speed.v_tcp = v,
                None => self.note(frame, line, "\\V: value known only at run time, ignored"),
            }
        }
        let (ov, vmax) = self.velset;
        speed.v_tcp = (speed.v_tcp * ov).min(vmax);
        speed.v_ori *= ov;
        let t_override = match t {
            Some(t) => match self.eval(t, frame)?.num() {
                Some(t) if !(t.is_finite() && t > 0.0) => return Err(not_positive("\\T", t)),
                Some(t) => Some(t / ov),
                None => {
                    self.note(frame, line, "\\T: value known only at run time, ignored");
                    None
                }
            },
            None => None,
        };
        Ok((speed, t_override))
    }

    pub(super) fn exec_move<'c>(
        &mut self,
        call: &'c Call,
        m: &Motion<'c>,
        s: &Statement,
        frame: &mut Frame<'p>,
        mut settled: SettledSlot<'_, 'p>,
    ) -> Result<()> {
        if let Some(Expr::Index(b)) = m.to {
            // An element of a declared array, found by its declaration.
            let array = settled.as_deref_mut().map(|st| &mut st.array);
            if let Some(i) = self.element_of(b, frame, array)? {
                let to = self.target_value(i)?;
                return self.exec_move_to(call, m, s, frame, Some(to), settled);
            }
            if let Some((base, elements)) = self.unsettled_elements(m.to, b, frame)? {
                self.note(
                    frame,
                    s.pos.line,
                    format!(
                        "{}: the index into {base} is known only at run time: its {} elements are visited in order, each timed",
                        call.name,
                        elements.len()
                    ),
                );
                for v in elements {
                    self.exec_move_to(call, m, s, frame, Some(v), settled.as_deref_mut())?;
                }
                return Ok(());
            }
        }
        self.exec_move_to(call, m, s, frame, None, settled)
    }

    /// The elements of the target array a move indexes where the walk
    /// cannot settle the index (`pScan{i}` in a loop whose bounds come
    /// at run time), with the array's name: the move may go to any of
    /// them, and a raster program goes to all in turn, so each is visited
    /// (and timed) in order. `None` where the index is settled, the array
    /// is not one of targets, or it has more than one dimension.
    fn unsettled_elements(
        &mut self,
        whole: Option<&Expr>,
        (base, index): &(Expr, Vec<Expr>),
        frame: &mut Frame<'p>,
    ) -> Result<Option<(String, Vec<Value>)>> {
        if index.len() != 1 {
            return Ok(None);
        }
        if let Some(e) = whole {
            if self.path_of(e, frame)?.is_some() {
                return Ok(None);
            }
        }
        let Some(base) = self.path_of(base, frame)? else {
            return Ok(None);
        };
        let routine = frame.routine.map(|r| &*r.name);
        let mut elements = Vec::new();
        for k in 1.. {
            let v = self.path_value(&format!("{base}{{{k}}}"), (frame.module, routine))?;
            if matches!(v, Value::Unknown) {
                break;
            }
            elements.push(v);
        }
        Ok((!elements.is_empty()).then_some((base, elements)))
    }

    /// One move, to `to` where it is given (an element of an array the
    /// move indexes), else to the value of its target argument.
    fn exec_move_to<'c>(
        &mut self,
        call: &'c Call,
        m: &Motion<'c>,
        s: &Statement,
        frame: &mut Frame<'p>,
        to: Option<Value>,
        settled: SettledSlot<'_, 'p>,
    ) -> Result<()> {
        let line = s.pos.line;
        let kind = m.signature.kind;
        if kind == MotionKind::ExtJoint {
            self.note(
                frame,
                line,
                format!(
                    "{}: external axes are not modelled, taken as 0 s",
                    call.name
                ),
            );
            return Ok(());
        }
        let (speed_slot, frames_slot) = match settled {
            Some(st) => (Some(&mut st.speed), Some(&mut st.frames)),
            None => (None, None),
        };
        let (speed, t_override) = self
            .move_speed([m.speed, m.v, m.t], frame, line, speed_slot)
            .map_err(|e| match e.location {
                Some(_) => e,
                None => e.at(self.location(frame, s)),
            })?;
        let ov = self.velset.0;
        let frames = self.frame_names(m.tool, m.wobj, frame, line, frames_slot)?;
        let (tool, wobj) = (&frames.0, &frames.1);
        let to = match (to, m.to) {
            (Some(v), _) => v,
            (None, Some(e)) => self.eval(e, frame)?,
            (None, None) => Value::Unknown,
        };
        let max_speed = self.robot.max_speed_deg_s.map(|v| v * ov);
        match (kind, to) {
            (MotionKind::AbsJoint, Value::Joint(j)) => {
                let (q, id) = *j;
                // Robot axes all 9E+09: a positioner's jointtarget; the arm
                // stays where it is.
                if q.iter().all(|a| a.to_degrees().abs() >= 8.9e9) {
                    self.note(
                        frame,
                        line,
                        format!(
                            "{}: no robot axes (9E+09): the arm stays, external axes are not modelled, taken as 0 s",
                            call.name
                        ),
                    );
                    self.visit_joint(id, self.robot_free / 60.0);
                    return Ok(());
                }
                if !self.check_joints(&q, id, call, frame, s) {
                    return Ok(());
                }
                let q_from = self.current_joints();
                // Where the move starts, in its frames (a move to a
                // robtarget works it out itself).
                let from = target_of_flange(&self.arm.flange, tool, wobj);
                let flange = self.robot.fk(&q);
                let tcp = match (&from, target_of_flange(&flange, tool, wobj)) {
                    (Ok(a), Ok(b)) => (b.translation.vector - a.translation.vector).norm(),
                    _ => 0.0,
                };
                let secs = match q_from {
                    Some(qf) => joint_move_seconds(&qf, &q, &max_speed, tcp, &speed),
                    None => seconds_for(tcp, speed.v_tcp),
                };
                let secs = t_override.unwrap_or(secs);
                self.advance(secs, m.conc);
                self.arm = Arm {
                    flange,
                    joints: Some(q),
                    conf: self.robot.conf_of(&q),
                };
                self.visit_joint(id, self.robot_free / 60.0);
                return Ok(());
            }
            (MotionKind::AbsJoint, _) => {
                self.note(
                    frame,
                    line,
                    format!(
                        "{}: jointtarget known only at run time, taken as 0 s",
                        call.name
                    ),
                );
                return Ok(());
            }
            (_, Value::Rob(rob)) => {
                let goal = Goal {
                    kind,
                    speed,
                    t_override,
                    conc: m.conc,
                    frames: &frames,
                    max_speed,
                };
                return self.move_to_rob(&goal, *rob, m.via, call, frame, s);
            }
            _ => {}
        }
        self.note(
            frame,
            line,
            format!(
                "{}: target known only at run time, not scheduled, taken as 0 s",
                call.name
            ),
        );
        self.arm.joints = None;
        Ok(())
    }

    /// A move to a robtarget (`goal` says how), timed and its targets'
    /// visits recorded: the walk's own moves and cut ones alike.
    pub(super) fn move_to_rob(
        &mut self,
        goal: &Goal,
        rob: Rob,
        via: Option<&Expr>,
        call: &Call,
        frame: &mut Frame<'p>,
        s: &Statement,
    ) -> Result<()> {
        let line = s.pos.line;
        let Goal {
            kind,
            speed,
            t_override,
            conc,
            frames,
            max_speed,
        } = *goal;
        let (tool, wobj) = (&frames.0, &frames.1);
        let from = target_of_flange(&self.arm.flange, tool, wobj);
        let flange = match flange_of_target(&rob.pose, tool, wobj) {
            Ok(f) => f,
            Err(e) => {
                self.note(
                    frame,
                    line,
                    format!("{}: {}; taken as 0 s", call.name, e.message),
                );
                self.visit(&rob, self.robot_free);
                return Ok(());
            }
        };
        if !self.check_rob(&rob, (&flange, frames), call, frame, s) {
            return Ok(());
        }
        let from = from.unwrap_or(rob.pose);
        let mut via_info = None;
        let secs = match kind {
            MotionKind::Joint => {
                let q = match self.joint_goal(&flange, &rob, &max_speed, call, frame, s) {
                    Ok(q) => q,
                    Err(e) => {
                        self.fail_target(e);
                        return Ok(());
                    }
                };
                let tcp = (rob.pose.translation.vector - from.translation.vector).norm();
                let secs = match self.current_joints() {
                    Some(qf) => joint_move_seconds(&qf, &q, &max_speed, tcp, &speed),
                    None => seconds_for(tcp, speed.v_tcp),
                };
                self.arm.joints = Some(q);
                secs
            }
            MotionKind::Circular => {
                let cir = match via {
                    Some(e) => self.eval(e, frame)?,
                    None => Value::Unknown,
                };
                let angle = from.rotation.angle_to(&rob.pose.rotation).to_degrees();
                if let Value::Rob(c) = &cir {
                    let via = flange_of_target(&c.pose, tool, wobj);
                    if via.is_ok_and(|v| !self.check_rob(c, (&v, frames), call, frame, s)) {
                        return Ok(());
                    }
                }
                let (len, frac, cir) = match cir {
                    Value::Rob(c) => {
                        let (len, to_via) = arc_length(
                            &from.translation.vector,
                            &c.pose.translation.vector,
                            &rob.pose.translation.vector,
                        );
                        (len, if len > 0.0 { to_via / len } else { 0.5 }, Some(c))
                    }
                    _ => {
                        self.note(
                            frame,
                            line,
                            format!(
                                "{}: CirPoint known only at run time, timed along the chord",
                                call.name
                            ),
                        );
                        (
                            (rob.pose.translation.vector - from.translation.vector).norm(),
                            0.5,
                            None,
                        )
                    }
                };
                via_info = cir.map(|c| (frac, c));
                self.arm.joints = None;
                seconds_for(len, speed.v_tcp).max(seconds_for(angle, speed.v_ori))
            }
            _ => {
                self.arm.joints = None;
                linear_move_seconds(&from, &rob.pose, &speed)
            }
        };
        self.arm.flange = flange;
        self.arm.conf = rob.conf;
        let secs = t_override.unwrap_or(secs);
        let start = self.clock.max(self.robot_free);
        self.advance(secs, conc);
        if let Some((frac, c)) = via_info {
            self.visit(&c, start + secs * frac);
        }
        self.visit(&rob, self.robot_free);
        Ok(())
    }

    /// Joints for a MoveJ target: the solution with its robconf, else (a
    /// robconf the pose does not have: taught loosely) the quickest
    /// solution from where the robot is, noted. No solution at all is an
    /// error naming the target.
    pub(super) fn joint_goal(
        &mut self,
        flange: &Isometry3<f64>,
        rob: &Rob,
        max_speed: &[f64; 6],
        call: &Call,
        frame: &Frame,
        s: &Statement,
    ) -> Result<Joints> {
        let err = match self.robot.ik_conf(flange, &rob.conf) {
            Ok(q) => return Ok(q),
            Err(e) => e,
        };
        let sols = match self.robot.ik(flange) {
            Ok(sols) if !sols.is_empty() => sols,
            Ok(_) => return Err(self.unreachable(rob, call, frame, s, err)),
            Err(e) => return Err(self.unreachable(rob, call, frame, s, e)),
        };
        let from = self.current_joints().unwrap_or([0.0; 6]);
        let v = MoveSpeed {
            v_tcp: f64::INFINITY,
            v_ori: f64::INFINITY,
            v_leax: 0.0,
            v_reax: 0.0,
        };
        let best = sols
            .iter()
            .map(|sol| (joint_move_seconds(&from, &sol.q, max_speed, 0.0, &v), sol))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, sol)| *sol);
        let Some(best) = best else {
            return Err(self.unreachable(rob, call, frame, s, err));
        };
        let name = self.rob_name(rob);
        self.note(
            frame,
            s.pos.line,
            format!(
                "{} {name}: no solution with robconf {}; timed with the quickest reachable configuration {}",
                call.name, rob.conf, best.conf
            ),
        );
        Ok(best.q)
    }

    pub(super) fn rob_name(&self, rob: &Rob) -> String {
        rob.id
            .or(rob.derived)
            .and_then(|i| self.program.targets().get(i))
            .map_or_else(|| "(computed target)".to_string(), |t| t.id.clone())
    }

    /// The moves of a run the fast lane read, each as the grammar makes it.
    /// A move naming the speed, tool and work object the one before it
    /// named takes what that one found ([`settled`]): the run's names are
    /// kept once each, so the same name is the same pointer, and the run's
    /// moves are all of one routine, with no call between them to make a
    /// variable (the scope is checked all the same).
    ///
    /// The batch counts one step of its own before its moves', at its
    /// first move, as the walk counted the statement that held a run
    /// when runs were statements of the tree: the counts the walk's
    /// limits quote (`129 each`) are kept as they were written.
    pub(super) fn exec_moves(&mut self, batch: MoveBatch<'p>, frame: &mut Frame<'p>) -> Result<()> {
        let mut found = Found::default();
        let mut last: Option<(u64, [NameKey; 3])> = None;
        let mut first = true;
        for mv in batch.moves() {
            let Some(s) = mv.statement() else {
                continue;
            };
            if std::mem::take(&mut first) {
                self.count_step(frame, &s)?;
            }
            self.count_step(frame, &s)?;
            let StatementKind::Call(call) = &s.kind else {
                continue;
            };
            if let Some(m) = call.motion() {
                let keys = [name_key(m.speed), name_key(m.tool), name_key(m.wobj)];
                let was = last
                    .filter(|&(scope, _)| scope == self.scope)
                    .map(|(_, k)| k);
                if was.is_none_or(|k| k[0].is_none() || k[0] != keys[0]) {
                    found.speed = None;
                }
                if was.is_none_or(|k| k[1].is_none() || k[2].is_none() || k[1..] != keys[1..]) {
                    found.frames = None;
                }
                found.array = None;
                last = Some((self.scope, keys));
                self.exec_move(call, &m, &s, frame, Some(&mut found))?;
            }
        }
        Ok(())
    }

    pub(super) fn unreachable(
        &self,
        rob: &Rob,
        call: &Call,
        frame: &Frame,
        s: &Statement,
        e: Error,
    ) -> Error {
        let id = rob
            .id
            .or(rob.derived)
            .and_then(|i| self.program.targets().get(i));
        let name = id.as_ref().map_or("(computed)", |t| t.id.as_str());
        let mut err = Error::new(
            ErrorKind::Unreachable,
            format!(
                "target {name} ({} at line {}): {}",
                call.name, s.pos.line, e.message
            ),
        );
        err = match &id {
            Some(t) => err.at(self.program.location(&t.origin)),
            None => err.at(self.location(frame, s)),
        };
        for n in e.notes {
            err = err.with_note(n);
        }
        err
    }

    /// The robot's joints now, by IK of where it is if it came there on a
    /// linear path (one IK per joint move at most).
    pub(super) fn current_joints(&mut self) -> Option<Joints> {
        if self.arm.joints.is_none() {
            // A robconf the pose does not have (ConfL \Off, loosely taught
            // targets): a solution on the same side of axis 1, else any.
            self.arm.joints = self
                .robot
                .ik_conf(&self.arm.flange, &self.arm.conf)
                .ok()
                .or_else(|| {
                    let sols = self.robot.ik(&self.arm.flange).ok()?;
                    let cf1 = self.arm.conf.cf1;
                    sols.iter()
                        .find(|s| s.conf.cf1 == cf1)
                        .or_else(|| sols.iter().next())
                        .map(|s| s.q)
                });
        }
        self.arm.joints
    }

    /// A motion of `secs` seconds: it starts when the robot is free and the
    /// program has got there; with `\Conc` the program runs on at once.
    pub(super) fn advance(&mut self, secs: f64, conc: bool) {
        let start = self.clock.max(self.robot_free);
        // Absurd speeds (0, negative, overflowing arithmetic) add no time.
        let secs = if secs.is_finite() { secs.max(0.0) } else { 0.0 };
        self.robot_free = start + secs;
        self.clock = if conc { start } else { self.robot_free };
    }

    /// A visit of jointtarget number `id` (where the move names one) at
    /// `t_min`.
    fn visit_joint(&mut self, id: Option<usize>, t_min: f64) {
        let program = self.program;
        if let Some((i, jt)) = id.and_then(|i| Some((i, program.jointtargets().get(i)?))) {
            self.joint_schedule
                .visit_target(i, t_min, || Arc::from(jt.id.as_str()));
        }
    }

    pub(super) fn visit(&mut self, rob: &Rob, at_s: f64) {
        let t = at_s / 60.0;
        let n = self.program.targets().len();
        // By number: the identifiers are read after the walk
        // ([`Walker::finish`]), on every core.
        if let Some(i) = rob.id.filter(|&i| i < n) {
            self.schedule.visit_number(i, t);
        } else if let Some(i) = rob.derived.filter(|&i| i < n) {
            self.schedule.visit_number(i, t);
            for &b in &rob.bases {
                self.base_visits.push((b, t));
            }
        }
    }
}

/// Length of the circular arc from `a` through `b` to `c`, and of its part
/// from `a` to `b` (mm). Collinear points: the two straight segments.
fn arc_length(a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>) -> (f64, f64) {
    let u = b - a;
    let v = c - a;
    let w = u.cross(&v);
    let w2 = w.norm_squared();
    if w2 <= 1e-12 * u.norm_squared().max(1.0) * v.norm_squared().max(1.0) {
        let ab = u.norm();
        return (ab + (c - b).norm(), ab);
    }
    let centre = a + (v.cross(&w) * u.norm_squared() + w.cross(&u) * v.norm_squared()) / (2.0 * w2);
    let n = w / w2.sqrt();
    let ra = a - centre;
    let radius = ra.norm();
    // Angle from `a` to `x` counter-clockwise about the normal (a→b→c runs
    // counter-clockwise about u×v).
    let angle = |x: &Vector3<f64>| {
        let rx = x - centre;
        let t = n.dot(&ra.cross(&rx)).atan2(ra.dot(&rx));
        if t < 0.0 {
            t + std::f64::consts::TAU
        } else {
            t
        }
    };
    (radius * angle(c), radius * angle(b))
}

/// A move's `\V` (mm/s) or `\T` (s) that is not a positive number: the
/// controller stops on it, and a time estimate would divide by it.
fn not_positive(arg: &str, value: f64) -> Error {
    let what = if arg == "\\T" {
        "a move time"
    } else {
        "a speed"
    };
    Error::new(
        ErrorKind::Syntax,
        format!("{arg}:={value} is not {what} (it must be greater than 0)"),
    )
}

/// An argument of a move as a key of what it names: `Some(None)` absent,
/// `Some(Some(p))` a plain name (its text's address), `None` anything else
/// (never taken for another's).
type NameKey = Option<Option<*const u8>>;

fn name_key(e: Option<&Expr>) -> NameKey {
    match e {
        None => Some(None),
        Some(Expr::Name(n)) => Some(Some(n.as_ptr())),
        Some(_) => None,
    }
}

impl<'p> Walker<'p> {
    /// Some name may now stand for something else: what statements
    /// settled before is asked again.
    pub(super) fn rescope(&mut self) {
        self.scope += 1;
    }

    /// `call` run as a move with what it settled at its last turn in this
    /// scope; `false` where it is not a motion instruction.
    pub(super) fn exec_settled(
        &mut self,
        call: &'p Call,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<bool> {
        let key = std::ptr::from_ref(call);
        let scope = self.scope;
        // Boxed: taken out and put back at every move, moved as a pointer.
        let kept = match self.last_settled.take() {
            Some((k, st)) if k == key => Some(st),
            other => {
                if let Some((k, st)) = other {
                    self.settled.insert(k, st);
                }
                self.settled.remove(&key)
            }
        };
        let mut st = match kept {
            Some(st) if st.scope == scope => st,
            Some(mut st) => {
                st.scope = scope;
                st.found = Found::default();
                st
            }
            None => match call.motion() {
                Some(motion) => Box::new(Settled {
                    scope,
                    motion,
                    found: Found::default(),
                }),
                None => return Ok(false),
            },
        };
        let Settled { motion, found, .. } = &mut *st;
        self.exec_move(call, motion, s, frame, Some(found))?;
        // Settled in a scope that ended during the move (a FUNC called
        // from an argument) is never taken again: scopes only grow. A move
        // such a FUNC made left its own here: to the map with it.
        if let Some((k, inner)) = self.last_settled.take() {
            self.settled.insert(k, inner);
        }
        self.last_settled = Some((key, st));
        Ok(true)
    }
}
