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
    /// The declarations held one by one; every declaration of the
    /// module, those the reader holds compactly too:
    /// [`Program::module_data`](super::Program::module_data).
    pub data: Vec<DataDecl>,
    /// Declarations of robtargets with literal values, one after another,
    /// that the fast lane read, held compactly: the program's declaration
    /// runs of these numbers, each a [`DataDecl`] of the grammar's (in
    /// [`Program::expanded`](super::Program::expanded)).
    pub(super) decl_runs: Vec<usize>,
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
    /// `None` too for an array of robtarget literals the reader holds
    /// compactly ([`DataDecl::has_value`] tells; its value, as the grammar
    /// makes it: [`Program::value_of`](super::Program::value_of)).
    pub init: Option<Expr>,
    pub pos: Pos,
    /// The array run of the fast lane holding the value, if one does.
    pub(super) elements: Option<usize>,
}

impl DataDecl {
    /// Whether the declaration gives a value (`:= ...`).
    pub fn has_value(&self) -> bool {
        self.init.is_some() || self.elements.is_some()
    }
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
    pub body: Block,
    pub backward: Option<Block>,
    /// ERROR handler: its error numbers (empty = all) and statements.
    pub error: Option<(Vec<Expr>, Block)>,
    pub undo: Option<Block>,
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
        branches: Vec<(Expr, Block)>,
        otherwise: Option<Block>,
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
        body: Block,
    },
    While {
        cond: Expr,
        body: Block,
    },
    Test {
        value: Expr,
        cases: Vec<(Vec<Expr>, Block)>,
        default: Option<Block>,
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
}

/// A list of statements: a routine's body or handler, a branch of a
/// block. It holds the statements the grammar read one by one (what it
/// dereferences to, in order) and, between them, the runs of moves the
/// fast lane read, held compactly and private to the reader. Every
/// statement of the list, whatever its storage:
/// [`Program::statements`](super::Program::statements) (one at a time)
/// or [`Program::items`](super::Program::items) (a run's moves at once).
#[derive(Clone, Default, PartialEq)]
pub struct Block {
    pub(super) stmts: Vec<Statement>,
    /// The runs of moves held between the statements: (how many
    /// statements come before it, the program's move run of that number),
    /// in order.
    pub(super) runs: Vec<(usize, usize)>,
}

impl Block {
    /// Whether the list holds no statement at all, in runs neither.
    pub fn is_empty(&self) -> bool {
        self.stmts.is_empty() && self.runs.is_empty()
    }
}

impl From<Vec<Statement>> for Block {
    fn from(stmts: Vec<Statement>) -> Block {
        Block {
            stmts,
            runs: Vec::new(),
        }
    }
}

impl std::ops::Deref for Block {
    type Target = [Statement];
    fn deref(&self) -> &[Statement] {
        &self.stmts
    }
}

impl std::ops::DerefMut for Block {
    fn deref_mut(&mut self) -> &mut [Statement] {
        &mut self.stmts
    }
}

impl<'a> IntoIterator for &'a Block {
    type Item = &'a Statement;
    type IntoIter = std::slice::Iter<'a, Statement>;
    fn into_iter(self) -> Self::IntoIter {
        self.stmts.iter()
    }
}

impl std::fmt::Debug for Block {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.runs.is_empty() {
            true => f.debug_list().entries(&self.stmts).finish(),
            false => f
                .debug_struct("Block")
                .field("stmts", &self.stmts)
                .field("runs", &self.runs)
                .finish(),
        }
    }
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
