//! What a correction run reports: each corrected target, each target left
//! as written and why, derived targets, and the summary.

use crate::rapid::rewrite::Edit;
use crate::rapid::{Program, Target, TargetKind};
use crate::resolve::{Through, Usage};
use nalgebra::Isometry3;
use serde::Serialize;
use std::collections::HashMap;

/// One corrected robtarget or jointtarget.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Correction {
    pub id: String,
    pub kind: Kind,
    pub file: String,
    pub line: u32,
    pub col: u32,
    /// Minute the correction is for (`None`: steady state).
    pub time_min: Option<f64>,
    pub temps_c: [f64; 6],
    /// The tool and work object the target is corrected for, by name
    /// (`tool0`/`wobj0` where the moves name none); `None` for
    /// jointtargets, which are joint angles in no frame.
    pub tool: Option<String>,
    pub wobj: Option<String>,
    /// The frame `drift_mm` and `correction_mm` are in.
    pub frame: Frame,
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
    /// Where the target as written puts the robot, in the world frame (the
    /// base frame where the robot stands in the cell; mm): the TCP of a
    /// robot-held tool, the flange with a stationary tool (whose TCP
    /// stands still) and for jointtargets. One frame for every work
    /// object, for pictures of where on the part the corrections are.
    #[serde(skip)]
    pub world_mm: Option<[f64; 3]>,
    /// Where the program first moves to the target (file index, byte
    /// offset; an inline target's or a jointtarget's own place): its
    /// place in program order.
    #[serde(skip)]
    pub order: (usize, usize),
    #[serde(skip)]
    pub(super) edits: Vec<Edit>,
    #[serde(skip)]
    pub(super) file_index: usize,
}

/// What a reported target is: a robtarget by where and how it is written
/// (its [`TargetKind`], or a literal written with expressions), or a
/// jointtarget.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Kind {
    #[serde(rename = "declared")]
    Declared,
    #[serde(rename = "array")]
    ArrayElement,
    #[serde(rename = "record")]
    RecordField,
    #[serde(rename = "inline")]
    Inline,
    #[serde(rename = "assigned")]
    Assigned,
    #[serde(rename = "derived")]
    Derived,
    /// A robtarget literal written with named constants or expressions.
    #[serde(rename = "expression")]
    Expression,
    #[serde(rename = "jointtarget")]
    JointTarget,
    /// A move's target argument that reaches no target of the files read
    /// (a parameter, a variable filled at run time, a name declared
    /// elsewhere): reported by the move's place.
    #[serde(rename = "argument")]
    Argument,
}

impl Kind {
    /// The kind's name in reports.
    pub fn code(self) -> &'static str {
        match self {
            Kind::Declared => "declared",
            Kind::ArrayElement => "array",
            Kind::RecordField => "record",
            Kind::Inline => "inline",
            Kind::Assigned => "assigned",
            Kind::Derived => "derived",
            Kind::Expression => "expression",
            Kind::JointTarget => "jointtarget",
            Kind::Argument => "argument",
        }
    }

    /// A robtarget's kind in reports: a literal with expressions is not
    /// derived from another target, whatever the parser files it under.
    pub fn of(target: &Target) -> Kind {
        if target.written_with_expressions() {
            return Kind::Expression;
        }
        match target.kind {
            TargetKind::Declared => Kind::Declared,
            TargetKind::ArrayElement => Kind::ArrayElement,
            TargetKind::RecordField => Kind::RecordField,
            TargetKind::Inline => Kind::Inline,
            TargetKind::Assigned => Kind::Assigned,
            TargetKind::Derived => Kind::Derived,
        }
    }

    /// Whether the target is a robtarget (not a jointtarget).
    pub fn is_robtarget(self) -> bool {
        !matches!(self, Kind::JointTarget | Kind::Argument)
    }
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.code())
    }
}

