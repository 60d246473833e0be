//! The per-target solve: the flange pose a target means, the warm joints
//! that reach it, the nominal pose those joints are for the controller, and
//! the check that the controller picks the same joints back.

use super::context::Run;
use super::edits::{quaternion_like, ORIENTATION_CHANGE_RAD};
use super::expressions::Evaluated;
use super::moments::minute_of;
use super::outcome::{Correction, Frame, Kind};
use crate::error::{Error, ErrorKind, Result, Subject};
use crate::model::{Moment, State, WarmRobot};
use crate::rapid::rewrite::{robtarget_edits, Edit};
use crate::rapid::{Program, Target, TargetKind};
use crate::resolve::monitoring::Monitor;
use crate::resolve::{frames_for, target_pose};
use crate::robot::conf::{quadrant_distance, RobConf};
use crate::robot::frames::{flange_of_target, target_of_flange, ToolFrame, WobjFrames};
use crate::robot::Joints;
use nalgebra::{Isometry3, Vector3};

/// The corrected pose of one meant TCP pose, and the joints involved.
pub(super) struct Solution {
    /// The corrected target: its nominal pose is where the warm robot
    /// must be sent.
    pub exact: Isometry3<f64>,
    /// The nominal joints of the pose as written (for the drift).
    pub q_nominal: Joints,
}

/// What the cold program means by a target, and when it is corrected
/// for: shared by the correction for its first tool and work object and
/// by what its other uses are checked (or split) against.
pub(super) struct Meant<'e> {
    pub pose: Isometry3<f64>,
    pub conf: RobConf,
    /// A literal written with expressions, valued (when the run may write
    /// numbers in its place).
    pub evaluated: Option<&'e Evaluated>,
    /// Every moment the target is reached, and the one picked.
    pub moments: super::moments::Moments,
    pub moment: Moment,
    pub state: State,
}

/// Whether a target's text changes, and the edits that change it where
/// the caller keeps them (a pass over a million targets keeps none).
pub(super) struct Rewrite {
    pub changed: bool,
    pub edits: Vec<Edit>,
}

impl Rewrite {
    /// The edits kept: the text changes where there is one.
    pub fn with(edits: Vec<Edit>) -> Rewrite {
        Rewrite {
            changed: !edits.is_empty(),
            edits,
        }
    }

    /// Only whether the text changes; the edits are written elsewhere.
    pub fn unkept(changed: bool) -> Rewrite {
        Rewrite {
            changed,
            edits: Vec::new(),
        }
    }
}

/// What is already known of a target's solve before it is made: its
/// exact nominal pose (a base placed by its derived uses), and the cold
/// joints of its meant pose in its frames (found by the walk that timed
/// the run).
pub(super) struct Known {
    pub exact: Option<Isometry3<f64>>,
    pub cold: Option<Joints>,
}

/// The robconf a pose is solved in, and its cold joints in it where
/// already found.
pub(super) struct InConf<'c> {
    pub conf: &'c RobConf,
    pub cold: Option<Joints>,
}

/// The correction of a target for one tool and work object (`names`, as
/// the report gives them): the solve, or `exact` where it is already
/// known (a base placed by its derived uses), the drift over the target's
/// moments, and the edits writing the new numbers over the literal.
pub(super) fn corrected(
    run: &Run,
    target: &Target,
    meant: &Meant,
    frames: (&ToolFrame, &WobjFrames),
    names: [&str; 2],
    exact: Option<Isometry3<f64>>,
) -> Result<Correction> {
    let known = Known { exact, cold: None };
    let numbers = corrected_numbers(run, target, meant, frames, known)?;
    let src = run.program.source(target.origin.file);
    let edits = edits_of(src, target, meant, &numbers);
    Ok(row(
        run,
        target,
        meant,
        frames,
        names,
        &numbers,
        Rewrite::with(edits),
    ))
}

