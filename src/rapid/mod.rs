//! Reading RAPID programs losslessly and rewriting their targets in place.
//!
//! [`parse()`] (one file) and [`parse_files`] (a run of several files) give a
//! [`Program`]: the modules with their RECORD types, data declarations and
//! routines down to statements and expressions, and, collected from
//! wherever they are written, every robtarget ([`Program::targets`]),
//! jointtarget, tooldata, wobjdata, speeddata and zonedata value with the
//! byte span of each of its numbers in the original file. The
//! [`rewrite`] module splices new numbers into the original bytes, leaving
//! every other byte (line endings, Latin-1 text) as it was. The `Program`
//! keeps the bytes it was parsed from ([`Program::source`]).
//!
//! Owns the language: the scanner (`scan`), the grammar glue and the
//! parser split by concept (`parse`), the syntax tree and targets with
//! spans (here), one traversal ([`visit`]), RAPID's own built-in knowledge
//! ([`builtins`]: Offs, RelTool, predefined speeddata, instant
//! instructions) and the edits ([`rewrite`]). Knows no robot: it may import
//! only the shared `error` (and nalgebra for RAPID's pose arithmetic).
//!
//! # Target identifiers
//!
//! As `docs/formats.md` defines them, plus what it leaves open:
//!
//! | where the robtarget is written | kind | identifier |
//! |---|---|---|
//! | `CONST robtarget p10 := [...]` | declared | `p10` (`Module:p10` when two modules of a run declare `p10`) |
//! | element of a declared array | array element | `arr{3}`, `arr{2,4}` (1-based) |
//! | field of a declared RECORD value | record field | `w.pos`, `w{3}.pos`, `w{2}.seam.start` (the path RAPID would use to read it) |
//! | literal in an instruction or expression of a routine | inline | `main#3`: the 3rd robtarget literal of routine `main` in source order |
//! | literal assigned in a routine, `p := [...]` | assigned | `main#4`: literals are counted together, whatever statement holds them |
//! | an expression (`Offs`, `RelTool`, `CRobT`, `CalcRobT`, `MirPos`, a FUNC returning robtarget) | derived | the declared name (`CONST robtarget p20 := Offs(p10,0,0,50)`), else `main@2`: the 2nd such expression of routine `main` |
//!
//! Routine-qualified identifiers get the module too (`MainModule:main#3`)
//! when two modules of the run have a routine of that name. Jointtargets
//! follow the same rules in their own name space.
//!
//! # Encoding
//!
//! Files may be UTF-8 (with or without BOM), Latin-1 or a mix. The parser
//! sees every byte above 0x7F as one placeholder character, so offsets and
//! spans are those of the original bytes; names and strings are decoded
//! from the original bytes (UTF-8 where valid, Latin-1 otherwise).

pub mod builtins;
pub mod constants;
pub mod fastlist;
pub mod fastmove;
mod motion;
mod parse;
pub mod rewrite;
mod scan;
pub mod task;
pub mod visit;

use crate::error::{Location, Result};
use std::ops::Range;
use std::sync::Arc;

pub use motion::{motion_signature, ArgAt, Motion, MotionKind, MotionSignature};
pub use parse::{parse, parse_files, parse_skeleton, parse_skeleton_runs};

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

// ------------------------------------------------------------------ syntax

/// A whole run: one or several files, each with one or several modules.
#[derive(Debug, Clone, Default)]
pub struct Program {
    /// File names as given to the parser.
    pub files: Vec<String>,
    /// Each file's bytes as read (see [`Program::source`]): every span of
    /// the program points into these.
    pub(crate) sources: Vec<Arc<[u8]>>,
    pub modules: Vec<Module>,
    pub(crate) targets: Vec<Target>,
    pub(crate) jointtargets: Vec<JointTarget>,
    pub(crate) tools: Vec<ToolData>,
    pub(crate) wobjs: Vec<WobjData>,
    pub(crate) speeds: Vec<SpeedData>,
    pub(crate) zones: Vec<ZoneData>,
    /// What the reader could not fully account for (not errors): for
    /// example robtargets inside a RECORD type no file of the run defines.
    pub warnings: Vec<Warning>,
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

impl Program {
    /// The bytes file `file` (an index into [`Program::files`], as in
    /// [`Origin::file`]) was parsed from, kept so that spans can be read
    /// and rewritten without the caller holding them; empty for an index
    /// out of range.
    pub fn source(&self, file: usize) -> &[u8] {
        self.sources.get(file).map_or(&[], |s| s)
    }

