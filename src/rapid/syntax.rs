//! The syntax tree of a program: modules, declarations, routines,
//! statements and expressions, as the reader builds them.

use super::values::{Number, Pos, Scope, Storage};
use std::ops::Range;
use std::sync::Arc;

#[derive(Debug, Clone, PartialEq)]
pub struct Module {
    pub name: Arc<str>,
    pub file: usize,
    /// `SYSMODULE`, `NOVIEW`, ...
    pub attributes: Vec<String>,
    pub records: Vec<RecordType>,
    pub aliases: Vec<(String, String)>,
    pub data: Vec<DataDecl>,
    /// Declarations of robtargets with literal values, one after another,
    /// that the fast lane read, held compactly: the program's declaration
    /// runs of these numbers, each a [`DataDecl`] of the grammar's (in
    /// [`Program::expanded`]).
    pub decl_runs: Vec<usize>,
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
    /// Moves one after another in this list that the fast lane read,
    /// held compactly: the program's move run of this number (see
    /// [`Program::moves`]). Each is the call the grammar makes of it
    /// ([`MoveRef::statement`](super::MoveRef::statement)).
    Moves(usize),
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
        positional(&self.args)
    }
    /// The optional argument `\name` (case-insensitive), if present.
    pub fn optional(&self, name: &str) -> Option<&Arg> {
        optional(&self.args, name)
    }
}

impl FunctionCall {
    /// Required (positional) arguments in order.
    pub fn positional(&self) -> impl Iterator<Item = &Expr> {
        positional(&self.args)
    }
    /// The optional argument `\name` (case-insensitive), if present.
    pub fn optional(&self, name: &str) -> Option<&Arg> {
        optional(&self.args, name)
    }
}

fn positional(args: &[Arg]) -> impl Iterator<Item = &Expr> {
    args.iter()
        .filter(|a| !a.optional)
        .filter_map(|a| a.value.as_ref())
}

fn optional<'a>(args: &'a [Arg], name: &str) -> Option<&'a Arg> {
    args.iter().find(|a| {
        a.optional
            && a.name
                .as_deref()
                .is_some_and(|n| n.eq_ignore_ascii_case(name))
    })
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
    /// The value of an array of robtarget literals the fast lane read,
    /// held compactly: the program's array run of this number. The
    /// grammar makes it an aggregate of [`Expr::Target`]s.
    Elements(usize),
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