/// The edits writing a target's corrected numbers over its literal (in
/// `src`), each formatted like the number it replaces.
pub(super) fn edits_of(src: &[u8], target: &Target, meant: &Meant, n: &Numbers) -> Vec<Edit> {
    let new_trans = n.exact.translation.vector;
    match (&target.value, meant.evaluated) {
        (Some(value), _) => robtarget_edits(src, value, new_trans.into(), n.turned, None),
        (None, Some(e)) => e.edits(src, new_trans.into(), n.turned),
        (None, None) => Vec::new(),
    }
}

/// A target's report row from its numbers: `rewritten` whether its text
/// changed, with the edits that change it where the caller keeps them.
pub(super) fn row(
    run: &Run,
    target: &Target,
    meant: &Meant,
    (tool, wobj): (&ToolFrame, &WobjFrames),
    [tool_name, wobj_name]: [&str; 2],
    numbers: &Numbers,
    Rewrite {
        changed: rewritten,
        edits,
    }: Rewrite,
) -> Correction {
    let Numbers {
        exact,
        drift,
        range,
        turn,
        new_rot,
        ..
    } = *numbers;
    let Meant {
        pose,
        evaluated,
        moment,
        state,
        ..
    } = meant;
    let new_trans = exact.translation.vector;
    let original: Vec<f64> = match (&target.value, evaluated) {
        (Some(value), _) => value
            .trans_values()
            .iter()
            .chain(&value.rot_values())
            .copied()
            .collect(),
        (None, Some(e)) => e.trans.iter().chain(&e.rot).copied().collect(),
        (None, None) => Vec::new(),
    };
    let correction = new_trans - pose.translation.vector;
    let location = run.program.location(&target.origin);
    Correction {
        id: target.id.clone(),
        kind: Kind::of(target),
        file: location.file,
        line: target.origin.pos.line,
        col: target.origin.pos.col,
        time_min: minute_of(*moment),
        temps_c: state.temps,
        tool: Some(tool_name.to_string()),
        wobj: Some(wobj_name.to_string()),
        frame: Frame::WobjObject,
        drift_mm: drift.into(),
        drift_norm_mm: drift.norm(),
        drift_range_mm: range,
        correction_mm: correction.into(),
        correction_norm_mm: correction.norm(),
        dangle_deg: turn.to_degrees(),
        original,
        corrected: new_trans.iter().chain(&new_rot).copied().collect(),
        rewritten,
        exact: Some(exact),
        world_mm: in_world(run, pose, tool, wobj),
        order: (target.origin.file, target.origin.pos.offset),
        edits,
        file_index: target.origin.file,
    }
}

/// The numbers of one target's correction, without its report row or
/// its edits: what a run of a million targets keeps of each.
#[derive(Clone, Copy)]
pub(super) struct Numbers {
    /// The corrected target.
    pub exact: Isometry3<f64>,
    /// Where the uncorrected target puts the warm robot, less where it is
    /// meant (mm), at the moment corrected for; its norm's range over
    /// the target's moments.
    pub drift: Vector3<f64>,
    pub range: (f64, f64),
    /// How far the orientation turns (rad); the quaternion to write over
    /// the literal's where it turns, and the one the target then has.
    pub turn: f64,
    pub turned: Option<[f64; 4]>,
    pub new_rot: [f64; 4],
}