/// The frame a correction's position differences are in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Frame {
    /// The object frame of the work object the target is corrected for
    /// (its `wobj`): the frame the robtarget's own numbers are written
    /// in, so a difference reads against them directly. For `wobj0` the
    /// world frame (the robot's base frame unless the task places the
    /// robot elsewhere).
    WobjObject,
    /// The robot's base frame, at the flange (jointtargets: the arm's
    /// tool0 point moved by the new joint angles).
    BaseFlange,
}

impl Frame {
    /// The frame's name in reports, as JSON writes it.
    pub fn code(self) -> &'static str {
        match self {
            Frame::WobjObject => "wobj-object",
            Frame::BaseFlange => "base-flange",
        }
    }
}

/// Why a target was left as written, or (`SharedFrames`) why one of its
/// uses is not right warm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reason {
    /// Its value is decided at run time: assigned in a routine, written by
    /// a search, or a placeholder (`[[0,0,0],[0,0,0,0],...]`).
    Runtime,
    /// Written with named constants or expressions (`[[nX,0,300],...]`).
    Expression,
    /// No move of the program reaches it, so its tool and work object are
    /// unknown.
    Unused,
    /// In a work object moved by a mechanical unit (coordinated motion),
    /// which the model does not hold.
    Coordinated,
    /// A jointtarget without robot axes (all `9E+09`): a positioner's or
    /// an external axis's, nothing of the arm to correct.
    NoRobotAxes,
    /// A move's target argument is a parameter of its procedure that the
    /// calls do not settle (one passes a literal, a function's result, or
    /// no call passes anything the files read declare).
    Parameter,
    /// A move's target is declared in none of the files read (another
    /// module of the task).
    Undeclared,
    /// Moved to with a tooldata or wobjdata declared PERS without a value
    /// (`PERS wobjdata wConv;`): another task or module sets it at run
    /// time, so its frames are the run's.
    SetElsewhere,
    /// Moved to (for all anyone can tell) by an instruction the reader
    /// does not know: an option's (`Search_Groove`), or a procedure of a
    /// module not read. What it does with its targets is unknown.
    Instruction,
    /// Moved to by a task that the backup's SYSPAR/SYS.cfg does not mark
    /// as a motion task (`-MotionTask`): which robot its moves move, if
    /// any, the backup does not say, so nothing of it is corrected.
    NotMotionTask,
    /// Not a target left alone but one use of a corrected target: moved to
    /// with another tool or work object than the one it is corrected for
    /// (its first use's), so at this use it is not right warm.
    SharedFrames,
}

impl Reason {
    /// The reason's name in reports and where a user accepts it.
    pub fn code(self) -> &'static str {
        match self {
            Reason::Runtime => "runtime",
            Reason::Expression => "expression",
            Reason::Unused => "unused",
            Reason::Coordinated => "coordinated",
            Reason::NoRobotAxes => "no-robot-axes",
            Reason::Parameter => "parameter",
            Reason::Undeclared => "undeclared",
            Reason::SetElsewhere => "set-elsewhere",
            Reason::Instruction => "instruction",
            Reason::NotMotionTask => "not-motion-task",
            Reason::SharedFrames => "shared-frames",
        }
    }

    /// Whether a target left alone for this reason may still be wrong on
    /// the warm robot. A jointtarget without robot axes moves no joint of
    /// the arm, so nothing of it drifts; every other reason leaves a
    /// target of the arm cold.
    pub fn leaves_target_cold(self) -> bool {
        self != Reason::NoRobotAxes
    }
}

/// A target the run left as written, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LeftAlone {
    pub id: String,
    pub kind: Kind,
    pub file: String,
    pub line: u32,
    pub col: u32,
    pub reason: Reason,
    /// The reason in words, with what the program does that causes it.
    pub detail: String,
    /// Where its written numbers put the robot in the world frame (as
    /// [`Correction::world_mm`]); `None` where they do not say (no move
    /// gives its work object, a moving work object, no numbers).
    #[serde(skip)]
    pub world_mm: Option<[f64; 3]>,
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

