//! What a program's values are: numbers with where their text is, places
//! in a file, and the robot data the reader collects from wherever they
//! are written (robtargets, jointtargets, tooldata, wobjdata, speeddata,
//! zonedata), each with its place.

use crate::error::Location;
use std::ops::Range;
use std::sync::Arc;

/// One number literal of the source: its value and where its text is.
/// The span includes a sign written directly before the digits. (Offsets
/// are stored as u32: files are limited to 4 GiB, and a CAM program of
/// millions of targets stays small in memory.)
#[derive(Debug, Clone, PartialEq)]
pub struct Number {
    pub value: f64,
    start: u32,
    end: u32,
}

impl Number {
    pub(crate) fn new(value: f64, span: Range<usize>) -> Number {
        Number {
            value,
            start: span.start as u32,
            end: span.end as u32,
        }
    }
    /// Byte range of the literal in the original file.
    pub fn span(&self) -> Range<usize> {
        self.start as usize..self.end as usize
    }
    /// The literal as written in `src` (the bytes the program was parsed
    /// from).
    pub fn text<'a>(&self, src: &'a [u8]) -> &'a str {
        src.get(self.span())
            .and_then(|b| std::str::from_utf8(b).ok())
            .unwrap_or("")
    }
}

/// A place in a source file: byte offset, 1-based line and column
/// (characters, as [`Location`] counts them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Pos {
    pub offset: usize,
    pub line: u32,
    pub col: u32,
}

/// The numbers of a robtarget literal `[[x,y,z],[q1,q2,q3,q4],[cf1,cf4,cf6,cfx],[eax_a..eax_f]]`.
#[derive(Debug, Clone, PartialEq)]
pub struct RobTargetValue {
    pub trans: [Number; 3],
    pub rot: [Number; 4],
    pub robconf: [Number; 4],
    pub extax: [Number; 6],
}

impl RobTargetValue {
    /// All 17 numbers in source order.
    pub fn numbers(&self) -> impl Iterator<Item = &Number> {
        self.trans
            .iter()
            .chain(&self.rot)
            .chain(&self.robconf)
            .chain(&self.extax)
    }
    pub fn trans_values(&self) -> [f64; 3] {
        self.trans.each_ref().map(|n| n.value)
    }
    pub fn rot_values(&self) -> [f64; 4] {
        self.rot.each_ref().map(|n| n.value)
    }
    pub fn robconf_values(&self) -> [f64; 4] {
        self.robconf.each_ref().map(|n| n.value)
    }
    pub fn extax_values(&self) -> [f64; 6] {
        self.extax.each_ref().map(|n| n.value)
    }
}

/// The numbers a robtarget's pose is made of: its position, orientation
/// and robconf, without its external axes (which no pose needs: a read
/// of a million poses read six numbers of seventeen for nothing).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseNumbers {
    pub trans: [f64; 3],
    pub rot: [f64; 4],
    pub robconf: [f64; 4],
}

impl From<&RobTargetValue> for PoseNumbers {
    fn from(v: &RobTargetValue) -> PoseNumbers {
        PoseNumbers {
            trans: v.trans_values(),
            rot: v.rot_values(),
            robconf: v.robconf_values(),
        }
    }
}

/// Where and how a target is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetKind {
    /// `CONST robtarget p10 := [...]` (module or routine data).
    Declared,
    /// An element of a declared array.
    ArrayElement,
    /// A robtarget field of a declared RECORD value.
    RecordField,
    /// A literal in an instruction or expression of a routine.
    Inline,
    /// A literal assigned in a routine: `p10 := [...]`.
    Assigned,
    /// An expression computing a robtarget (Offs, RelTool, CRobT, FUNC call).
    Derived,
}

impl TargetKind {
    pub fn as_str(self) -> &'static str {
        match self {
            TargetKind::Declared => "declared",
            TargetKind::ArrayElement => "array",
            TargetKind::RecordField => "record",
            TargetKind::Inline => "inline",
            TargetKind::Assigned => "assigned",
            TargetKind::Derived => "derived",
        }
    }
}

/// Storage class of a declaration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    Const,
    Pers,
    Var,
}

/// `LOCAL` or `TASK` before a declaration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    Local,
    Task,
}

/// What a derived target is computed from.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivation {
    /// The expression as written.
    pub expr: String,
    /// The function called (`Offs`, `RelTool`, `CRobT`, a FUNC's name).
    pub function: String,
    /// Identifiers of the robtargets it reads (declared names, `arr{i}`
    /// when the index is a literal).
    pub bases: Vec<String>,
}

