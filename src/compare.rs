//! Target-by-target comparison of two programs (typically an original and
//! its corrected version): matched by identifier, with the position change
//! in the target's own frame and the change of orientation.
//!
//! A job of its own beside `correct`: may import `rapid`, `robot`,
//! `resolve` and the shared `error`; never `correct` or `diagnose`.

use crate::error::Result;
use crate::rapid::{Program, TargetKind};
use crate::robot::frames::pose_from_rapid;
use serde::Serialize;

/// One target present in both programs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TargetDelta {
    pub id: String,
    /// `robtarget` or `jointtarget`.
    pub kind: &'static str,
    /// Position change (mm), in the frame the target is written in; zero
    /// for jointtargets.
    pub dx: f64,
    pub dy: f64,
    pub dz: f64,
    pub dist: f64,
    /// Orientation change (deg) for robtargets; largest joint-angle change
    /// (deg) for jointtargets.
    pub dangle: f64,
}

/// The comparison of two programs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Diff {
    pub targets: Vec<TargetDelta>,
    /// Identifiers only in the first / second program.
    pub only_in_a: Vec<String>,
    pub only_in_b: Vec<String>,
    /// Derived targets (expressions) are not compared: their values exist
    /// only at run time.
    pub derived: usize,
    pub summary: Summary,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub compared: usize,
    /// Targets whose position or orientation differs.
    pub changed: usize,
    pub max_mm: f64,
    pub rms_mm: f64,
    pub max_deg: f64,
}

/// Compare every robtarget and jointtarget of `a` with the one of the same
/// identifier in `b`.
pub fn diff(a: &Program, b: &Program) -> Result<Diff> {
    let mut targets = Vec::new();
    let mut only_in_a = Vec::new();
    let mut derived = 0;
    for ta in a.targets() {
        if ta.kind == TargetKind::Derived {
            derived += 1;
            continue;
        }
        let Some(tb) = b.target(&ta.id) else {
            only_in_a.push(ta.id.clone());
            continue;
        };
        let (Some(va), Some(vb)) = (&ta.value, &tb.value) else {
            continue;
        };
        let pa = pose_from_rapid(va.trans_values(), va.rot_values())?;
        let pb = pose_from_rapid(vb.trans_values(), vb.rot_values())?;
        let d = pb.translation.vector - pa.translation.vector;
        targets.push(TargetDelta {
            id: ta.id.clone(),
            kind: "robtarget",
            dx: d.x,
            dy: d.y,
            dz: d.z,
            dist: d.norm(),
            dangle: pa.rotation.angle_to(&pb.rotation).to_degrees(),
        });
    }
    for ja in a.jointtargets() {
        let Some(jb) = b
            .jointtargets()
            .iter()
            .find(|j| j.id.eq_ignore_ascii_case(&ja.id))
        else {
            only_in_a.push(ja.id.clone());
            continue;
        };
        let dq = ja
            .robax
            .iter()
            .zip(&jb.robax)
            .map(|(x, y)| (y.value - x.value).abs())
            .fold(0.0, f64::max);
        targets.push(TargetDelta {
            id: ja.id.clone(),
            kind: "jointtarget",
            dx: 0.0,
            dy: 0.0,
            dz: 0.0,
            dist: 0.0,
            dangle: dq,
        });
    }
    let only_in_b = b
        .targets()
        .iter()
        .filter(|t| t.kind != TargetKind::Derived && a.target(&t.id).is_none())
        .map(|t| t.id.clone())
        .chain(
            b.jointtargets()
                .iter()
                .filter(|j| {
                    !a.jointtargets()
                        .iter()
                        .any(|x| x.id.eq_ignore_ascii_case(&j.id))
                })
                .map(|j| j.id.clone()),
        )
        .collect();
    let summary = summarise(&targets);
    Ok(Diff {
        targets,
        only_in_a,
        only_in_b,
        derived,
        summary,
    })
}

fn summarise(targets: &[TargetDelta]) -> Summary {
    let robtargets: Vec<&TargetDelta> = targets.iter().filter(|t| t.kind == "robtarget").collect();
    let n = robtargets.len();
    let sum_sq: f64 = robtargets.iter().map(|t| t.dist * t.dist).sum();
    Summary {
        compared: targets.len(),
        changed: targets
            .iter()
            .filter(|t| t.dist > 0.0 || t.dangle > 0.0)
            .count(),
        max_mm: robtargets.iter().map(|t| t.dist).fold(0.0, f64::max),
        rms_mm: if n > 0 {
            (sum_sq / n as f64).sqrt()
        } else {
            0.0
        },
        max_deg: targets.iter().map(|t| t.dangle).fold(0.0, f64::max),
    }
}
