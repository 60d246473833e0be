//! The per-target solve: the flange pose a target means, the warm joints
//! that reach it, the nominal pose those joints are for the controller, and
//! the check that the controller picks the same joints back.

use super::derived::{calls_by_offset, unapply_with};
use super::edits::{quaternion_like, ORIENTATION_CHANGE_RAD};
use super::expressions::{Evaluated, Expressions};
use super::moments::{minute_of, moments_of, pick};
use super::outcome::{leave, Correction, Frame, LeftAlone, Reason};
use super::shared::{Names, OtherPair};
use super::Options;
use crate::error::{Error, ErrorKind, Result};
use crate::model::{Moment, State, States, WarmRobot};
use crate::rapid::constants::{Constants, Site};
use crate::rapid::rewrite::robtarget_edits;
use crate::rapid::{Expr, FunctionCall, Program, Storage, Target, TargetKind};
use crate::resolve::dataflow::{runtime_writes, Write};
use crate::resolve::{frames_of, target_pose, usages, Frames, Through, Usage};
use crate::robot::conf::{quadrant_distance, RobConf};
use crate::robot::frames::{flange_of_target, target_of_flange, ToolData, WobjData};
use crate::robot::Joints;
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use std::cell::{OnceCell, RefCell};
use std::collections::HashMap;

/// What became of one robtarget: corrected (with its other tool and
/// work object pairs, if any), or left alone.
pub(super) enum Solved {
    Corrected(Box<Correction>, Vec<OtherPair>),
    LeftAlone(LeftAlone),
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
    /// Robtarget and jointtarget variables the run writes, by lower-case
    /// name.
    pub writes: HashMap<String, Write>,
    pub constants: Constants<'a>,
    /// Every function call of the program by where it starts.
    pub calls: HashMap<usize, &'a FunctionCall>,
    pub expressions: Expressions<'a>,
    /// Choices made on the way that the user should know about.
    pub notes: RefCell<Vec<String>>,
    /// Where names are declared and read, for splitting targets (built
    /// when first needed).
    pub names: OnceCell<Names>,
}