/// A jointtarget corrected with a rule that leaves a residual (axis 4
/// kept at a wrist singularity).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Residual {
    pub id: String,
    pub file: String,
    pub line: u32,
    /// Flange position and orientation left uncorrected (mm, degrees).
    pub position_mm: f64,
    pub angle_deg: f64,
    pub rule: String,
}

/// One use of a corrected target with another tool or work object than
/// the one it is corrected for (the first use's, in program order): how
/// far from where the cold program meant it the warm robot's TCP lands
/// there, in that use's own tool and work object, at the moment the
/// target is corrected for.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SharedUse {
    pub id: String,
    pub kind: Kind,
    pub file: String,
    pub line: u32,
    pub col: u32,
    /// The pair the target is corrected for, and the use that decided it.
    pub corrected_for: FramesUse,
    /// The other use.
    pub other: FramesUse,
    /// Minute of the moment (`None`: steady state).
    pub time_min: Option<f64>,
    /// TCP position and orientation off at this use (mm, degrees); `None`
    /// where only the run time knows the pose there (why in `unknown`).
    pub residual_mm: Option<f64>,
    pub residual_deg: Option<f64>,
    pub unknown: Option<String>,
    /// Why the target was not split, where a split was asked for.
    pub not_split: Option<String>,
}

/// A move instruction and the tool and work object it names.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FramesUse {
    pub tool: String,
    pub wobj: String,
    pub instruction: String,
    /// The expression the move goes to when it reaches the target through
    /// one (`Offs(pHome,0,0,50)`).
    pub through: Option<String>,
    pub routine: String,
    pub line: u32,
}

impl FramesUse {
    pub(super) fn of(u: &Usage, program: &Program) -> FramesUse {
        let through = match u.through {
            Through::Derived(i) => program
                .targets()
                .get(i)
                .and_then(|t| t.derived.as_ref().map(|d| d.expr.clone())),
            _ => None,
        };
        FramesUse {
            tool: u.tool_name().to_string(),
            wobj: u.wobj_name().to_string(),
            instruction: u.instruction.clone(),
            through,
            routine: u.routine.clone(),
            line: u.line,
        }
    }
}

/// A target split on request: a copy declared right after it, corrected
/// for another tool and work object, which the moves with that pair now
/// name. The copy's correction is among the corrections, by its name.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SplitTarget {
    pub id: String,
    /// The copy's name.
    pub copy: String,
    pub file: String,
    /// The original's line: the copy is written on the line after its
    /// declaration.
    pub line: u32,
    pub tool: String,
    pub wobj: String,
    /// The moves that now name the copy.
    pub moves: Vec<FramesUse>,
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
    /// Targets left as written (each with its reason).
    pub left_alone: usize,
    /// Uses of targets with another tool or work object than the one they
    /// are corrected for.
    pub shared: usize,
    /// Copies written for targets split by tool and work object.
    pub split: usize,
    /// The program's move instructions by where they end.
    pub moves: MoveCounts,
}

/// The outcome of correcting a program: the per-target report and the new
/// bytes of each file.
#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    /// Every move instruction of the program and where it ends (kept
    /// where the run keeps its rows).
    pub moves: Vec<MoveFate>,
    pub corrections: Vec<Correction>,
    pub derived: Vec<Derived>,
    pub left_alone: Vec<LeftAlone>,
    /// Corrections made by a rule that leaves a residual.
    pub residuals: Vec<Residual>,
    /// Uses of targets with another tool or work object than the one they
    /// are corrected for, with what that leaves there.
    pub shared: Vec<SharedUse>,
    /// Targets split by tool and work object (only when asked for).
    pub splits: Vec<SplitTarget>,
    /// The program was already corrected on this basis by an earlier run
    /// (its marker says so): nothing was done.
    pub already_corrected: Option<String>,
    /// Choices the correction made that the user should know about.
    pub notes: Vec<String>,
    pub summary: Summary,
    /// New contents, one per input file (same order).
    #[serde(skip)]
    pub outputs: Vec<Vec<u8>>,
}

