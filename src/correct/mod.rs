//! Correcting a program for thermal drift: for each target, the
//! coordinates that make the warm robot reach what the cold program meant;
//! and the target-by-target comparison of two programs.
//!
//! For a target T (TCP pose in its work object, robconf C), the program
//! means the flange pose F = frames(T). The controller, with its nominal
//! model, turns a target into joints by inverse kinematics; the warm robot
//! at joints q is at warm(q). The corrected target T' is the one whose
//! nominal joints are the warm joints that reach F:
//!
//! ```text
//! q_warm = IK_warm(F, C)        warm(q_warm) = F
//! F'     = FK_nominal(q_warm)   what the controller must be told
//! T'     = frames⁻¹(F')         in the target's own tool and work object
//! ```
//!
//! For pure link expansion the warm arm has the nominal arm's shape, and
//! `IK_warm` is the closed form on the expanded lengths: exact. Effects that
//! change the shape (bending, joint offsets, ...) are solved by Newton from
//! that start. The robconf is never changed.

pub mod derived;

use crate::error::{Error, ErrorKind, Result};
use crate::model::warm::{self, Moment, WarmRobot};
use crate::rapid::rewrite::{
    apply_edits, number_edit, Edit, POSITION_RESOLUTION, QUATERNION_RESOLUTION,
};
use crate::rapid::{JointTarget, Number, Program, Target, TargetKind};
use crate::resolve::{frames_of, target_pose, usages, Frames};
use crate::robot::conf::{quadrant_distance, RobConf};
use crate::robot::frames::{flange_of_target, target_of_flange};
use crate::robot::Joints;
use crate::schedule::{Schedule, Visit};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use serde::Serialize;

/// Joint angles of jointtargets are written to 1e-5°: at the IRB 140's
/// reach that is under 0.0002 mm at the flange.
pub const JOINT_RESOLUTION_DEG: f64 = 0.000_01;

/// Orientation is rewritten only when it turns by more than this (rad): a
/// quaternion written with six decimals resolves about 2e-6 rad.
pub const ORIENTATION_CHANGE_RAD: f64 = 1e-6;

/// When the targets are reached.
#[derive(Debug, Clone, PartialEq)]
pub enum When {
    /// Every target at one moment.
    At(Moment),
    /// Times per target (the user's file or an estimate); `default` for
    /// targets the schedule does not list (absent: an error).
    Schedule {
        schedule: Schedule,
        /// Times of jointtargets when kept apart (an estimate keeps them in
        /// their own name space); `None`: looked up in `schedule`.
        joints: Option<Schedule>,
        default: Option<Moment>,
    },
}

/// How one run corrects.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub when: When,
    /// Which visit a target reached several times is corrected for.
    pub visit: Visit,
}

/// One corrected robtarget or jointtarget.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Correction {
    pub id: String,
    /// `robtarget` kinds (`declared`, `inline`, ...) or `jointtarget`.
    pub kind: String,
    pub file: String,
    pub line: u32,
    pub col: u32,
    /// Minute the correction is for (`None`: steady state).
    pub time_min: Option<f64>,
    pub temps_c: [f64; 6],
    /// Where the uncorrected program puts the TCP, minus where it should
    /// be, in the target's work object (mm); for jointtargets, at the
    /// flange in the base frame.
    pub drift_mm: [f64; 3],
    pub drift_norm_mm: f64,
    /// Spread of |drift| over the target's visits (min, max), mm.
    pub drift_range_mm: (f64, f64),
    /// Corrected minus original coordinates (mm; for jointtargets the
    /// largest joint change in degrees is in `dangle_deg`).
    pub correction_mm: [f64; 3],
    pub correction_norm_mm: f64,
    pub dangle_deg: f64,
    /// Original and corrected values as written to the program: x, y, z,
    /// q1..q4 (robtargets) or the six axes in degrees (jointtargets).
    pub original: Vec<f64>,
    pub corrected: Vec<f64>,
    /// Whether the written text changed.
    pub rewritten: bool,
    /// The exact corrected pose (before rounding to the written digits).
    #[serde(skip)]
    pub exact: Option<Isometry3<f64>>,
    #[serde(skip)]
    edits: Vec<Edit>,
    #[serde(skip)]
    file_index: usize,
}

