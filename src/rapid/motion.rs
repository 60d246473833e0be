//! The motion instructions of RAPID (and of the Arc, Spot, Paint, Cap and
//! Trigg options): which positional argument is the target, the speed, the
//! zone and the tool. The reader uses it to check target literals and to
//! name each inline target's tool; a schedule estimator uses
//! [`Call::motion`] to time a move.

use super::{Call, Expr};

/// Where a positional argument sits: counted from the first, or from the
/// last (process instructions have a varying number of process data
/// arguments between speed and tool).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArgAt {
    Index(usize),
    /// 1 = the last positional argument.
    FromEnd(usize),
}

impl ArgAt {
    fn resolve(self, count: usize) -> Option<usize> {
        match self {
            ArgAt::Index(i) => (i < count).then_some(i),
            ArgAt::FromEnd(k) => count.checked_sub(k),
        }
    }
}

/// How the robot moves to the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// TCP on a straight line (MoveL, ArcL, SearchL, ...).
    Linear,
    /// Joint interpolation to a robtarget (MoveJ, SearchJ, ...).
    Joint,
    /// Circle through a CirPoint (MoveC, ArcC, ...).
    Circular,
    /// Joint interpolation to a jointtarget (MoveAbsJ).
    AbsJoint,
    /// External axes only (MoveExtJ).
    ExtJoint,
}

/// Positional arguments of a motion instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MotionSignature {
    pub kind: MotionKind,
    /// Positions of robtarget arguments (CirPoint before ToPoint).
    pub robtargets: &'static [usize],
    /// Positions of jointtarget arguments.
    pub jointtargets: &'static [usize],
    pub speed: Option<ArgAt>,
    /// `None` where the instruction always stops (SearchL, SpotL).
    pub zone: Option<ArgAt>,
    pub tool: Option<ArgAt>,
}

/// The signature of a motion instruction (name case-insensitive), or
/// `None` for anything else.
pub fn motion_signature(name: &str) -> Option<MotionSignature> {
    use ArgAt::{FromEnd, Index};
    use MotionKind::*;
    // Upper-cased on the stack: the fast move recogniser asks this of a
    // million moves, twice. No motion instruction's name is longer.
    let mut upper = [0u8; 16];
    let n = upper.get_mut(..name.len()).map(|u| {
        u.copy_from_slice(name.as_bytes());
        u.make_ascii_uppercase();
        &*u
    })?;
    let n = std::str::from_utf8(n).ok()?;
    let sig = |kind, robtargets, jointtargets, speed, zone, tool| {
        Some(MotionSignature {
            kind,
            robtargets,
            jointtargets,
            speed: Some(speed),
            zone,
            tool,
        })
    };
    match n {
        "MOVEL" | "MOVELDO" | "MOVELSYNC" | "MOVELAO" | "MOVELGO" | "PAINTL" | "TRIGGLIOS" => {
            sig(Linear, &[0], &[], Index(1), Some(Index(2)), Some(Index(3)))
        }
        "MOVEJ" | "MOVEJDO" | "MOVEJSYNC" | "MOVEJAO" | "MOVEJGO" | "TRIGGJIOS" => {
            sig(Joint, &[0], &[], Index(1), Some(Index(2)), Some(Index(3)))
        }
        // TriggL ToPoint, Speed, Trigg_1, Zone, Tool
        "TRIGGL" => sig(Linear, &[0], &[], Index(1), Some(Index(3)), Some(Index(4))),
        "TRIGGJ" => sig(Joint, &[0], &[], Index(1), Some(Index(3)), Some(Index(4))),
        "MOVEC" | "MOVECDO" | "MOVECSYNC" | "MOVECAO" | "MOVECGO" | "PAINTC" => sig(
            Circular,
            &[0, 1],
            &[],
            Index(2),
            Some(Index(3)),
            Some(Index(4)),
        ),
        "TRIGGC" => sig(
            Circular,
            &[0, 1],
            &[],
            Index(2),
            Some(Index(4)),
            Some(Index(5)),
        ),
        "MOVEABSJ" | "MOVEABSJDO" | "MOVEABSJSYNC" | "ARCMOVEABSJ" => sig(
            AbsJoint,
            &[],
            &[0],
            Index(1),
            Some(Index(2)),
            Some(Index(3)),
        ),
        "MOVEEXTJ" | "ARCMOVEEXTJ" => sig(ExtJoint, &[], &[0], Index(1), Some(Index(2)), None),
        // SearchL Signal, SearchPoint (the result), ToPoint, Speed, Tool
        "SEARCHL" => sig(Linear, &[2], &[], Index(3), None, Some(Index(4))),
        "SEARCHJ" => sig(Joint, &[2], &[], Index(3), None, Some(Index(4))),
        "SEARCHC" => sig(Circular, &[2, 3], &[], Index(4), None, Some(Index(5))),
        // SmarTac's Search_1D Result, StartPoint, SearchPoint, Speed, Tool:
        // to the start, then searching toward the search point.
        "SEARCH_1D" => sig(Linear, &[1, 2], &[], Index(3), None, Some(Index(4))),
        // Process instructions: ToPoint, Speed, process data..., Zone, Tool
        "ARCL" | "ARCL1" | "ARCL2" | "ARCLSTART" | "ARCLEND" | "CAPL" | "ARCCALCL"
        | "ARCCALCLSTART" | "ARCCALCLEND" | "ARCADAPTL" | "ARCADAPTLSTART" | "ARCADAPTLEND"
        | "DISPL" => sig(
            Linear,
            &[0],
            &[],
            Index(1),
            Some(FromEnd(2)),
            Some(FromEnd(1)),
        ),
        "ARCC" | "ARCC1" | "ARCC2" | "ARCCSTART" | "ARCCEND" | "CAPC" | "ARCCALCC"
        | "ARCCALCCSTART" | "ARCCALCCEND" | "ARCADAPTC" | "ARCADAPTCSTART" | "ARCADAPTCEND"
        | "DISPC" => sig(
            Circular,
            &[0, 1],
            &[],
            Index(2),
            Some(FromEnd(2)),
            Some(FromEnd(1)),
        ),
        // ContactL ToPoint, Speed, Tool (the Contact option): a stop.
        "CONTACTL" => sig(Linear, &[0], &[], Index(1), None, Some(Index(2))),
        // SpotL ToPoint, Speed, Spot, Tool: always a stop point.
        "SPOTL" => sig(Linear, &[0], &[], Index(1), None, Some(FromEnd(1))),
        "SPOTJ" => sig(Joint, &[0], &[], Index(1), None, Some(FromEnd(1))),
        _ => None,
    }
}