    /// The name file `file` was given to the parser with; empty for an
    /// index out of range.
    pub fn file_name(&self, file: usize) -> &str {
        self.files.get(file).map_or("", String::as_str)
    }

    /// Every robtarget, in file and source order.
    pub fn targets(&self) -> &[Target] {
        &self.targets
    }
    pub fn jointtargets(&self) -> &[JointTarget] {
        &self.jointtargets
    }
    pub fn tools(&self) -> &[ToolData] {
        &self.tools
    }
    pub fn wobjs(&self) -> &[WobjData] {
        &self.wobjs
    }
    pub fn speeds(&self) -> &[SpeedData] {
        &self.speeds
    }
    pub fn zones(&self) -> &[ZoneData] {
        &self.zones
    }

    /// The target with this identifier (names compared without regard to
    /// case, as RAPID does).
    pub fn target(&self, id: &str) -> Option<&Target> {
        self.targets.iter().find(|t| t.id.eq_ignore_ascii_case(id))
    }

    /// The routine with this name (first module that has it).
    pub fn routine(&self, name: &str) -> Option<(&Module, &Routine)> {
        self.modules.iter().find_map(|m| {
            m.routines
                .iter()
                .find(|r| r.name.eq_ignore_ascii_case(name))
                .map(|r| (m, r))
        })
    }

