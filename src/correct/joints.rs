//! MoveAbsJ jointtargets: the same flange pose, reached by the warm arm
//! with the joints nearest the ones written.
//!
//! Rules:
//! - A jointtarget has no robconf: its joints are the truth. The warm
//!   joints are the warm solution nearest the written ones, each axis
//!   taken within ±180° of its written value (the controller moves the
//!   axes, it does not wrap them), whatever configuration that solution
//!   has: a warm axis 6 crossing 90°, or an elbow bending off a stretched
//!   arm, is no reason to refuse.
//! - Refused only where an axis lies beyond the arm's limits (as written,
//!   or in the warm solution), naming the axis, its value and the limit.
//! - At a wrist singularity (axis 5 written as 0) axes 4 and 6 turn about
//!   one line and only their sum is fixed by the pose: any split is "the
//!   same pose", but the arm would turn them by up to 180° differently.
//!   Axis 4 keeps its written value; the other five are solved on the warm
//!   model in the least-squares sense, and what of the pose remains is
//!   reported as the target's residual.
//! - Robot axes all `9E+09` (a positioner's jointtarget): nothing of the arm
//!   to correct; left alone. External axes are never changed.

use super::context::Run;
use super::moments::{joint_moments_of, minute_of, pick};
use super::outcome::{Correction, Frame, Kind, LeftAlone, Reason, Residual};
use super::progress::Progress;
use crate::error::{Error, ErrorKind, Location, Result, Subject};
use crate::model::warm::{pose_error, wrap_near};
use crate::model::{Moment, State};
use crate::rapid::rewrite::{jointtarget_edits, Edit};
use crate::rapid::{JointTarget, Storage, TargetKind};
use crate::robot::{degrees_text, Joints, Violation};
use nalgebra::{Isometry3, Matrix6x5, Vector5, Vector6};

/// RAPID's "no value" for an axis: `9E+09`, as the controller keeps it in
/// single precision (a relative step of 6e-8), so within a millionth.
const NO_AXIS: f64 = 9e9;

/// Whether an axis value is RAPID's "no value".
fn no_value(v: f64) -> bool {
    (v - NO_AXIS).abs() <= NO_AXIS * 1e-6
}

/// An axis beyond this (degrees) is no angle (a typing or unit mistake):
/// far past any arm's travel.
const NO_ANGLE_DEG: f64 = 1e6;

/// Whether an axis value can be an angle (a value that is not a number
/// cannot).
fn is_angle(v: f64) -> bool {
    v.abs() < NO_ANGLE_DEG
}

/// Axis 5 closer to 0 than this (degrees) is a wrist singularity: the
/// written value is 0 to the controller's resolution.
const SINGULAR_DEG: f64 = 1e-3;

/// Orientation weight in the least-squares solve (mm per radian). With
/// axis 4 held, the pose has one direction of turn the other axes cannot
/// make; the flange position is reached first (a small weight) and that
/// turn is what is left, reported as the residual.
const ORIENTATION_MM_PER_RAD: f64 = 1.0;

/// What became of one jointtarget.
pub(super) enum JointSolved {
    Corrected(Box<Correction>, Option<Residual>),
    LeftAlone(LeftAlone),
}