/// The parts of a motion instruction a schedule estimator needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion<'a> {
    pub signature: MotionSignature,
    /// ToPoint (robtarget) or ToJointPos (jointtarget): a name, an
    /// [`Expr::Target`]/[`Expr::JointTarget`] literal, or an expression
    /// (Offs, ...).
    pub to: Option<&'a Expr>,
    /// CirPoint of circular moves.
    pub via: Option<&'a Expr>,
    pub speed: Option<&'a Expr>,
    pub zone: Option<&'a Expr>,
    pub tool: Option<&'a Expr>,
    /// `\WObj:=`
    pub wobj: Option<&'a Expr>,
    /// `\V:=` (TCP speed, mm/s) and `\T:=` (time, s) override the speed.
    pub v: Option<&'a Expr>,
    pub t: Option<&'a Expr>,
    /// `\Z:=` (zone size, mm) overrides the zone.
    pub z: Option<&'a Expr>,
    /// `\Conc`: the next statements run while the robot moves.
    pub conc: bool,
}

impl Call {
    /// The motion parts of this call, if it is a motion instruction.
    pub fn motion(&self) -> Option<Motion<'_>> {
        let sig = motion_signature(&self.name)?;
        // An argument is looked up by its place among the call's few, not
        // gathered into a list first: the walk asks a million moves for
        // their motion.
        let n = self.positional().count();
        let arg = |i: usize| self.positional().nth(i);
        let at = |a: Option<ArgAt>| a.and_then(|a| a.resolve(n)).and_then(arg);
        let targets: &[usize] = if sig.robtargets.is_empty() {
            sig.jointtargets
        } else {
            sig.robtargets
        };
        let to = targets.last().and_then(|&i| arg(i));
        let via = (targets.len() > 1)
            .then(|| targets.first().and_then(|&i| arg(i)))
            .flatten();
        let opt = |n: &str| self.optional(n).and_then(|a| a.value.as_ref());
        Some(Motion {
            signature: sig,
            to,
            via,
            speed: at(sig.speed),
            zone: at(sig.zone),
            tool: at(sig.tool),
            wobj: opt("WObj"),
            v: opt("V"),
            t: opt("T"),
            z: opt("Z"),
            conc: self.optional("Conc").is_some(),
        })
    }
}
