//! Target-by-target comparison of two programs (typically an original and
//! its corrected version): matched by identifier, with the position change
//! in the target's own frame and the change of orientation; and the
//! [`Gate`] a CI job puts on it ([`Diff::gate`]).
//!
//! A job of its own beside `correct`: may import `rapid`, `robot`,
//! `resolve` and the shared `error`; never `correct` or `diagnose`.

use crate::error::{Error, Result};
use crate::rapid::{Program, Target, TargetKind};
use crate::robot::frames::pose_from_rapid;
use serde::Serialize;
use std::borrow::Cow;
use std::collections::HashMap;

/// One target present in both programs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TargetDelta {
    pub id: String,
    /// `robtarget` or `jointtarget`.
    pub kind: DataType,
    /// Position change (mm), in the frame the target is written in; zero
    /// for jointtargets.
    pub dx: f64,
    pub dy: f64,
    pub dz: f64,
    pub dist: f64,
    /// Orientation change (deg) for robtargets; largest joint-angle change
    /// (deg) for jointtargets.
    pub dangle: f64,
    /// The robtarget's configuration (cf1, cf4, cf6, cfx) differs: the
    /// arm reaches the same pose through another configuration, swinging
    /// through the space between (always false for jointtargets).
    pub robconf_changed: bool,
    /// An external axis differs: one now used that was not (`9E+09`), or
    /// one moved (a track, a positioner).
    pub extax_changed: bool,
}

impl TargetDelta {
    /// What changed besides the position and orientation, in words
    /// (empty: nothing).
    pub fn also_changed(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        if self.robconf_changed {
            out.push("its robconf changed");
        }
        if self.extax_changed {
            out.push("an external axis changed");
        }
        out
    }
}

/// RAPID's value of an external axis not in use.
const UNUSED_AXIS: f64 = 9e9;

/// Two values of an external axis differ: one in use and the other not,
/// or both in use and apart by more than the six significant digits a
/// controller keeps of a `num` (so `9E9` and `9E+09`, or a value saved
/// back by the controller, are one value).
fn axis_changed(a: f64, b: f64) -> bool {
    let unused = |v: f64| v.abs() >= UNUSED_AXIS;
    match (unused(a), unused(b)) {
        (true, true) => false,
        (false, false) => !same_num(a, b),
        _ => true,
    }
}

/// One `num` as a controller keeps it: equal to six significant digits.
fn same_num(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 5e-7 * a.abs().max(b.abs())
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
    pub summary: CompareSummary,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareSummary {
    pub compared: usize,
    /// Targets whose position, orientation, robconf or external axes
    /// differ.
    pub changed: usize,
    pub max_mm: f64,
    pub rms_mm: f64,
    pub max_deg: f64,
}

/// What a compared target is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum DataType {
    #[serde(rename = "robtarget")]
    Robtarget,
    #[serde(rename = "jointtarget")]
    Jointtarget,
}

impl std::fmt::Display for DataType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            DataType::Robtarget => "robtarget",
            DataType::Jointtarget => "jointtarget",
        })
    }
}