    /// A value's place as an error [`Location`] (without the line text).
    pub fn location(&self, origin: &Origin) -> Location {
        Location {
            file: self.files.get(origin.file).cloned().unwrap_or_default(),
            line: origin.pos.line as usize,
            col: origin.pos.col as usize,
            line_text: Box::default(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Module {
    pub name: Arc<str>,
    pub file: usize,
    /// `SYSMODULE`, `NOVIEW`, ...
    pub attributes: Vec<String>,
    pub records: Vec<RecordType>,
    pub aliases: Vec<(String, String)>,
    pub data: Vec<DataDecl>,
    pub routines: Vec<Routine>,
    pub pos: Pos,
}

/// `RECORD name  type field; ...  ENDRECORD`
#[derive(Debug, Clone, PartialEq)]
pub struct RecordType {
    pub name: String,
    pub local: bool,
    /// (type, name) of each component.
    pub components: Vec<(String, String)>,
    pub pos: Pos,
}

/// A data declaration: `LOCAL PERS robtarget p{2,3} := ...;`
#[derive(Debug, Clone, PartialEq)]
pub struct DataDecl {
    pub scope: Option<Scope>,
    pub storage: Storage,
    pub type_name: String,
    pub name: String,
    /// Array sizes (numbers or constants).
    pub dims: Vec<Expr>,
    /// Robtarget/jointtarget literals are replaced by [`Expr::Target`] /
    /// [`Expr::JointTarget`] (the values are in the program's lists).
    pub init: Option<Expr>,
    pub pos: Pos,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoutineKind {
    Proc,
    Func,
    Trap,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// Written with `\`.
    pub optional: bool,
    /// Parameters of one `\a | b` group share this number.
    pub group: usize,
    pub access: Option<String>,
    /// `switch` for switches.
    pub type_name: String,
    pub name: String,
    /// Number of `*` dimensions (`{*}` = 1).
    pub array_dims: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Routine {
    pub kind: RoutineKind,
    pub local: bool,
    pub name: Arc<str>,
    /// FUNC return type.
    pub return_type: Option<String>,
    pub params: Vec<Param>,
    pub data: Vec<DataDecl>,
    pub body: Vec<Statement>,
    pub backward: Option<Vec<Statement>>,
    /// ERROR handler: its error numbers (empty = all) and statements.
    pub error: Option<(Vec<Expr>, Vec<Statement>)>,
    pub undo: Option<Vec<Statement>>,
    pub pos: Pos,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Statement {
    pub pos: Pos,
    pub kind: StatementKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum StatementKind {
    /// A procedure call (every instruction: MoveL, WaitTime, user PROCs).
    Call(Call),
    Assign {
        target: Expr,
        value: Expr,
    },
    If {
        /// IF and ELSEIF conditions with their statements.
        branches: Vec<(Expr, Vec<Statement>)>,
        otherwise: Option<Vec<Statement>>,
    },
    /// `IF cond statement` on one line.
    CompactIf {
        cond: Expr,
        then: Box<Statement>,
    },
    For {
        var: Arc<str>,
        from: Expr,
        to: Expr,
        step: Option<Box<Expr>>,
        body: Vec<Statement>,
    },
    While {
        cond: Expr,
        body: Vec<Statement>,
    },
    Test {
        value: Expr,
        cases: Vec<(Vec<Expr>, Vec<Statement>)>,
        default: Option<Vec<Statement>>,
    },
    Goto(String),
    Label(String),
    Return(Option<Expr>),
    Raise(Option<Expr>),
    Exit,
    Retry,
    TryNext,
    Connect {
        interrupt: Expr,
        trap: String,
    },
    /// `<SMT>` left by the pendant.
    Placeholder(String),
    /// Moves a [`Skeleton`](fastmove::Skeleton) cut out of the file, not
    /// read: its cuts `cuts`, one after another in this list, whose
    /// robtarget literals are the routine's inline targets after its first
    /// `inline`, their identifiers `{prefix}#{n}` (the routine's name, with
    /// its module where identifiers are qualified: `M1:main`). Only in a
    /// program read by [`parse_skeleton_runs`], for a walk that reads the
    /// moves from the file itself.
    CutMoves {
        cuts: Range<usize>,
        inline: usize,
        prefix: Arc<str>,
    },
}

/// A procedure call: `MoveL p10, v100, z10, tool0\WObj:=wobj1;`
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    /// The procedure (for a late-bound call `%expr%`, the expression text).
    pub name: Arc<str>,
    pub late_bound: bool,
    pub args: Vec<Arg>,
    /// Indices into [`Program::targets`] of the robtargets written in the
    /// arguments (literals and derived expressions), in source order.
    pub targets: Vec<usize>,
    /// Indices into [`Program::jointtargets`] likewise.
    pub jointtargets: Vec<usize>,
}

impl Call {
    /// Required (positional) arguments in order.
    pub fn positional(&self) -> impl Iterator<Item = &Expr> {
        self.args
            .iter()
            .filter(|a| !a.optional)
            .filter_map(|a| a.value.as_ref())
    }
    /// The optional argument `\name` (case-insensitive), if present.
    pub fn optional(&self, name: &str) -> Option<&Arg> {
        self.args.iter().find(|a| {
            a.optional
                && a.name
                    .as_deref()
                    .is_some_and(|n| n.eq_ignore_ascii_case(name))
        })
    }
}

/// One argument: `p10`, `\WObj:=wobj1`, `\Conc` (a switch: no value).
#[derive(Debug, Clone, PartialEq)]
pub struct Arg {
    pub optional: bool,
    pub name: Option<Arc<str>>,
    pub value: Option<Expr>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnaryOp {
    Neg,
    Plus,
    Not,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinaryOp {
    Add,
    Sub,
    Mul,
    Div,
    IntDiv,
    Mod,
    Lt,
    Le,
    Eq,
    Ne,
    Ge,
    Gt,
    And,
    Or,
    Xor,
}

/// An expression. Variants with more than one field are boxed so that an
/// expression is 24 bytes: a CAM program holds millions of them.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    Num(Number),
    Str(Box<str>),
    Bool(bool),
    /// `<EXP>` and other pendant placeholders.
    Placeholder(Box<str>),
    Name(Arc<str>),
    /// `p.trans.x`
    Component(Box<(Expr, Arc<str>)>),
    /// `arr{i, j}`
    Index(Box<(Expr, Vec<Expr>)>),
    Call(Box<FunctionCall>),
    Aggregate(Box<Aggregate>),
    Unary(UnaryOp, Box<Expr>),
    Binary(Box<(BinaryOp, Expr, Expr)>),
    /// A robtarget literal: index into [`Program::targets`].
    Target(usize),
    /// A jointtarget literal: index into [`Program::jointtargets`].
    JointTarget(usize),
}

/// `Offs(p10, 0, 0, 50)`
#[derive(Debug, Clone, PartialEq)]
pub struct FunctionCall {
    pub name: Arc<str>,
    pub args: Vec<Arg>,
    /// Byte range of the whole call in the original file.
    pub span: Range<usize>,
}

/// `[a, b, ...]`
#[derive(Debug, Clone, PartialEq)]
pub struct Aggregate {
    pub items: Vec<Expr>,
    pub span: Range<usize>,
}

impl Expr {
    /// The number, if this is a literal (possibly signed).
    pub fn as_num(&self) -> Option<f64> {
        match self {
            Expr::Num(n) => Some(n.value),
            _ => None,
        }
    }
    /// The name, if this is a plain variable reference.
    pub fn as_name(&self) -> Option<&str> {
        match self {
            Expr::Name(n) => Some(n),
            _ => None,
        }
    }
}
