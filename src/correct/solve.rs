//! The per-target solve: the flange pose a target means, the warm joints
//! that reach it, the nominal pose those joints are for the controller, and
//! the check that the controller picks the same joints back.

use super::edits::{quaternion_like, ORIENTATION_CHANGE_RAD};
use super::moments::{joint_moments_of, minute_of, moments_of, pick};
use super::outcome::{skip, Correction, Skipped};
use super::Options;
use crate::error::{Error, ErrorKind, Result};
use crate::model::{State, States, WarmRobot};
use crate::rapid::rewrite::{jointtarget_edits, robtarget_edits};
use crate::rapid::{JointTarget, Program, Target, TargetKind};
use crate::resolve::{frames_of, target_pose, usages, Frames, Usage};
use crate::robot::conf::{quadrant_distance, RobConf};
use crate::robot::frames::{flange_of_target, target_of_flange};
use crate::robot::Joints;
use nalgebra::{Isometry3, Vector3};
use std::cell::RefCell;
use std::collections::HashMap;

/// What became of one robtarget.
pub(super) enum Solved {
    Corrected(Box<Correction>),
    Skipped(Skipped),
    /// Nothing to write: the value is known only at run time.
    Nothing,
}

/// What every target of a run shares: the program's frames and usages, the
/// warm robot's states, the options.
pub(super) struct Run<'a> {
    pub program: &'a Program,
    pub warm: &'a WarmRobot,
    pub states: States<'a>,
    pub options: &'a Options,
    pub frames: Frames,
    pub uses: HashMap<usize, Vec<Usage>>,
    pub conf_off: bool,
    /// Choices made on the way that the user should know about.
    pub notes: RefCell<Vec<String>>,
}