/// Compare every robtarget and jointtarget of `a` with the one of the same
/// identifier in `b`.
pub fn diff(a: &Program, b: &Program) -> Result<Diff> {
    // Identifiers compared as RAPID compares names (without regard to
    // case), each looked up once: a scan of the other program per target
    // made two backups of 20,000 targets take half a minute.
    let a_targets: Vec<Cow<Target>> = a.targets().iter().collect();
    let b_targets: Vec<Cow<Target>> = b.targets().iter().collect();
    let (a_ids, b_ids) = (by_id(&a_targets, |t| &t.id), by_id(&b_targets, |t| &t.id));
    let a_joints = by_id(a.jointtargets(), |j| &j.id);
    let b_joints = by_id(b.jointtargets(), |j| &j.id);
    let mut targets = Vec::new();
    let mut only_in_a = Vec::new();
    let mut derived = 0;
    for ta in &a_targets {
        if ta.kind == TargetKind::Derived {
            derived += 1;
            continue;
        }
        let Some(tb) = b_ids
            .get(&ta.id.to_ascii_lowercase())
            .map(|&i| &b_targets[i])
        else {
            only_in_a.push(ta.id.clone());
            continue;
        };
        let (Some(va), Some(vb)) = (&ta.value, &tb.value) else {
            continue;
        };
        // A run-time placeholder (`[[0,0,0],[0,0,0,0],…]`) has no
        // orientation: two of them compare by position, and neither turned.
        let zero = |r: [f64; 4]| r.iter().all(|v| *v == 0.0);
        let (ra, rb) = (va.rot_values(), vb.rot_values());
        let (d, dangle) = if zero(ra) && zero(rb) {
            let (a, b) = (va.trans_values(), vb.trans_values());
            (
                nalgebra::Vector3::new(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                0.0,
            )
        } else {
            let at = |p: &Program, t: &crate::rapid::Target, e: Error| {
                e.with_note(format!("target {}", t.id))
                    .at(p.location(&t.origin))
            };
            let pa = pose_from_rapid(va.trans_values(), ra).map_err(|e| at(a, ta, e))?;
            let pb = pose_from_rapid(vb.trans_values(), rb).map_err(|e| at(b, tb, e))?;
            // The same numbers are the same orientation; acos of a
            // product of equal quaternions is not exactly zero.
            let dangle = if ra == rb {
                0.0
            } else {
                pa.rotation.angle_to(&pb.rotation).to_degrees()
            };
            (pb.translation.vector - pa.translation.vector, dangle)
        };
        targets.push(TargetDelta {
            id: ta.id.clone(),
            kind: DataType::Robtarget,
            dx: d.x,
            dy: d.y,
            dz: d.z,
            dist: d.norm(),
            dangle,
            robconf_changed: va
                .robconf_values()
                .iter()
                .zip(vb.robconf_values())
                .any(|(x, y)| !same_num(*x, y)),
            extax_changed: va
                .extax_values()
                .iter()
                .zip(vb.extax_values())
                .any(|(x, y)| axis_changed(*x, y)),
        });
    }
    for ja in a.jointtargets() {
        let Some(jb) = b_joints
            .get(&ja.id.to_ascii_lowercase())
            .map(|&i| &b.jointtargets()[i])
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
            kind: DataType::Jointtarget,
            dx: 0.0,
            dy: 0.0,
            dz: 0.0,
            dist: 0.0,
            dangle: dq,
            robconf_changed: false,
            extax_changed: ja
                .extax
                .iter()
                .zip(&jb.extax)
                .any(|(x, y)| axis_changed(x.value, y.value)),
        });
    }
    let only_in_b = b_targets
        .iter()
        .filter(|t| {
            t.kind != TargetKind::Derived && !a_ids.contains_key(&t.id.to_ascii_lowercase())
        })
        .map(|t| t.id.clone())
        .chain(
            b.jointtargets()
                .iter()
                .filter(|j| !a_joints.contains_key(&j.id.to_ascii_lowercase()))
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

/// Index of the first item of each identifier, by its identifier in
/// ASCII lower case (what `eq_ignore_ascii_case` compares).
fn by_id<T>(items: &[T], id: impl Fn(&T) -> &String) -> HashMap<String, usize> {
    let mut out = HashMap::with_capacity(items.len());
    for (i, t) in items.iter().enumerate() {
        out.entry(id(t).to_ascii_lowercase()).or_insert(i);
    }
    out
}

fn summarise(targets: &[TargetDelta]) -> CompareSummary {
    let robtargets: Vec<&TargetDelta> = targets
        .iter()
        .filter(|t| t.kind == DataType::Robtarget)
        .collect();
    let n = robtargets.len();
    let sum_sq: f64 = robtargets.iter().map(|t| t.dist * t.dist).sum();
    CompareSummary {
        compared: targets.len(),
        changed: targets
            .iter()
            .filter(|t| t.dist > 0.0 || t.dangle > 0.0 || t.robconf_changed || t.extax_changed)
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

/// Default lever (mm) of a gate's angle: a gate of `max_mm` without an
/// angle of its own lets a robtarget turn, and a jointtarget's joints
/// turn, by `max_mm / GATE_LEVER_MM` radians, the turn that moves a point
/// 100 mm from the axis by `max_mm` (0.15 mm → 0.086°, 0.5 mm → 0.29°).
///
/// Why 100 mm and not the arm's reach: a thermal correction of a
/// jointtarget keeps its flange pose and lets the wrist axes make up for
/// the longer warm arm, so its joints turn by more than the millimetres
/// suggest at full reach: on `samples/service_positions.mod` at the
/// steady state a 0.27 mm correction turns joints by up to 0.126°, an
/// effective lever of about 150 mm. A lever of 500 mm (0.1 mm ≈ 0.01°)
/// would fail every warm correction of a jointtarget; 100 mm (the wrist
/// centre to the TCP of a short tool) passes them at the gate that
/// passes their robtargets, and still fails a jointtarget taught anew or
/// moved by hand, whose joints turn by degrees. A corrected
/// robtarget keeps its orientation (it turns by micro-degrees at most),
/// so the same angle gates a robtarget's orientation change.
pub const GATE_LEVER_MM: f64 = 100.0;

/// The largest changes a [`Diff`] may show and still pass.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Gate {
    /// Position change of a robtarget, mm.
    pub max_mm: f64,
    /// Orientation change of a robtarget, and the largest joint change of
    /// a jointtarget, degrees.
    pub max_deg: f64,
}

/// The largest limit (mm) a gate or a check takes: beyond it, no
/// thermal correction is told from a target re-taught (`data/gate.toml`,
/// with its reasons).
pub fn max_limit_mm() -> f64 {
    #[derive(serde::Deserialize)]
    struct Limits {
        max_mm: f64,
    }
    // Embedded and pinned by a test: it parses.
    toml::from_str::<Limits>(include_str!("../data/gate.toml")).map_or(10.0, |l| l.max_mm)
}

/// The largest angle limit (°) a gate takes: the turn of
/// [`max_limit_mm`] at [`GATE_LEVER_MM`].
pub fn max_limit_deg() -> f64 {
    (max_limit_mm() / GATE_LEVER_MM).to_degrees()
}

impl Gate {
    /// A gate of `max_mm` (any limit not given is infinite: not gated),
    /// with `max_deg` or, without it, the angle of [`GATE_LEVER_MM`].
    /// Thresholds must be finite, not negative, and no larger than
    /// [`max_limit_mm`] and [`max_limit_deg`].
    pub fn new(max_mm: Option<f64>, max_deg: Option<f64>) -> Result<Gate> {
        for (v, unit, most) in [
            (max_mm, "mm", max_limit_mm()),
            (max_deg, "°", max_limit_deg()),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= 0.0 && *v <= most)) {
                return Err(Error::usage(format!(
                    "gate threshold {} {unit}: must be a number from 0 to {most:.2} {unit} (beyond, no thermal correction is told from a target re-taught)",
                    if v.abs() >= 1e6 { format!("{v:e}") } else { v.to_string() }
                )));
            }
        }
        Ok(Gate {
            max_mm: max_mm.unwrap_or(f64::INFINITY),
            max_deg: max_deg
                .or(max_mm.map(|mm| (mm / GATE_LEVER_MM).to_degrees()))
                .unwrap_or(f64::INFINITY),
        })
    }
}