impl<'a> Run<'a> {
    pub fn new(program: &'a Program, warm: &'a WarmRobot, options: &'a Options) -> Result<Run<'a>> {
        Ok(Run {
            program,
            warm,
            states: warm.states(),
            options,
            frames: match &options.base_frame {
                Some(base) => Frames::of_program(program)?.placed(base),
                None => Frames::of_program(program)?,
            },
            uses: usages(program),
            conf_off: configuration_monitoring_off(program),
            writes: runtime_writes(program),
            constants: Constants::of(program),
            calls: calls_by_offset(program),
            expressions: Expressions::of(program),
            notes: RefCell::new(Vec::new()),
            names: OnceCell::new(),
        })
    }

    /// The value of a number in the program as written at `target`
    /// (literals and constants).
    pub fn eval(&self, target: &Target, e: &Expr) -> Option<f64> {
        let site = Site {
            module: &target.origin.module,
            routine: target.origin.routine.as_deref(),
        };
        self.constants.num(e, site)
    }
}

/// Why a robtarget is not corrected, when it is not: its value is decided
/// at run time, it is written with expressions (and the run was not asked
/// to write numbers in their place), or no move reaches it.
fn left_alone(run: &Run, index: usize, target: &Target) -> Option<LeftAlone> {
    let program = run.program;
    let variable = matches!(target.storage, Some(Storage::Var | Storage::Pers));
    if variable && target.kind != TargetKind::Assigned {
        let name = target.name.as_deref().unwrap_or_default().to_lowercase();
        if let Some(w) = run.writes.get(&name) {
            return Some(leave(
                program,
                target,
                Reason::Runtime,
                format!(
                    "{} is {} at run time ({} line {}): its declared value is not what the robot moves to",
                    w.variable, w.how, w.routine, w.line
                ),
            ));
        }
        if let Some(v) = &target.value {
            if v.rot_values().iter().all(|&x| x == 0.0) {
                return Some(leave(
                    program,
                    target,
                    Reason::Runtime,
                    "a placeholder (zero quaternion) that the run fills in",
                ));
            }
        }
    }
    if target.kind != TargetKind::Inline && !run.uses.contains_key(&index) {
        return Some(leave(
            program,
            target,
            Reason::Unused,
            "no move instruction of the program reaches it, so its tool and work object are unknown",
        ));
    }
    None
}

/// The corrected pose of one meant TCP pose, and the joints involved.
struct Solution {
    /// The corrected target: its nominal pose is where the warm robot
    /// must be sent.
    exact: Isometry3<f64>,
    /// The nominal joints of the pose as written (for the drift).
    q_nominal: Joints,
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
    pub moments: Vec<Moment>,
    pub moment: Moment,
    pub state: State,
}

/// Correct the robtarget `index` of the program: the warm joints that
/// reach the flange pose it means, written back as the nominal pose of
/// those joints in the target's own tool and work object. A target moved
/// to with several tools or work objects is corrected for its first use's
/// pair; its other pairs are returned for the report (or a split).
pub(super) fn correct_robtarget(run: &Run, index: usize, target: &Target) -> Result<Solved> {
    let Run {
        program,
        states,
        options,
        frames,
        uses,
        ..
    } = run;
    if let Some(left) = left_alone(run, index, target) {
        return Ok(Solved::LeftAlone(left));
    }
    let target_uses = uses.get(&index);
    let mut evaluated: Option<Evaluated> = None;
    let (pose, conf) = match &target.value {
        Some(_) => target_pose(program, target)?.ok_or_else(|| {
            at_target(program, target, Error::input("a robtarget without numbers"))
        })?,
        None => {
            let value = run.expressions.evaluate(run, target);
            let Some(v) = value.filter(|_| options.expand_expressions) else {
                return Ok(Solved::LeftAlone(run.expressions.left_alone(run, target)));
            };
            let pc = v.pose_conf().map_err(|e| at_target(program, target, e))?;
            evaluated = Some(v);
            pc
        }
    };
    let (tool, wobj, tool_name, wobj_name) = frames_of(program, frames, index, target_uses)?;
    let names = [
        tool_name.as_deref().unwrap_or("tool0"),
        wobj_name.as_deref().unwrap_or("wobj0"),
    ];
    if let Err(e) = flange_of_target(&pose, &tool, &wobj) {
        if e.kind == ErrorKind::Unsupported {
            return Ok(Solved::LeftAlone(leave(
                program,
                target,
                Reason::Coordinated,
                e.message,
            )));
        }
    }
    let moments = moments_of(&options.when, &target.id)
        .map_err(|e| e.at(program.location(&target.origin)))?;
    let moment = pick(&moments, options.visit);
    let state = states
        .at(moment)
        .map_err(|e| at_target(program, target, e))?;
    let meant = Meant {
        pose,
        conf,
        evaluated: evaluated.as_ref(),
        moments,
        moment,
        state,
    };
    // The uses the target is corrected for: those with its first use's
    // tool and work object (copied only when some use has another pair:
    // a CAM program has millions of targets with one use each).
    let filtered: Vec<Usage>;
    let first_pair = match target_uses {
        Some(u) if u.iter().any(|x| !x.same_frames(&u[0])) => {
            filtered = u.iter().filter(|x| x.same_frames(&u[0])).cloned().collect();
            Some(&filtered)
        }
        other => other,
    };
    let exact = by_derived_uses(run, target, first_pair, &meant, (&tool, &wobj))?;
    let mut correction = corrected(run, target, &meant, (&tool, &wobj), names, exact)?;
    if let Some(first) = target_uses.and_then(|u| u.first()) {
        correction.order = (first.file, first.offset);
    }
    let others = super::shared::other_pairs(run, index, target, &meant, &correction)?;
    Ok(Solved::Corrected(Box::new(correction), others))
}

/// The correction of a target for one tool and work object (`names`, as
/// the report gives them): the solve,
/// or `exact` where it is already known (a base placed by its derived
/// uses), the drift over the target's moments, and the edits writing the
/// new numbers over the literal.
pub(super) fn corrected(
    run: &Run,
    target: &Target,
    meant: &Meant,
    frames: (&ToolData, &WobjData),
    names: [&str; 2],
    exact: Option<Isometry3<f64>>,
) -> Result<Correction> {
    let src = run.program.source(target.origin.file);
    corrected_in(run, src, target, meant, frames, names, exact)
}

/// [`corrected`] for a target whose numbers lie in `src` (a streamed
/// file the run's program was cut from).
pub(super) fn corrected_in(
    run: &Run,
    src: &[u8],
    target: &Target,
    meant: &Meant,
    (tool, wobj): (&ToolData, &WobjData),
    [tool_name, wobj_name]: [&str; 2],
    exact: Option<Isometry3<f64>>,
) -> Result<Correction> {
    let Numbers {
        exact,
        drift,
        range,
        turn,
        turned,
        new_rot,
    } = corrected_numbers(run, target, meant, (tool, wobj), exact)?;
    let Meant {
        pose,
        evaluated,
        moment,
        state,
        ..
    } = meant;
    let new_trans = exact.translation.vector;
    let edits = match (&target.value, evaluated) {
        (Some(value), _) => robtarget_edits(src, value, new_trans.into(), turned, None),
        (None, Some(e)) => e.edits(src, new_trans.into(), turned),
        (None, None) => Vec::new(),
    };
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
    Ok(Correction {
        id: target.id.clone(),
        kind: super::outcome::kind_of(target).to_string(),
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
        rewritten: !edits.is_empty(),
        exact: Some(exact),
        world_mm: in_world(run, pose, tool, wobj),
        order: (target.origin.file, target.origin.pos.offset),
        edits,
        file_index: target.origin.file,
    })
}

/// The numbers of one target's correction, without its report row or
/// its edits: what a streamed run of a million targets keeps of each.
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

/// The solve of [`corrected_in`], or `exact` where it is already known,
/// the drift over the target's moments, and what is to be written over
/// the literal (the position of `exact`, and `turned`).
pub(super) fn corrected_numbers(
    run: &Run,
    target: &Target,
    meant: &Meant,
    (tool, wobj): (&ToolData, &WobjData),
    exact: Option<Isometry3<f64>>,
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
    let solution = solve(run, target, pose, conf, (tool, wobj), state, *moment)?;
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
    tool: &ToolData,
    wobj: &WobjData,
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
    let uses = run.uses.get(&index);
    if uses.is_none() && target.kind != TargetKind::Inline {
        return None;
    }
    let (pose, _) = match &target.value {
        Some(_) => target_pose(run.program, target).ok()??,
        None => run.expressions.evaluate(run, target)?.pose_conf().ok()?,
    };
    let (tool, wobj, _, _) = frames_of(run.program, &run.frames, index, uses).ok()?;
    in_world(run, &pose, &tool, &wobj)
}

/// The corrected target for one meant pose (TCP `pose` in its work object,
/// robconf `conf`) at one thermal state.
fn solve(
    run: &Run,
    target: &Target,
    pose: &Isometry3<f64>,
    conf: &RobConf,
    (tool, wobj): (&ToolData, &WobjData),
    state: &State,
    moment: Moment,
) -> Result<Solution> {
    let Run {
        program,
        warm,
        conf_off,
        ..
    } = run;
    let flange = match flange_of_target(pose, tool, wobj) {
        Ok(f) => f,
        Err(e) => return Err(at_target(program, target, e)),
    };
    let (q_nominal, conf) = match warm.nominal.ik_conf(&flange, conf) {
        Ok(q) => (q, *conf),
        // With configuration monitoring off the controller takes the
        // solution nearest the robot's current one and ignores the
        // robconf; the nearest-quadrant solution stands for it, and a
        // correction of tenths of a millimetre keeps that branch.
        Err(e) if *conf_off && e.kind == ErrorKind::Unreachable => {
            match nearest_solution(warm, &flange, conf) {
                Some(q) => {
                    let nearest = warm.nominal.conf_of(&q);
                    let note = format!(
                        "target {} (line {}): robconf {conf} matches no solution; configuration monitoring is off (ConfL/ConfJ \\Off), so it is corrected on the nearest configuration {nearest}",
                        target.id, target.origin.pos.line
                    );
                    let mut notes = run.notes.borrow_mut();
                    if !notes.contains(&note) {
                        notes.push(note);
                    }
                    (q, nearest)
                }
                None => return Err(at_target(program, target, prefix(e, "as written"))),
            }
        }
        Err(e) => return Err(at_target(program, target, prefix(e, "as written"))),
    };
    let q_warm = warm.joints_for(&flange, &conf, state).map_err(|e| {
        at_target(
            program,
            target,
            prefix(e, &format!("on the warm robot at {moment}")),
        )
    })?;
    let corrected_flange = warm.nominal.fk(&q_warm);
    let exact = target_of_flange(&corrected_flange, tool, wobj)?;
    // The controller must pick back the warm joints from the corrected
    // target and the unchanged robconf: certain without solving away from
    // every boundary (a third of the solving of a million targets), else
    // solved.
    if warm.nominal.picks_back(&q_warm, &conf) {
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

/// A base no move names, reached only through `Offs`/`RelTool` with
/// offsets known before the run (`MoveL Offs(pPallet, 0, 0, 50), ...`): it
/// is corrected so that its derived poses land, on average. Each use's
/// derived pose is corrected as a target of its own; the base that use
/// asks for is that corrected pose with the offset taken back; the base
/// written is the mean of those (positions averaged, orientations by the
/// normalised sum of aligned quaternions). What remains at each use is
/// reported as that derived target's residual. `uses` are those with the
/// tool and work object the base is corrected for (its first use's).
/// `None` when the rule does not apply: a move names the base itself
/// (then it is corrected for that), or no use has offsets known before
/// the run.
fn by_derived_uses(
    run: &Run,
    target: &Target,
    uses: Option<&Vec<Usage>>,
    meant: &Meant,
    frames: (&ToolData, &WobjData),
) -> Result<Option<Isometry3<f64>>> {
    let Meant {
        pose,
        conf,
        state,
        moment,
        ..
    } = meant;
    let Some(uses) = uses else { return Ok(None) };
    if uses
        .iter()
        .any(|u| !matches!(u.through, Through::Derived(_)))
    {
        return Ok(None);
    }
    let eval = |e: &Expr| run.eval(target, e);
    let mut bases: Vec<Isometry3<f64>> = Vec::new();
    let mut seen = Vec::new();
    for u in uses {
        let Through::Derived(i) = u.through else {
            continue;
        };
        if seen.contains(&i) {
            continue;
        }
        seen.push(i);
        let derived = &run.program.targets()[i];
        let Some(call) = run.calls.get(&derived.origin.pos.offset) else {
            continue;
        };
        let Some(meant) = super::derived::apply_with(call, pose, &eval) else {
            continue;
        };
        let sol = solve(run, derived, &meant, conf, frames, state, *moment)?;
        if let Some(base) = unapply_with(call, &sol.exact, &eval) {
            bases.push(base);
        }
    }
    if bases.is_empty() {
        return Ok(None);
    }
    let n = bases.len() as f64;
    let position = bases
        .iter()
        .map(|b| b.translation.vector)
        .sum::<Vector3<f64>>()
        / n;
    let first = bases[0].rotation.into_inner();
    let sum = bases
        .iter()
        .map(|b| {
            let q = b.rotation.into_inner();
            if q.dot(&first) < 0.0 {
                -q
            } else {
                q
            }
        })
        .fold(nalgebra::Quaternion::new(0.0, 0.0, 0.0, 0.0), |a, q| a + q);
    let rotation = UnitQuaternion::from_quaternion(sum);
    Ok(Some(Isometry3::from_parts(position.into(), rotation)))
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
    let message = format!("target {}: {}", target.id, e.message);
    Error { message, ..e }.at(program.location(&target.origin))
}