/// Jointtarget number `index` of the program, `jt`, corrected.
pub(super) fn correct_jointtarget(
    run: &Run,
    index: usize,
    jt: &JointTarget,
) -> Result<JointSolved> {
    let Run {
        warm,
        states,
        options,
        ..
    } = run;
    let one = OneJoint {
        run,
        jt,
        location: run.program.location(&jt.origin),
    };
    let degrees: [f64; 6] = jt.robax.each_ref().map(|n| n.value);
    if let Some(left) = one.not_corrected(&degrees)? {
        return Ok(left);
    }
    let q: Joints = degrees.map(f64::to_radians);
    let nominal = &warm.nominal;
    // Written beyond a limit, the controller refuses the move itself: its
    // joints are the truth, so no other configuration stands in for it.
    if let Some(v) = nominal.outside_limits(&q).first() {
        return Err(one.located(beyond_limit(&nominal.name, v, "")));
    }
    let flange = nominal.fk(&q);
    let moments = joint_moments_of(&options.when, index, &jt.id).map_err(|e| one.located(e))?;
    let moment = pick(&moments, options.visit);
    let state = states.at(moment).map_err(|e| one.located(e))?;
    let singular = degrees[4].abs() < SINGULAR_DEG;
    let mut q_warm = warm
        .joints_near(&flange, &q, singular, &state)
        .map_err(|e| one.located(e))?;
    if singular {
        q_warm = keep_axis_4(run, &flange, &q, &q_warm, &state);
    }
    let residual = one.residual(&flange, &q_warm, &state, singular);
    // The warm arm needs an axis past its limit: the one refusal a
    // jointtarget can meet (no configuration boundary is one).
    if let Some(v) = nominal.outside_limits(&q_warm).first() {
        return Err(one.located(beyond_limit(
            &nominal.name,
            v,
            " on the warm robot (written within its limits)",
        )));
    }
    if q_warm.iter().any(|x| !x.is_finite()) {
        return Err(one.located(Error::new(
            ErrorKind::NoConvergence,
            "the warm joints are not finite numbers",
        )));
    }
    let row = one.row(&Solution {
        degrees,
        q,
        flange,
        q_warm,
        moment,
        state,
    });
    Ok(JointSolved::Corrected(Box::new(row), residual))
}

/// The jointtarget being corrected, and where it is written.
struct OneJoint<'r, 'a> {
    run: &'r Run<'a>,
    jt: &'r JointTarget,
    location: Location,
}

/// What the solve of one jointtarget found: its written joints (degrees
/// and radians), the flange pose they mean, the warm joints that reach
/// it, and the moment and state they were solved for.
struct Solution {
    degrees: [f64; 6],
    q: Joints,
    flange: Isometry3<f64>,
    q_warm: Joints,
    moment: Moment,
    state: State,
}

impl OneJoint<'_, '_> {
    /// An error about this jointtarget, at its place.
    fn located(&self, e: Error) -> Error {
        e.about(Subject::JointTarget(self.jt.id.clone()))
            .at(self.location.clone())
    }

    /// This jointtarget left alone for `reason`.
    fn leave(&self, reason: Reason, detail: String) -> JointSolved {
        let jt = self.jt;
        JointSolved::LeftAlone(LeftAlone {
            id: jt.id.clone(),
            kind: Kind::JointTarget,
            file: self.location.file.clone(),
            line: jt.origin.pos.line,
            col: jt.origin.pos.col,
            reason,
            detail,
            world_mm: None,
        })
    }

    /// The jointtarget left alone (no robot axes, or changed at run time)
    /// or refused (axes that are no angles, or only some of them given),
    /// on its written axes alone; None where it is to be solved.
    fn not_corrected(&self, degrees: &[f64; 6]) -> Result<Option<JointSolved>> {
        let (run, jt) = (self.run, self.jt);
        let absent = degrees.iter().filter(|d| no_value(**d)).count();
        if let Some(i) = (0..6).find(|&i| !no_value(degrees[i]) && !is_angle(degrees[i])) {
            return Err(self.located(Error::input(format!(
                "axis {} is {:e}: neither an angle nor 9E+09 (no value)",
                i + 1,
                degrees[i]
            ))));
        }
        if absent == 6 {
            return Ok(Some(self.leave(
                Reason::NoRobotAxes,
                "its robot axes are all 9E+09 (a positioner's or external axes' target): no joint of the arm to correct".to_string(),
            )));
        }
        if absent > 0 {
            return Err(self.located(Error::input(format!(
                "{absent} of its robot axes are 9E+09 and the others are angles: a jointtarget of the arm gives all six"
            ))));
        }
        if matches!(jt.storage, Some(Storage::Var | Storage::Pers)) {
            let name = jt.name.as_deref().unwrap_or_default().to_lowercase();
            if let Some(w) = run.set.writes.get(&name) {
                return Ok(Some(self.leave(
                    Reason::Runtime,
                    format!(
                        "{} is {} at run time ({} line {}): its declared value is not what the robot moves to",
                        w.variable, w.how, w.routine, w.line
                    ),
                )));
            }
        }
        Ok(None)
    }