/// The solve of a target, or `exact` where it is already known,
/// the drift over the target's moments, and what is to be written over
/// the literal (the position of `exact`, and `turned`). `cold`: the cold
/// joints of the meant pose in these frames, where already found.
pub(super) fn corrected_numbers(
    run: &Run,
    target: &Target,
    meant: &Meant,
    (tool, wobj): (&ToolFrame, &WobjFrames),
    Known { exact, cold }: Known,
) -> Result<Numbers> {
    let Run {
        program,
        warm,
        states,
        ..
    } = run;
    let Meant {
        pose,
        conf,
        evaluated,
        moments,
        moment,
        state,
    } = meant;
    let solution = solve(
        run,
        target,
        pose,
        InConf { conf, cold },
        (tool, wobj),
        state,
        *moment,
    )?;
    let exact = exact.unwrap_or(solution.exact);
    let q_nominal = solution.q_nominal;
    let drift_at = |state: &State| -> Result<Vector3<f64>> {
        let reached = target_of_flange(&warm.flange(&q_nominal, state), tool, wobj)?;
        Ok(reached.translation.vector - pose.translation.vector)
    };
    let drift = drift_at(state)?;
    let mut range = (drift.norm(), drift.norm());
    if moments.len() > 1 {
        for m in moments {
            let d = drift_at(&states.at(*m).map_err(|e| at_target(program, target, e))?)?.norm();
            range = (range.0.min(d), range.1.max(d));
        }
    }
    let turn = pose.rotation.angle_to(&exact.rotation);
    let written_rot = match (&target.value, evaluated) {
        (Some(v), _) => v.rot_values(),
        (None, Some(e)) => e.rot,
        (None, None) => [1.0, 0.0, 0.0, 0.0],
    };
    // Orientation is rewritten only when it turns: a quaternion rewritten
    // for nothing would change bytes the correction does not mean.
    let turned =
        (turn > ORIENTATION_CHANGE_RAD).then(|| quaternion_like(&exact.rotation, &written_rot));
    let new_rot = turned.unwrap_or(written_rot);
    Ok(Numbers {
        exact,
        drift,
        range,
        turn,
        turned,
        new_rot,
    })
}

/// Where a target pose in `tool` and `wobj` puts the robot in the world
/// frame: the TCP of a robot-held tool, the flange with a stationary tool
/// (its TCP stands still; the flange is what moves over the cell).
fn in_world(
    run: &Run,
    pose: &Isometry3<f64>,
    tool: &ToolFrame,
    wobj: &WobjFrames,
) -> Option<[f64; 3]> {
    let flange = flange_of_target(pose, tool, wobj).ok()?;
    let in_base = if tool.robhold {
        flange * tool.tframe
    } else {
        flange
    };
    let world = run
        .options
        .base_frame
        .map_or(in_base, |base| base * in_base);
    Some(world.translation.vector.into())
}

/// Where a target left alone puts the robot in the world frame by its
/// written numbers and the tool and work object of its first move; `None`
/// where they do not say (no move names its work object, no numbers, a
/// work object a mechanical unit moves).
pub(super) fn written_in_world(run: &Run, index: usize, target: &Target) -> Option<[f64; 3]> {
    let first = run.set.uses.first(index);
    if first.is_none() && target.kind != TargetKind::Inline {
        return None;
    }
    let (pose, _) = match &target.value {
        Some(_) => target_pose(run.program, target).ok()??,
        None => run
            .set
            .expressions
            .evaluate(&run.set.constants, target)?
            .pose_conf()
            .ok()?,
    };
    let first = first.map(|f| (f.tool(), f.wobj()));
    let (tool, wobj, _, _) = frames_for(run.program, &run.set.frames, target, first).ok()?;
    in_world(run, &pose, &tool, &wobj)
}

