//! One robtarget's whole treatment: left alone and why, or what it
//! means, its tool and work object, its moments, its solve (or its
//! derived uses' mean, for a base reached only through Offs/RelTool), and
//! its uses with other tools or work objects.

use super::context::Run;
use super::derived::unapply_with;
use super::expressions::Evaluated;
use super::moments::{moments_of, pick};
use super::outcome::{leave, Correction, LeftAlone, Reason};
use super::shared::OtherPair;
use super::solve::{
    at_target, corrected_numbers, edits_of, row, solve, InConf, Known, Meant, Numbers, Rewrite,
};
use crate::error::{Error, ErrorKind, Result};
use crate::model::{Moment, State};
use crate::rapid::{Expr, Storage, Target, TargetKind};
use crate::resolve::{frames_for_in, target_pose, Through, Usage};
use crate::robot::conf::RobConf;
use crate::robot::frames::{check_setup, ToolFrame, WobjFrames};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use std::borrow::Cow;

/// What became of one robtarget: solved (its numbers, for its first
/// use's tool and work object), or left alone.
pub(super) enum Solved<'r> {
    Corrected(Box<SolvedTarget<'r>>),
    LeftAlone(LeftAlone),
}

/// A robtarget solved: what it means and when ([`Meant`]), its first
/// pair's tool and work object, and its corrected numbers.
pub(super) struct SolvedTarget<'r> {
    pub evaluated: Option<Evaluated>,
    pub pose: Isometry3<f64>,
    pub conf: RobConf,
    pub moments: super::moments::Moments,
    pub moment: Moment,
    pub state: State,
    /// The run's frames by those names.
    pub frames: (&'r ToolFrame, &'r WobjFrames),
    /// The tool's and work object's names as the report gives them.
    pub names: [Cow<'r, str>; 2],
    pub numbers: Numbers,
    /// Where the program first moves to it (file, byte offset).
    pub order: Option<(usize, usize)>,
}