/// A target the run could not or would not correct.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Skipped {
    pub id: String,
    pub file: String,
    pub line: u32,
    pub reason: String,
}

/// A derived target (`Offs(p10, ...)`): left as written; its base's
/// correction carries it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Derived {
    pub id: String,
    pub file: String,
    pub line: u32,
    pub expr: String,
    pub bases: Vec<String>,
    /// Largest correction among its bases (mm): the derived point moves
    /// with them.
    pub base_correction_mm: f64,
    /// Where the warm robot puts it after its base's correction, against
    /// where the cold program meant it (mm); `None` where only the run
    /// time knows the pose (CRobT, a FUNC, computed offsets).
    pub residual_mm: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub corrected: usize,
    /// Corrections whose written text changed.
    pub rewritten: usize,
    pub max_mm: f64,
    pub rms_mm: f64,
    pub max_drift_mm: f64,
    pub derived: usize,
    pub skipped: usize,
}

/// The outcome of correcting a program: the per-target report and the new
/// bytes of each file.
#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    pub corrections: Vec<Correction>,
    pub derived: Vec<Derived>,
    pub skipped: Vec<Skipped>,
    /// Choices the correction made that the user should know about.
    pub notes: Vec<String>,
    pub summary: Summary,
    /// New contents, one per input file (same order).
    #[serde(skip)]
    pub outputs: Vec<Vec<u8>>,
}