/// The corrected target for one meant pose (TCP `pose` in its work object,
/// robconf `conf`) at one thermal state. `cold`: the pose's cold joints
/// with `conf`, where already found (by the walk that timed the run, as
/// [`crate::robot::Robot::ik_conf`] finds them).
pub(super) fn solve(
    run: &Run,
    target: &Target,
    pose: &Isometry3<f64>,
    InConf { conf, cold }: InConf,
    (tool, wobj): (&ToolFrame, &WobjFrames),
    state: &State,
    moment: Moment,
) -> Result<Solution> {
    let Run { program, warm, .. } = run;
    let held = run
        .set
        .unmonitored
        .get(&(target.origin.file, target.origin.pos.offset))
        .copied();
    let conf_off = held == Some(Monitor::Off);
    // Where the walk cannot tell, the refusal says that it took
    // monitoring as on.
    // A target out of reach that carries external axis positions: the
    // arm may ride a track the files read do not place.
    // Read only where a refusal says it.
    let track = || {
        target.value.as_ref().and_then(|v| {
            let names = ["eax_a", "eax_b", "eax_c", "eax_d", "eax_e", "eax_f"];
            let set: Vec<String> = (v.extax_values().iter().zip(names))
                .filter(|(x, _)| x.abs() > 1e-9 && x.abs() < 8.9e9)
                .map(|(x, n)| format!("{n} = {x}"))
                .collect();
            (!set.is_empty()).then(|| set.join(", "))
        })
    };
    let prefix = |e: Error, context: &str| {
        let e = prefix(e, context);
        let e = match (e.kind == ErrorKind::Unreachable).then(track).flatten() {
            Some(axes) => e.with_note(format!(
                "the target carries external axis positions ({axes}): if the arm rides a track or stands on a moving base, read the task from its backup (its MOC.cfg places the base)"
            )),
            None => e,
        };
        if held == Some(Monitor::Unsettled) {
            e.with_note("configuration monitoring at its move cannot be settled (ConfL/ConfJ \\Off is in effect on some paths to it only): taken as on, so its robconf is held")
        } else {
            e
        }
    };
    let flange = match flange_of_target(pose, tool, wobj) {
        Ok(f) => f,
        Err(e) => return Err(at_target(program, target, e)),
    };
    // Found already, they are what the solve would find: checked so in
    // every test run.
    debug_assert!(
        cold.is_none_or(|q| warm.nominal.ik_conf(&flange, conf).ok() == Some(q)),
        "cold joints given are not the IK's"
    );
    let cold = match cold {
        Some(q) => Ok(q),
        None => warm.nominal.ik_conf(&flange, conf),
    };
    let (q_nominal, conf) = match cold {
        Ok(q) => (q, *conf),
        // With configuration monitoring off the controller takes the
        // solution nearest the robot's current one and ignores the
        // robconf; the nearest-quadrant solution stands for it, and a
        // correction of tenths of a millimetre keeps that branch.
        Err(e) if conf_off && e.kind == ErrorKind::Unreachable => {
            match nearest_solution(warm, &flange, conf) {
                Some(q) => {
                    let nearest = warm.nominal.conf_of(&q);
                    let note = format!(
                        "target {} (line {}): robconf {conf} matches no solution; configuration monitoring is off at every move to it (ConfL/ConfJ \\Off), so it is corrected on the nearest configuration {nearest}",
                        target.id, target.origin.pos.line
                    );
                    run.note((target.origin.file, target.origin.pos.offset), note);
                    (q, nearest)
                }
                None => return Err(at_target(program, target, prefix(e, "as written"))),
            }
        }
        Err(e) => return Err(at_target(program, target, prefix(e, "as written"))),
    };
    let q_warm = match warm.joints_for(&flange, &conf, state) {
        Ok(q) => q,
        // With configuration monitoring off the controller ignores the
        // robconf and takes the solution nearest the joints it is at: the
        // warm solution nearest the cold one stands for it, where the
        // cold one lies so near a boundary that the warm arm crosses it.
        Err(e) if conf_off => match nearest_within_limits(warm, &flange, &q_nominal, state) {
            Some(q) => {
                let note = format!(
                    "target {} (line {}): the warm arm leaves its cold configuration {conf} at {moment}; configuration monitoring is off at every move to it (ConfL/ConfJ \\Off), so it is corrected on the warm solution nearest its cold joints ({})",
                    target.id,
                    target.origin.pos.line,
                    warm.nominal.conf_of(&q)
                );
                run.note((target.origin.file, target.origin.pos.offset), note);
                q
            }
            None => {
                return Err(at_target(
                    program,
                    target,
                    prefix(
                        beyond_warm_limit(warm, &flange, &q_nominal, state).unwrap_or(e),
                        &format!("on the warm robot at {moment}"),
                    ),
                ))
            }
        },
        Err(e) => {
            return Err(at_target(
                program,
                target,
                prefix(e, &format!("on the warm robot at {moment}")),
            ))
        }
    };
    let corrected_flange = warm.nominal.fk(&q_warm);
    let exact = target_of_flange(&corrected_flange, tool, wobj)?;
    // The controller must pick back the warm joints from the corrected
    // target and the unchanged robconf: certain without solving away from
    // every boundary (a third of the solving of a million targets), else
    // solved.
    // With monitoring off the robconf picks nothing back: the nearest
    // solution is taken, which the warm joints are.
    if conf_off || warm.nominal.picks_back(&q_warm, &conf) {
        return Ok(Solution { exact, q_nominal });
    }
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
    Ok(Solution { exact, q_nominal })
}