/// Where a value sits in the program.
#[derive(Debug, Clone, PartialEq)]
pub struct Origin {
    /// Index into [`Program::files`].
    pub file: usize,
    pub module: Arc<str>,
    /// The routine, for routine data and everything inline.
    pub routine: Option<Arc<str>>,
    pub pos: Pos,
}

/// One robtarget of the program.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    /// Identifier as in the module docs (unique in the run).
    pub id: String,
    pub kind: TargetKind,
    pub origin: Origin,
    /// The declared (or assigned) variable: `p10` for `p10`, `arr{3}` and
    /// `p10 := ...`; the record variable for record fields.
    pub name: Option<String>,
    pub storage: Option<Storage>,
    /// The numbers, for literals; `None` for derived targets.
    pub value: Option<RobTargetValue>,
    /// The instruction holding an inline or derived target (`MoveL`).
    pub instruction: Option<Arc<str>>,
    /// Tool named by that instruction (`\Tool:=` or its tool argument).
    pub tool: Option<Arc<str>>,
    /// Work object named by that instruction (`\WObj:=`).
    pub wobj: Option<Arc<str>>,
    pub derived: Option<Box<Derivation>>,
}

impl Target {
    /// A robtarget literal whose parts are written with named constants
    /// or expressions (`[[nX,0,300],...]`): a value, not a derivation from
    /// another target, but not numbers either.
    pub fn written_with_expressions(&self) -> bool {
        self.kind == TargetKind::Derived
            && self
                .derived
                .as_ref()
                .is_some_and(|d| d.function.is_empty() && d.expr.trim_start().starts_with('['))
    }
}

/// One jointtarget: `[[rax_1..rax_6],[eax_a..eax_f]]`, degrees.
#[derive(Debug, Clone, PartialEq)]
pub struct JointTarget {
    pub id: String,
    pub kind: TargetKind,
    pub origin: Origin,
    pub name: Option<String>,
    pub storage: Option<Storage>,
    pub robax: [Number; 6],
    pub extax: [Number; 6],
    pub instruction: Option<Arc<str>>,
    pub tool: Option<Arc<str>>,
    pub wobj: Option<Arc<str>>,
}

/// A boolean, string or other non-number component as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Flag {
    pub value: bool,
    pub span: Range<usize>,
}

/// `tooldata`: `[robhold, [[x,y,z],[q1..q4]], [mass, [cog], [aom], ix, iy, iz]]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolData {
    pub name: String,
    pub origin: Origin,
    pub storage: Storage,
    pub robhold: Flag,
    pub tframe_trans: [Number; 3],
    pub tframe_rot: [Number; 4],
    pub mass: Number,
    pub cog: [Number; 3],
    pub aom: [Number; 4],
    pub inertia: [Number; 3],
}

/// `wobjdata`: `[robhold, ufprog, "ufmec", [[uframe]], [[oframe]]]`.
#[derive(Debug, Clone, PartialEq)]
pub struct WobjData {
    pub name: String,
    pub origin: Origin,
    pub storage: Storage,
    pub robhold: Flag,
    pub ufprog: Flag,
    pub ufmec: String,
    pub uframe_trans: [Number; 3],
    pub uframe_rot: [Number; 4],
    pub oframe_trans: [Number; 3],
    pub oframe_rot: [Number; 4],
}

/// `speeddata`: `[v_tcp, v_ori, v_leax, v_reax]` (mm/s, deg/s).
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedData {
    pub name: String,
    pub origin: Origin,
    pub storage: Storage,
    pub v_tcp: Number,
    pub v_ori: Number,
    pub v_leax: Number,
    pub v_reax: Number,
}

/// `zonedata`: `[finep, pzone_tcp, pzone_ori, pzone_eax, zone_ori, zone_leax, zone_reax]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ZoneData {
    pub name: String,
    pub origin: Origin,
    pub storage: Storage,
    pub finep: Flag,
    /// pzone_tcp, pzone_ori, pzone_eax, zone_ori, zone_leax, zone_reax.
    pub values: [Number; 6],
}

/// A located remark about the input that is not an error.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    pub location: Location,
    pub message: String,
}

impl std::fmt::Display for Warning {
    /// `file:line:col: warning: message`
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let l = &self.location;
        write!(
            f,
            "{}:{}:{}: warning: {}",
            l.file, l.line, l.col, self.message
        )
    }
}