impl SolvedTarget<'_> {
    pub fn meant(&self) -> Meant<'_> {
        Meant {
            pose: self.pose,
            conf: self.conf,
            evaluated: self.evaluated.as_ref(),
            moments: self.moments.clone(),
            moment: self.moment,
            state: self.state,
        }
    }

    /// Its report row, with the edits writing its numbers.
    pub fn correction(&self, run: &Run, target: &Target) -> Correction {
        let meant = self.meant();
        let src = run.program.source(target.origin.file);
        let edits = edits_of(src, target, &meant, &self.numbers);
        let mut c = row(
            run,
            target,
            &meant,
            self.frames,
            [&self.names[0], &self.names[1]],
            &self.numbers,
            Rewrite::with(edits),
        );
        if let Some(order) = self.order {
            c.order = order;
        }
        c
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
        if let Some(w) = run.set.writes.get(&name) {
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
    if !run.set.unsettled_frames.is_empty() {
        if let Some(left) = unsettled_frames(run, index, target) {
            return Some(left);
        }
    }
    if target.kind != TargetKind::Inline && !run.set.uses.contains(index) {
        if let Some(why) = run.set.by_name.why(&target.id) {
            return Some(leave(program, target, Reason::Runtime, why));
        }
        return Some(leave(
            program,
            target,
            Reason::Unused,
            "no move instruction of the program reaches it, so its tool and work object are unknown",
        ));
    }
    None
}

/// A target some move reaches with a tool or work object that is a
/// parameter its calls do not settle: the frames it moves in are the
/// run's, and correcting it for any one would be a guess.
fn unsettled_frames(run: &Run, index: usize, target: &Target) -> Option<LeftAlone> {
    for u in run.set.uses.of(index) {
        let routine = u.routine().to_ascii_lowercase();
        for (what, name) in [("tool", u.tool()), ("work object", u.wobj())] {
            let Some(name) = name else { continue };
            if run
                .set
                .unsettled_frames
                .contains(&(routine.clone(), name.to_ascii_lowercase()))
            {
                return Some(leave(
                    run.program,
                    target,
                    Reason::Parameter,
                    format!(
                        "moved to by {} in {} (line {}) with {what} {name}, a parameter of {} that its calls do not settle (each must pass a {what} declared in the files read)",
                        u.instruction(),
                        u.routine(),
                        u.line(),
                        u.routine()
                    ),
                ));
            }
        }
    }
    None
}

/// Correct the robtarget `index` of the program: the warm joints that
/// reach the flange pose it means, written back as the nominal pose of
/// those joints in the target's own tool and work object. A target moved
/// to with several tools or work objects is corrected for its first use's
/// pair ([`with_others`] says what its other pairs come to).
pub(super) fn correct_robtarget<'r>(
    run: &'r Run,
    index: usize,
    target: &Target,
) -> Result<Solved<'r>> {
    let Run {
        program,
        states,
        options,
        set,
        ..
    } = run;
    let (frames, uses) = (&set.frames, &set.uses);
    if let Some(left) = left_alone(run, index, target) {
        return Ok(Solved::LeftAlone(left));
    }
    let first = uses.first(index);
    let mut evaluated: Option<Evaluated> = None;
    let (pose, conf) = match &target.value {
        Some(_) => target_pose(program, target)?.ok_or_else(|| {
            at_target(program, target, Error::input("a robtarget without numbers"))
        })?,
        None => {
            let value = run.set.expressions.evaluate(&run.set.constants, target);
            let Some(v) = value.filter(|_| options.expand_expressions) else {
                return Ok(Solved::LeftAlone(run.set.expressions.left_alone(
                    run.program,
                    &run.set.constants,
                    target,
                )));
            };
            let pc = v.pose_conf().map_err(|e| at_target(program, target, e))?;
            evaluated = Some(v);
            pc
        }
    };
    // Frames another task or module sets at run time: the run's.
    let named = match first {
        Some(f) => [f.tool(), f.wobj()],
        None => [target.tool.as_deref(), target.wobj.as_deref()],
    };
    for (what, name) in ["tooldata", "wobjdata"].into_iter().zip(named) {
        if let Some(name) = name.filter(|n| frames.set_elsewhere(n)) {
            return Ok(Solved::LeftAlone(leave(
                program,
                target,
                Reason::SetElsewhere,
                format!("its {what} `{name}` is PERS data declared without a value: another task or module sets it at run time"),
            )));
        }
    }
    // The names of the first move to it (borrowed from the run), else
    // the target's own.
    let (tool, wobj, tool_name, wobj_name) =
        frames_for_in(program, frames, target, first.map(|f| (f.tool(), f.wobj())))?;
    let names = [
        tool_name.unwrap_or(Cow::Borrowed("tool0")),
        wobj_name.unwrap_or(Cow::Borrowed("wobj0")),
    ];
    if let Err(e) = check_setup(tool, wobj) {
        if e.kind == ErrorKind::Unsupported {
            return Ok(Solved::LeftAlone(leave(
                program,
                target,
                Reason::Coordinated,
                e.message,
            )));
        }
    }
    let moments = moments_of(&options.when, index, &target.id)
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
    // A base reached only through derived expressions (every use of its
    // first pair a `Through::Derived`): its uses are looked at one by one
    // (a CAM program has millions of targets with one direct use each).
    let exact = match first {
        Some(f) if matches!(f.through(), Through::Derived(_)) => {
            let first_pair: Vec<Usage> = uses
                .of(index)
                .filter(|u| u.same_frames(&f))
                .map(|u| u.to_usage())
                .collect();
            by_derived_uses(run, target, Some(&first_pair), &meant, (tool, wobj))?
        }
        _ => None,
    };
    // The cold joints the walk of a `--start` run found for this very
    // literal in these very frames: the solve would find them again.
    let cold = match (&target.value, &run.cold_joints) {
        (Some(_), Some(r)) => r.joints(index, tool, wobj),
        _ => None,
    };
    let numbers = corrected_numbers(run, target, &meant, (tool, wobj), Known { exact, cold })?;
    let Meant { moments, .. } = meant;
    Ok(Solved::Corrected(Box::new(SolvedTarget {
        evaluated,
        pose,
        conf,
        moments,
        moment,
        state,
        frames: (tool, wobj),
        names,
        numbers,
        order: first.map(|f| (f.file(), f.offset())),
    })))
}

/// The correction of a target moved to with several tools or work
/// objects, and its other pairs (a line each for the report, and with a
/// split asked for, the copies).
pub(super) fn with_others(
    run: &Run,
    index: usize,
    target: &Target,
    found: &SolvedTarget,
) -> Result<(Correction, Vec<OtherPair>)> {
    let correction = found.correction(run, target);
    let others = super::shared::other_pairs(run, index, target, &found.meant(), &correction)?;
    Ok((correction, others))
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
    frames: (&ToolFrame, &WobjFrames),
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
        let derived = run.program.targets().at(i);
        let derived = &*derived;
        let Some(call) = run.set.calls.get(&derived.origin.pos.offset) else {
            continue;
        };
        let Some(meant) = super::derived::apply_with(call, pose, &eval) else {
            continue;
        };
        let in_conf = InConf { conf, cold: None };
        let sol = solve(run, derived, &meant, in_conf, frames, state, *moment)?;
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