/// Correct every target of `program` (parsed from `sources`, one byte
/// buffer per file in the program's file order). `progress` is called with
/// (done, total) now and then.
pub fn correct(
    program: &Program,
    sources: &[&[u8]],
    warm: &WarmRobot,
    options: &Options,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Outcome> {
    correct_all(program, sources, warm, options, progress)
        .map_err(|e| with_source(e, sources, program))
}

fn correct_all(
    program: &Program,
    sources: &[&[u8]],
    warm: &WarmRobot,
    options: &Options,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Outcome> {
    let frames = Frames::of_program(program)?;
    let uses = usages(program);
    let conf_off = configuration_monitoring_off(program);
    let states = warm.states();
    if let When::Schedule {
        schedule, joints, ..
    } = &options.when
    {
        check_schedule_names(program, schedule)?;
        if let Some(j) = joints {
            check_schedule_names(program, j)?;
        }
    }
    let total = program.targets().len() + program.jointtargets().len();
    let mut corrections = Vec::new();
    let mut skipped = Vec::new();
    let mut derived_targets = Vec::new();
    let mut notes = Vec::new();
    for (index, target) in program.targets().iter().enumerate() {
        if index % 4096 == 0 {
            progress(index, total);
        }
        if target.kind == TargetKind::Derived {
            derived_targets.push(index);
            continue;
        }
        let target_uses = uses.get(&index);
        if target.kind != TargetKind::Inline && target_uses.is_none() {
            skipped.push(skip(program, target, "no move instruction of the program reaches it, so its tool and work object are unknown"));
            continue;
        }
        let (tool, wobj, _, _) = frames_of(program, &frames, index, target_uses)?;
        let Some((pose, conf)) = target_pose(program, target)? else {
            continue;
        };
        let flange = match flange_of_target(&pose, &tool, &wobj) {
            Ok(f) => f,
            Err(e) if e.kind == ErrorKind::Unsupported => {
                skipped.push(skip(program, target, &e.message));
                continue;
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
            Err(e) if conf_off && e.kind == ErrorKind::Unreachable => {
                match nearest_solution(warm, &flange, &conf) {
                    Some(q) => {
                        let nearest = warm.nominal.conf_of(&q);
                        notes.push(format!(
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
        let drift_at = |state: &warm::State| -> Result<Vector3<f64>> {
            let reached = target_of_flange(&warm.flange(&q_nominal, state), &tool, &wobj)?;
            Ok(reached.translation.vector - pose.translation.vector)
        };
        let drift = drift_at(&state)?;
        let mut range = (drift.norm(), drift.norm());
        if moments.len() > 1 {
            for m in &moments {
                let d =
                    drift_at(&states.at(*m).map_err(|e| at_target(program, target, e))?)?.norm();
                range = (range.0.min(d), range.1.max(d));
            }
        }
        let Some(value) = &target.value else { continue };
        let src = sources.get(target.origin.file).copied().unwrap_or_default();
        let mut edits = Vec::new();
        let new_trans = exact.translation.vector;
        for (num, new) in value.trans.iter().zip(new_trans.iter()) {
            push_edit(&mut edits, src, num, *new, POSITION_RESOLUTION);
        }
        let turn = pose.rotation.angle_to(&exact.rotation);
        let mut new_rot = value.rot_values();
        if turn > ORIENTATION_CHANGE_RAD {
            new_rot = quaternion_like(&exact.rotation, &value.rot_values());
            for (num, new) in value.rot.iter().zip(new_rot.iter()) {
                push_edit(&mut edits, src, num, *new, QUATERNION_RESOLUTION);
            }
        }
        let correction = new_trans - pose.translation.vector;
        let location = program.location(&target.origin);
        corrections.push(Correction {
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
        });
    }
    for (k, jt) in program.jointtargets().iter().enumerate() {
        if k % 4096 == 0 {
            progress(program.targets().len() + k, total);
        }
        if jt.kind == TargetKind::Derived {
            continue;
        }
        corrections.push(correct_jointtarget(
            program, sources, warm, &states, options, jt,
        )?);
    }
    progress(total, total);
    let calls = derived::calls_by_offset(program);
    let lookup = (&frames, &uses);
    let derived: Vec<Derived> = derived_targets
        .into_iter()
        .map(|i| {
            let target = &program.targets()[i];
            let mut report = derived_report(program, target, &corrections);
            report.residual_mm = derived::residual(
                program,
                target,
                &calls,
                &lookup,
                &corrections,
                warm,
                &states,
            );
            report
        })
        .collect();
    let outputs = write_files(program, sources, &corrections)?;
    let summary = summarise(&corrections, &derived, &skipped);
    Ok(Outcome {
        corrections,
        derived,
        skipped,
        notes,
        summary,
        outputs,
    })
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
fn correct_jointtarget(
    program: &Program,
    sources: &[&[u8]],
    warm: &WarmRobot,
    states: &warm::States,
    options: &Options,
    jt: &JointTarget,
) -> Result<Correction> {
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
    let src = sources.get(jt.origin.file).copied().unwrap_or_default();
    let mut edits = Vec::new();
    for (num, new) in jt.robax.iter().zip(new_deg.iter()) {
        push_edit(&mut edits, src, num, *new, JOINT_RESOLUTION_DEG);
    }
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

/// An edit for a number whose value changes by more than half its
/// resolution (smaller changes are below what the controller can hold, and
/// keeping the old text keeps unchanged targets byte-identical).
fn push_edit(edits: &mut Vec<Edit>, src: &[u8], num: &Number, new: f64, resolution: f64) {
    if (new - num.value).abs() <= resolution / 2.0 {
        return;
    }
    if let Some(edit) = number_edit(src, num, new, resolution) {
        edits.push(edit);
    }
}

/// The quaternion of `rot` with the sign of the written one (q and −q are
/// the same rotation; keep what the user wrote).
fn quaternion_like(rot: &UnitQuaternion<f64>, written: &[f64; 4]) -> [f64; 4] {
    let q = rot.quaternion();
    let dot = q.w * written[0] + q.i * written[1] + q.j * written[2] + q.k * written[3];
    let s = if dot < 0.0 { -1.0 } else { 1.0 };
    [s * q.w, s * q.i, s * q.j, s * q.k]
}

fn write_files(
    program: &Program,
    sources: &[&[u8]],
    corrections: &[Correction],
) -> Result<Vec<Vec<u8>>> {
    (0..sources.len())
        .map(|f| {
            let edits: Vec<Edit> = corrections
                .iter()
                .filter(|c| c.file_index == f)
                .flat_map(|c| c.edits.iter().cloned())
                .collect();
            let name = program.files.get(f).map(String::as_str).unwrap_or("");
            apply_edits(name, sources[f], &edits)
        })
        .collect()
}

fn summarise(corrections: &[Correction], derived: &[Derived], skipped: &[Skipped]) -> Summary {
    let robtargets: Vec<&Correction> = corrections
        .iter()
        .filter(|c| c.kind != "jointtarget")
        .collect();
    let n = robtargets.len();
    let sum_sq: f64 = robtargets
        .iter()
        .map(|c| c.correction_norm_mm.powi(2))
        .sum();
    Summary {
        corrected: corrections.len(),
        rewritten: corrections.iter().filter(|c| c.rewritten).count(),
        max_mm: robtargets
            .iter()
            .map(|c| c.correction_norm_mm)
            .fold(0.0, f64::max),
        rms_mm: if n > 0 {
            (sum_sq / n as f64).sqrt()
        } else {
            0.0
        },
        max_drift_mm: corrections
            .iter()
            .map(|c| c.drift_norm_mm)
            .fold(0.0, f64::max),
        derived: derived.len(),
        skipped: skipped.len(),
    }
}

fn derived_report(program: &Program, target: &Target, corrections: &[Correction]) -> Derived {
    let d = target.derived.as_deref();
    let bases: Vec<String> = d.map(|d| d.bases.clone()).unwrap_or_default();
    let base_correction_mm = bases
        .iter()
        .filter_map(|b| corrections.iter().find(|c| c.id.eq_ignore_ascii_case(b)))
        .map(|c| c.correction_norm_mm)
        .fold(0.0, f64::max);
    let location = program.location(&target.origin);
    Derived {
        id: target.id.clone(),
        file: location.file,
        line: target.origin.pos.line,
        expr: d.map(|d| d.expr.clone()).unwrap_or_default(),
        bases,
        base_correction_mm,
        residual_mm: None,
    }
}

/// The moments a target is reached.
fn moments_of(when: &When, id: &str) -> Result<Vec<Moment>> {
    moments_in(when, id, false)
}

/// The moments a jointtarget is reached.
fn joint_moments_of(when: &When, id: &str) -> Result<Vec<Moment>> {
    moments_in(when, id, true)
}

fn moments_in(when: &When, id: &str, joint: bool) -> Result<Vec<Moment>> {
    match when {
        When::At(m) => Ok(vec![*m]),
        When::Schedule {
            schedule,
            joints,
            default,
        } => match joints.as_ref().filter(|_| joint).unwrap_or(schedule).times(id) {
            Some(times) => Ok(times.iter().map(|&t| Moment::Minute(t)).collect()),
            None => default.map(|m| vec![m]).ok_or_else(|| {
                Error::input(format!(
                    "the schedule has no time for target {id} (add it, or give a default time with --default-time)"
                ))
            }),
        },
    }
}

fn pick(moments: &[Moment], visit: Visit) -> Moment {
    let minutes: Vec<f64> = moments
        .iter()
        .filter_map(|m| match m {
            Moment::Minute(t) => Some(*t),
            Moment::Steady => None,
        })
        .collect();
    if minutes.len() < moments.len() || minutes.is_empty() {
        Moment::Steady
    } else {
        Moment::Minute(visit.pick(&minutes))
    }
}

fn minute_of(m: Moment) -> Option<f64> {
    match m {
        Moment::Minute(t) => Some(t),
        Moment::Steady => None,
    }
}

/// Every identifier of the schedule must name a target of the program.
fn check_schedule_names(program: &Program, schedule: &Schedule) -> Result<()> {
    for id in schedule.targets() {
        let known = program.target(id).is_some()
            || program
                .jointtargets()
                .iter()
                .any(|j| j.id.eq_ignore_ascii_case(id));
        if !known {
            return Err(Error::input(format!(
                "the schedule names target `{id}`, which the program does not have"
            )));
        }
    }
    Ok(())
}

fn skip(program: &Program, target: &Target, reason: &str) -> Skipped {
    let location = program.location(&target.origin);
    Skipped {
        id: target.id.clone(),
        file: location.file,
        line: target.origin.pos.line,
        reason: reason.to_string(),
    }
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

/// Errors located in the program gain the source line and caret.
fn with_source(e: Error, sources: &[&[u8]], program: &Program) -> Error {
    let Some(loc) = &e.location else { return e };
    if !loc.line_text.is_empty() {
        return e;
    }
    let Some(file) = program.files.iter().position(|f| *f == loc.file) else {
        return e;
    };
    let Some(src) = sources.get(file) else {
        return e;
    };
    let line_start = src
        .split_inclusive(|&b| b == b'\n')
        .take(loc.line.saturating_sub(1))
        .map(<[u8]>::len)
        .sum::<usize>();
    let line_text = crate::error::Location::from_offset(&loc.file, src, line_start).line_text;
    let location = crate::error::Location {
        line_text,
        ..loc.clone()
    };
    e.at(location)
}