/// The report of a derived target. A name it reads that is a parameter
/// its calls settle (`passed`, by `routine/parameter`; `reads`: the plain
/// names the expression is given) moves as the targets passed.
pub(super) fn derived_report(
    program: &Program,
    target: &Target,
    corrections: &[Correction],
    passed: &HashMap<String, Vec<String>>,
    reads: &[&str],
) -> Derived {
    let d = target.derived.as_deref();
    let bases: Vec<String> = d.map(|d| d.bases.clone()).unwrap_or_default();
    let correction_of = |b: &str| {
        corrections
            .iter()
            .find(|c| c.id.eq_ignore_ascii_case(b))
            .map(|c| c.correction_norm_mm)
    };
    let routine = target.origin.routine.as_deref().unwrap_or_default();
    let through_parameters = reads.iter().flat_map(|r| {
        let key = format!("{routine}/{r}").to_ascii_lowercase();
        passed.get(&key).into_iter().flatten()
    });
    let base_correction_mm = (bases.iter().chain(through_parameters))
        .filter_map(|b| correction_of(b))
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

pub(super) fn leave(
    program: &Program,
    target: &Target,
    reason: Reason,
    detail: impl Into<String>,
) -> LeftAlone {
    let location = program.location(&target.origin);
    LeftAlone {
        id: target.id.clone(),
        kind: Kind::of(target),
        file: location.file,
        line: target.origin.pos.line,
        col: target.origin.pos.col,
        reason,
        detail: detail.into(),
        world_mm: None,
    }
}

/// What became of one move instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "fate", content = "reason", rename_all = "kebab-case")]
pub enum Fate {
    /// Its target is corrected (for this move's tool and work object, or
    /// it is one of the target's other uses, reported as such).
    Corrected,
    /// Its target is derived from corrected targets at run time (Offs,
    /// RelTool, a variable assigned from them): their corrections carry it.
    Derived,
    /// Its target is left as written, for this reason.
    LeftAlone(Reason),
    /// The run is refused over it: its error names the place, and nothing
    /// is written. A refused run has no report, so no row carries this;
    /// it completes the rule.
    Refused,
}

impl Fate {
    /// The fate's name in reports.
    pub fn code(self) -> &'static str {
        match self {
            Fate::Corrected => "corrected",
            Fate::Derived => "derived",
            Fate::LeftAlone(_) => "left-alone",
            Fate::Refused => "refused",
        }
    }

    /// The worse of two fates: a move is only as right as its worst
    /// target.
    pub(super) fn worst(self, other: Fate) -> Fate {
        let rank = |f: Fate| match f {
            Fate::Corrected => 0,
            Fate::Derived => 1,
            Fate::LeftAlone(_) => 2,
            Fate::Refused => 3,
        };
        if rank(other) > rank(self) {
            other
        } else {
            self
        }
    }
}

/// One move instruction and its fate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MoveFate {
    pub instruction: String,
    pub file: String,
    pub line: u32,
    pub col: u32,
    pub routine: String,
    /// Its target argument as written (a name, a target's identifier, a
    /// function call); the CirPoint first for circular moves.
    pub target: String,
    #[serde(flatten)]
    pub fate: Fate,
}

/// How many move instructions ended in each place.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct MoveCounts {
    pub moves: usize,
    pub corrected: usize,
    pub derived: usize,
    pub left_alone: usize,
}

impl MoveCounts {
    pub(super) fn add(&mut self, fate: Fate) {
        self.moves += 1;
        match fate {
            Fate::Corrected => self.corrected += 1,
            Fate::Derived => self.derived += 1,
            Fate::LeftAlone(_) => self.left_alone += 1,
            Fate::Refused => {}
        }
    }
}