    /// What of the flange pose the warm joints miss, where they miss it.
    fn residual(
        &self,
        flange: &Isometry3<f64>,
        q_warm: &Joints,
        state: &State,
        singular: bool,
    ) -> Option<Residual> {
        let jt = self.jt;
        let r = pose_error(flange, &self.run.warm.flange(q_warm, state));
        let (position_mm, angle_deg) = (
            r.fixed_rows::<3>(0).norm(),
            r.fixed_rows::<3>(3).norm().to_degrees(),
        );
        if position_mm > 1e-6 || angle_deg > 1e-6 {
            let rule = if singular {
                "wrist singular (axis 5 at 0): axis 4 kept as written"
            } else {
                "the warm model's joints nearest the written ones reach no nearer"
            };
            return Some(Residual {
                id: jt.id.clone(),
                file: self.location.file.clone(),
                line: jt.origin.pos.line,
                position_mm,
                angle_deg,
                rule: rule.to_string(),
            });
        }
        None
    }

    /// The jointtarget's report row, with the edits of its new joints.
    fn row(&self, s: &Solution) -> Correction {
        let (run, jt) = (self.run, self.jt);
        let (warm, program) = (run.warm, run.program);
        let Solution {
            degrees,
            q,
            flange,
            q_warm,
            moment,
            ref state,
        } = *s;
        let new_deg = q_warm.map(f64::to_degrees);
        let drift = warm.flange(&q, state).translation.vector - flange.translation.vector;
        let src = program.source(jt.origin.file);
        let edits = jointtarget_edits(src, jt, new_deg);
        let dangle = degrees
            .iter()
            .zip(&new_deg)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let corrected_flange = warm.nominal.fk(&q_warm);
        let correction = corrected_flange.translation.vector - flange.translation.vector;
        Correction {
            id: jt.id.clone(),
            kind: Kind::JointTarget,
            file: self.location.file.clone(),
            line: jt.origin.pos.line,
            col: jt.origin.pos.col,
            time_min: minute_of(moment),
            temps_c: state.temps,
            tool: None,
            wobj: None,
            frame: Frame::BaseFlange,
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
            world_mm: Some(
                run.options
                    .base_frame
                    .map_or(flange, |base| base * flange)
                    .translation
                    .vector
                    .into(),
            ),
            order: (jt.origin.file, jt.origin.pos.offset),
            edits,
            file_index: jt.origin.file,
        }
    }
}