/// Why no warm solution lies within the limits, where the one nearest the
/// cold joints `near` passes one: "axis 3 at 50.001° (49.992° cold)
/// beyond the IRB 140's +50°".
fn beyond_warm_limit(
    warm: &WarmRobot,
    flange: &Isometry3<f64>,
    near: &Joints,
    state: &State,
) -> Option<Error> {
    let q = warm.joints_near(flange, near, false, state).ok()?;
    let v = *warm.nominal.outside_limits(&q).first()?;
    let cold = format!(" ({}° cold)", crate::robot::degrees_text(near[v.0]));
    Some(
        Error::new(
            ErrorKind::Unreachable,
            super::joints::limit_words(&warm.nominal.name, &v, &cold),
        )
        .with_note("the pose is taught at the limit: the warm arm needs the axis past it, on this configuration and on every other (configuration monitoring is off, so any would do)"),
    )
}

/// The warm joints within the arm's limits that put the flange at
/// `flange`, nearest `near` (every branch, axes 4 and 6 a turn either
/// way): what a controller without configuration monitoring moves to.
fn nearest_within_limits(
    warm: &WarmRobot,
    flange: &Isometry3<f64>,
    near: &Joints,
    state: &State,
) -> Option<Joints> {
    let turn = std::f64::consts::TAU;
    let distance = |q: &Joints| (0..6).map(|j| (q[j] - near[j]).powi(2)).sum::<f64>();
    let mut best: Option<Joints> = None;
    for b in warm.nominal.branches_scaled(flange, &state.scales).ok()? {
        for k4 in [-1.0, 0.0, 1.0] {
            for k6 in [-1.0, 0.0, 1.0] {
                let mut q = b;
                q[3] += k4 * turn;
                q[5] += k6 * turn;
                let better = best.is_none_or(|p| distance(&q) < distance(&p));
                if better && warm.nominal.outside_limits(&q).is_empty() {
                    best = Some(q);
                }
            }
        }
    }
    let q = best?;
    if warm.is_pure_expansion() {
        return Some(q);
    }
    // Effects beyond expansion: refined from that branch.
    let q = warm.joints_near(flange, &q, false, state).ok()?;
    warm.nominal.outside_limits(&q).is_empty().then_some(q)
}

/// The solution of the nominal arm whose axes lie nearest the quadrants of
/// `conf` (same cfx preferred).
pub(super) fn nearest_solution(
    warm: &WarmRobot,
    flange: &Isometry3<f64>,
    conf: &RobConf,
) -> Option<Joints> {
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

pub(super) fn prefix(e: Error, context: &str) -> Error {
    Error {
        message: format!("{context}: {}", e.message),
        ..e
    }
}

pub(super) fn at_target(program: &Program, target: &Target, e: Error) -> Error {
    e.about(Subject::Target(target.id.clone()))
        .at(program.location(&target.origin))
}