impl<'a> Run<'a> {
    pub fn new(program: &'a Program, warm: &'a WarmRobot, options: &'a Options) -> Result<Run<'a>> {
        Ok(Run {
            program,
            warm,
            states: warm.states(),
            options,
            frames: Frames::of_program(program)?,
            uses: usages(program),
            conf_off: configuration_monitoring_off(program),
            notes: RefCell::new(Vec::new()),
        })
    }
}

/// Correct the robtarget `index` of the program: the warm joints that
/// reach the flange pose it means, written back as the nominal pose of
/// those joints in the target's own tool and work object.
pub(super) fn correct_robtarget(run: &Run, index: usize, target: &Target) -> Result<Solved> {
    let Run {
        program,
        warm,
        states,
        options,
        frames,
        uses,
        conf_off,
        ..
    } = run;
    let target_uses = uses.get(&index);
    if target.kind != TargetKind::Inline && target_uses.is_none() {
        return Ok(Solved::Skipped(skip(program, target, "no move instruction of the program reaches it, so its tool and work object are unknown")));
    }
    let (tool, wobj, _, _) = frames_of(program, frames, index, target_uses)?;
    let Some((pose, conf)) = target_pose(program, target)? else {
        return Ok(Solved::Nothing);
    };
    let flange = match flange_of_target(&pose, &tool, &wobj) {
        Ok(f) => f,
        Err(e) if e.kind == ErrorKind::Unsupported => {
            return Ok(Solved::Skipped(skip(program, target, &e.message)));
        }
        Err(e) => return Err(at_target(program, target, e)),
    };
    let moments = moments_of(&options.when, &target.id)
        .map_err(|e| e.at(program.location(&target.origin)))?;
    let moment = pick(&moments, options.visit);
    let (q_nominal, conf) = match warm.nominal.ik_conf(&flange, &conf) {
        Ok(q) => (q, conf),
        // With configuration monitoring off the controller takes the
        // solution nearest the robot's current one and ignores the
        // robconf; the nearest-quadrant solution stands for it, and a
        // correction of tenths of a millimetre keeps that branch.
        Err(e) if *conf_off && e.kind == ErrorKind::Unreachable => {
            match nearest_solution(warm, &flange, &conf) {
                Some(q) => {
                    let nearest = warm.nominal.conf_of(&q);
                    run.notes.borrow_mut().push(format!(
                        "target {} (line {}): robconf {conf} matches no solution; configuration monitoring is off (ConfL/ConfJ \\Off), so it is corrected on the nearest configuration {nearest}",
                        target.id, target.origin.pos.line
                    ));
                    (q, nearest)
                }
                None => return Err(at_target(program, target, prefix(e, "as written"))),
            }
        }
        Err(e) => return Err(at_target(program, target, prefix(e, "as written"))),
    };
    let state = states
        .at(moment)
        .map_err(|e| at_target(program, target, e))?;
    let q_warm = warm.joints_for(&flange, &conf, &state).map_err(|e| {
        at_target(
            program,
            target,
            prefix(e, &format!("on the warm robot at {moment}")),
        )
    })?;
    let corrected_flange = warm.nominal.fk(&q_warm);
    let exact = target_of_flange(&corrected_flange, &tool, &wobj)?;
    // The controller must pick back the warm joints from the corrected
    // target and the unchanged robconf.
    let picked = warm
        .nominal
        .ik_conf(&corrected_flange, &conf)
        .map_err(|e| at_target(program, target, prefix(e, "corrected")))?;
    if picked
        .iter()
        .zip(&q_warm)
        .any(|(a, b)| (a - b).abs() > 1e-6)
    {
        return Err(at_target(
            program,
            target,
            Error::new(
                ErrorKind::Unreachable,
                format!("the corrected target's robconf {conf} selects other joints than the warm robot needs (the target lies on a configuration boundary)"),
            ),
        ));
    }
    let drift_at = |state: &State| -> Result<Vector3<f64>> {
        let reached = target_of_flange(&warm.flange(&q_nominal, state), &tool, &wobj)?;
        Ok(reached.translation.vector - pose.translation.vector)
    };
    let drift = drift_at(&state)?;
    let mut range = (drift.norm(), drift.norm());
    if moments.len() > 1 {
        for m in &moments {
            let d = drift_at(&states.at(*m).map_err(|e| at_target(program, target, e))?)?.norm();
            range = (range.0.min(d), range.1.max(d));
        }
    }
    let Some(value) = &target.value else {
        return Ok(Solved::Nothing);
    };
    let src = program.source(target.origin.file);
    let new_trans = exact.translation.vector;
    let turn = pose.rotation.angle_to(&exact.rotation);
    // Orientation is rewritten only when it turns: a quaternion rewritten
    // for nothing would change bytes the correction does not mean.
    let turned = (turn > ORIENTATION_CHANGE_RAD)
        .then(|| quaternion_like(&exact.rotation, &value.rot_values()));
    let new_rot = turned.unwrap_or(value.rot_values());
    let edits = robtarget_edits(src, value, new_trans.into(), turned, None);
    let correction = new_trans - pose.translation.vector;
    let location = program.location(&target.origin);
    Ok(Solved::Corrected(Box::new(Correction {
        id: target.id.clone(),
        kind: target.kind.as_str().to_string(),
        file: location.file,
        line: target.origin.pos.line,
        col: target.origin.pos.col,
        time_min: minute_of(moment),
        temps_c: state.temps,
        drift_mm: drift.into(),
        drift_norm_mm: drift.norm(),
        drift_range_mm: range,
        correction_mm: correction.into(),
        correction_norm_mm: correction.norm(),
        dangle_deg: turn.to_degrees(),
        original: value
            .trans_values()
            .iter()
            .chain(&value.rot_values())
            .copied()
            .collect(),
        corrected: new_trans.iter().chain(&new_rot).copied().collect(),
        rewritten: !edits.is_empty(),
        exact: Some(exact),
        edits,
        file_index: target.origin.file,
    })))
}

/// Whether the program switches configuration monitoring off
/// (`ConfL \Off`, `ConfJ \Off`): then the controller does not hold targets
/// to their robconf.
fn configuration_monitoring_off(program: &Program) -> bool {
    let mut off = false;
    for module in &program.modules {
        for routine in &module.routines {
            crate::resolve::walk_calls(&routine.body, &mut |call, _| {
                let name = call.name.as_ref();
                if (name.eq_ignore_ascii_case("ConfL") || name.eq_ignore_ascii_case("ConfJ"))
                    && call.optional("Off").is_some()
                {
                    off = true;
                }
            });
        }
    }
    off
}

/// The solution of the nominal arm whose axes lie nearest the quadrants of
/// `conf` (same cfx preferred).
fn nearest_solution(warm: &WarmRobot, flange: &Isometry3<f64>, conf: &RobConf) -> Option<Joints> {
    let sols = warm.nominal.ik(flange).ok()?;
    let cost = |q: &Joints| {
        let c = warm.nominal.conf_of(q);
        let cfx = if c.cfx == conf.cfx { 0.0 } else { 10.0 };
        cfx + quadrant_distance(q[0], conf.cf1)
            + quadrant_distance(q[3], conf.cf4)
            + quadrant_distance(q[5], conf.cf6)
    };
    sols.iter()
        .map(|s| s.q)
        .min_by(|a, b| cost(a).total_cmp(&cost(b)))
}

/// A MoveAbsJ jointtarget: the same flange pose, reached by the warm arm.
pub(super) fn correct_jointtarget(run: &Run, jt: &JointTarget) -> Result<Correction> {
    let Run {
        program,
        warm,
        states,
        options,
        ..
    } = run;
    let located = |e: Error| {
        let msg = format!("jointtarget {}: {}", jt.id, e.message);
        Error { message: msg, ..e }.at(program.location(&jt.origin))
    };
    let degrees: [f64; 6] = jt.robax.each_ref().map(|n| n.value);
    let q: [f64; 6] = degrees.map(f64::to_radians);
    let flange = warm.nominal.fk(&q);
    let conf = warm.nominal.conf_of(&q);
    let moments = joint_moments_of(&options.when, &jt.id).map_err(located)?;
    let moment = pick(&moments, options.visit);
    let state = states.at(moment).map_err(located)?;
    let q_warm = warm.joints_for(&flange, &conf, &state).map_err(located)?;
    let new_deg = q_warm.map(f64::to_degrees);
    let drift = warm.flange(&q, &state).translation.vector - flange.translation.vector;
    let src = program.source(jt.origin.file);
    let edits = jointtarget_edits(src, jt, new_deg);
    let dangle = degrees
        .iter()
        .zip(&new_deg)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let location = program.location(&jt.origin);
    let corrected_flange = warm.nominal.fk(&q_warm);
    let correction = corrected_flange.translation.vector - flange.translation.vector;
    Ok(Correction {
        id: jt.id.clone(),
        kind: "jointtarget".to_string(),
        file: location.file,
        line: jt.origin.pos.line,
        col: jt.origin.pos.col,
        time_min: minute_of(moment),
        temps_c: state.temps,
        drift_mm: drift.into(),
        drift_norm_mm: drift.norm(),
        drift_range_mm: (drift.norm(), drift.norm()),
        correction_mm: correction.into(),
        correction_norm_mm: correction.norm(),
        dangle_deg: dangle,
        original: degrees.to_vec(),
        corrected: new_deg.to_vec(),
        rewritten: !edits.is_empty(),
        exact: Some(corrected_flange),
        edits,
        file_index: jt.origin.file,
    })
}

fn prefix(e: Error, context: &str) -> Error {
    Error {
        message: format!("{context}: {}", e.message),
        ..e
    }
}

fn at_target(program: &Program, target: &Target, e: Error) -> Error {
    let message = format!("target {}: {}", target.id, e.message);
    Error { message, ..e }.at(program.location(&target.origin))
}