/// Why a [`Diff`] fails a [`Gate`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum GateFailure {
    /// A target moved (mm) or turned (°) more than the gate allows (a
    /// change that is not a finite number counts as too large), or its
    /// robconf or an external axis changed, whatever the gate: a thermal
    /// correction changes neither, and either moves the robot another way.
    Moved(TargetDelta),
    /// A target of the first program is not in the second.
    OnlyInFirst(String),
    /// A target of the second program is not in the first.
    OnlyInSecond(String),
    /// The two programs have targets but none in common (or only derived
    /// ones, which are not compared): nothing was compared, so nothing is
    /// known to be within the gate. Two programs without any target (a
    /// background task's) are equal in their targets and pass.
    NothingCompared,
}

impl Diff {
    /// Every reason this comparison fails `gate`, in the order of the
    /// diff (empty: it passes). A target in one program only fails (it was
    /// added, removed or renamed: its change is unknown), and so do two
    /// programs with targets but none in common.
    pub fn gate(&self, gate: &Gate) -> Vec<GateFailure> {
        let over = |v: f64, limit: f64| v.is_nan() || v > limit;
        let mut out: Vec<GateFailure> = self
            .targets
            .iter()
            .filter(|t| {
                over(t.dist, gate.max_mm)
                    || over(t.dangle, gate.max_deg)
                    || t.robconf_changed
                    || t.extax_changed
            })
            .cloned()
            .map(GateFailure::Moved)
            .collect();
        out.extend(self.only_in_a.iter().cloned().map(GateFailure::OnlyInFirst));
        out.extend(
            self.only_in_b
                .iter()
                .cloned()
                .map(GateFailure::OnlyInSecond),
        );
        let any = !self.only_in_a.is_empty() || !self.only_in_b.is_empty() || self.derived > 0;
        if self.targets.is_empty() && any {
            out.push(GateFailure::NothingCompared);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn delta(id: &str, kind: DataType, dist: f64, dangle: f64) -> TargetDelta {
        TargetDelta {
            id: id.to_string(),
            kind,
            dx: dist,
            dy: 0.0,
            dz: 0.0,
            dist,
            dangle,
            robconf_changed: false,
            extax_changed: false,
        }
    }

    fn diff_of(targets: Vec<TargetDelta>, a: &[&str], b: &[&str]) -> Diff {
        let summary = summarise(&targets);
        Diff {
            targets,
            only_in_a: a.iter().map(|s| s.to_string()).collect(),
            only_in_b: b.iter().map(|s| s.to_string()).collect(),
            derived: 0,
            summary,
        }
    }

    // Before the gate existed `--fail-above` looked at `dist` alone: the
    // jointtarget, the one-sided targets and the empty comparison passed.
    #[test]
    fn gate_fails_turned_jointtargets_one_sided_and_disjoint() {
        let gate = Gate::new(Some(0.15), None).unwrap();
        assert!((gate.max_deg - 0.15 / 100.0 * 180.0 / std::f64::consts::PI).abs() < 1e-12);
        let d = diff_of(
            vec![
                delta("p10", DataType::Robtarget, 0.1, 0.0),
                delta("j10", DataType::Jointtarget, 0.0, 30.0),
                delta("p20", DataType::Robtarget, f64::NAN, 0.0),
            ],
            &["pOld"],
            &["pNew"],
        );
        let f = d.gate(&gate);
        assert_eq!(f.len(), 4, "{f:?}");
        assert!(matches!(&f[0], GateFailure::Moved(t) if t.id == "j10"));
        assert!(matches!(&f[1], GateFailure::Moved(t) if t.id == "p20"));
        assert_eq!(f[2], GateFailure::OnlyInFirst("pOld".into()));
        assert_eq!(f[3], GateFailure::OnlyInSecond("pNew".into()));
        let disjoint = diff_of(vec![], &["pA"], &["pB"]);
        assert_eq!(
            disjoint.gate(&gate).last(),
            Some(&GateFailure::NothingCompared)
        );
        // No target on either side (a background task's): equal, passes.
        let none = diff_of(vec![], &[], &[]);
        assert!(none.gate(&gate).is_empty());
        let ok = diff_of(vec![delta("p10", DataType::Robtarget, 0.1, 0.01)], &[], &[]);
        assert!(ok.gate(&gate).is_empty());
        // An angle alone gates angles only.
        let deg = Gate::new(None, Some(1.0)).unwrap();
        assert!(
            diff_of(vec![delta("p10", DataType::Robtarget, 5.0, 0.5)], &[], &[])
                .gate(&deg)
                .is_empty()
        );
    }

    #[test]
    fn gate_thresholds_must_be_finite_and_not_negative() {
        // The data file parses (its fallback is never taken).
        #[derive(serde::Deserialize)]
        struct Limits {
            max_mm: f64,
        }
        let l: Limits = toml::from_str(include_str!("../data/gate.toml")).unwrap();
        assert_eq!(max_limit_mm(), l.max_mm);
        assert!((max_limit_deg() - 5.729577951308232).abs() < 1e-12);
        for bad in [f64::NAN, f64::INFINITY, -1.0, 1e308, 10.001] {
            assert!(Gate::new(Some(bad), None).is_err());
            assert!(Gate::new(None, Some(bad)).is_err());
        }
        assert!(Gate::new(Some(0.0), Some(0.0)).is_ok());
        assert!(Gate::new(Some(10.0), Some(5.7)).is_ok());
        assert!(Gate::new(None, Some(5.8)).is_err());
    }
}