/// The warm joints with axis 4 at its written value: axis 6 takes over
/// what the solve gave axis 4 (they turn about one line at the
/// singularity), then axes 1, 2, 3, 5 and 6 are refined by Gauss-Newton on
/// the warm model.
fn keep_axis_4(
    run: &Run,
    flange: &Isometry3<f64>,
    q: &Joints,
    q_warm: &Joints,
    state: &State,
) -> Joints {
    let warm = run.warm;
    let error = |x: &Joints| weighted(&pose_error(flange, &warm.flange(x, state)));
    let moved = q_warm[3] - q[3];
    let candidates = [1.0, -1.0].map(|s| {
        let mut x = *q_warm;
        x[3] = q[3];
        x[5] = wrap_near(q_warm[5] + s * moved, q[5]);
        x
    });
    let mut x = if error(&candidates[0]).norm() <= error(&candidates[1]).norm() {
        candidates[0]
    } else {
        candidates[1]
    };
    const FREE: [usize; 5] = [0, 1, 2, 4, 5];
    const H: f64 = 1e-7;
    for _ in 0..20 {
        let r = error(&x);
        if r.norm() < 1e-10 {
            break;
        }
        let mut j = Matrix6x5::zeros();
        for (col, &axis) in FREE.iter().enumerate() {
            let (mut p, mut m) = (x, x);
            p[axis] += H;
            m[axis] -= H;
            // pose_error(goal, at) is goal − at, so this column is the
            // (weighted) pose's derivative: J·step = r moves onto the goal.
            j.set_column(col, &((error(&m) - error(&p)) / (2.0 * H)));
        }
        let Ok(step) = j.svd(true, true).solve(&r, 1e-12) else {
            break;
        };
        let step: Vector5<f64> = step;
        // Halve the step until it helps: near the singularity the model
        // is far from linear over a full step.
        let better = (0..12).map(|k| 0.5f64.powi(k)).find_map(|alpha| {
            let mut next = x;
            for (col, &axis) in FREE.iter().enumerate() {
                next[axis] += alpha * step[col];
            }
            (error(&next).norm() < r.norm()).then_some(next)
        });
        match better {
            Some(next) => x = next,
            None => break,
        }
    }
    x
}

fn weighted(r: &Vector6<f64>) -> Vector6<f64> {
    let mut w = *r;
    for i in 3..6 {
        w[i] *= ORIENTATION_MM_PER_RAD;
    }
    w
}

/// An axis past a limit in words: "axis 3 at 54.5°{whose} beyond the IRB
/// 140's +50°", the limit passed named with its sign.
pub(super) fn limit_words(arm: &str, v: &Violation, whose: &str) -> String {
    let (axis, q, (lo, hi)) = *v;
    let limit = if q > hi { hi } else { lo };
    format!(
        "axis {} at {}°{whose} beyond the {arm}'s {}{}°",
        axis + 1,
        degrees_text(q),
        if limit >= 0.0 { "+" } else { "" },
        degrees_text(limit),
    )
}

/// The refusal of a jointtarget whose axis lies past a limit: "axis 3 at
/// 54.5° beyond the IRB 140's +50°", the limit passed named with its sign.
fn beyond_limit(arm: &str, v: &Violation, whose: &str) -> Error {
    let (axis, _, (lo, hi)) = *v;
    Error::new(ErrorKind::Unreachable, limit_words(arm, v, whose))
    .with_note(format!(
        "the {arm}'s axis {} turns from {}° to +{}°; a jointtarget's joints are what the controller moves to, so no other configuration stands in for them",
        axis + 1,
        degrees_text(lo),
        degrees_text(hi)
    ))
}

/// The jointtargets' corrections, done before the robtargets' (their
/// rows come after theirs in the report).
#[derive(Default)]
pub(super) struct JointCorrections {
    pub rows: Vec<Correction>,
    pub residuals: Vec<Residual>,
    pub left: Vec<LeftAlone>,
    pub errors: Vec<(usize, Error)>,
    /// Edits of their numbers, by file.
    pub edits: Vec<(usize, Edit)>,
}

pub(super) fn correct_joints(run: &Run, progress: &mut Progress) -> JointCorrections {
    let mut j = JointCorrections::default();
    for (index, jt) in run.program.jointtargets().iter().enumerate() {
        if jt.kind == TargetKind::Derived {
            continue;
        }
        progress.step();
        match correct_jointtarget(run, index, jt) {
            Ok(JointSolved::Corrected(c, r)) => {
                j.edits
                    .extend(c.edits.iter().map(|e| (c.file_index, e.clone())));
                j.rows.push(*c);
                j.residuals.extend(r);
            }
            Ok(JointSolved::LeftAlone(s)) => j.left.push(s),
            Err(e) => j.errors.push((usize::MAX, e)),
        }
    }
    j
}
