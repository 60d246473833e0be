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
//! when two modules of the run have a routine of that name. A routine's
//! own declaration of a name declared elsewhere too shadows it within the
//! routine, and its identifier carries the routine (`r1/pA`): a move in
//! `r1` reads it, a move elsewhere the other. Jointtargets
//! follow the same rules in their own name space.
//!
//! # Encoding
//!
//! Files may be UTF-8 (with or without BOM), Latin-1 or a mix. The parser
//! sees every byte above 0x7F as one placeholder character, so offsets and
//! spans are those of the original bytes; names and strings are decoded
//! from the original bytes (UTF-8 where valid, Latin-1 otherwise).
mod bounds;
mod build;
pub mod builtins;
pub mod constants;
mod expand;
mod lane;
mod motion;
mod nocase;
mod num_compare;
pub(crate) use nocase::NoCase;
pub(crate) use num_compare::compare;
pub mod numprint;
mod parse;
mod place;
mod program;
mod reserved;
pub mod rewrite;
mod runs;
mod scan;
mod source;
mod syntax;
pub mod targets;
pub mod task;
mod values;
mod view;
pub mod visit;

pub use lane::{Decline, Declined, LaneTally, Part, StoppedAt};
pub use motion::{motion_signature, ArgAt, Motion, MotionKind, MotionSignature};
pub use parse::{parse, parse_files, parse_read, parse_sources, Reading};
pub use program::Program;
/// The grammar's reserved words, which the list of RAPID's own names
/// (`correct::runtime::names`) is held equal to.
#[cfg_attr(not(test), allow(unused_imports))]
pub(crate) use reserved::RESERVED;
pub use runs::MoveRef;
pub use source::Source;
pub use syntax::{
    Aggregate, Arg, BinaryOp, Block, Call, DataDecl, Expr, FunctionCall, Module, Param, RecordType,
    Routine, RoutineKind, Statement, StatementKind, UnaryOp,
};
pub use targets::Targets;
pub use values::{
    Derivation, Flag, JointTarget, Number, Origin, Pos, PoseNumbers, RobTargetValue, Scope,
    SpeedData, Storage, Target, TargetKind, ToolData, Warning, WobjData, ZoneData,
};
pub use view::{DeclBatch, Items, Listed, MoveBatch, StatementRef};
