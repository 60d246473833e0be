//! Runs: statements and declarations the fast lane read, one after
//! another, held compactly (a few numbers each, the rest read again from
//! the file when asked for) rather than as a statement, a declaration
//! and a target each: a program of a million moves holds a million of
//! these. Each is made, on demand, into exactly what the grammar makes of
//! it, by the constructors the grammar makes it by (`build`): one target at a time ([`Program::targets`](super::Program::targets)), one move at a time
//! ([`MoveRef`]), or the whole program
//! ([`Program::expanded`](super::Program::expanded)).

use super::build::{
    declaration, declared_id, inline_id, qualify, DeclParts, HeldBy, MoveParts, Place, TargetParts,
};
use super::lane::{Cursor, Seen};
use super::place::pos_on;
use super::source::Source;
use super::syntax::{DataDecl, Expr, Statement};
use super::values::{
    Number, Origin, Pos, PoseNumbers, RobTargetValue, Scope, Storage, Target, TargetKind,
};
use std::sync::Arc;

/// No name (a move without a work object).
pub(crate) const NONE: u16 = u16::MAX;

/// Everything the lane read, held compactly.
#[derive(Debug, Clone, Default)]
pub(crate) struct Runs {
    /// Names met in the runs' moves (instructions, speeds, zones, tools,
    /// work objects and the `WObj` argument's name as written), interned.
    pub names: Vec<Arc<str>>,
    pub moves: Vec<MoveRun>,
    pub decls: Vec<DeclRun>,
    pub arrays: Vec<ArrayRun>,
}

/// Moves one after another in one list of statements of one routine.
#[derive(Debug, Clone)]
pub(crate) struct MoveRun {
    pub file: usize,
    pub module: Arc<str>,
    pub routine: Arc<str>,
    /// The prefix of its literals' identifiers: the routine's name, with
    /// its module where identifiers are qualified (`M1:main`).
    pub prefix: Arc<str>,
    /// Robtarget literals per move (1, or 2 for a circular move); 0 for
    /// moves to a target by name.
    pub literals: u8,
    /// The routine's inline literals before the run's first.
    pub first: u32,
    /// The program's number of the run's first literal.
    pub base: usize,
    pub items: Vec<MoveItem>,
}

/// One move of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MoveItem {
    /// Where the statement starts, and its line.
    pub at: u32,
    pub line: u32,
    /// Instruction, speed, zone, tool, the `WObj` argument's name as
    /// written and the work object (into [`Runs::names`]; [`NONE`]).
    pub names: [u16; 6],
    /// Each literal's `[` after `at`, or the target's name (after `at`,
    /// and its length) for a move by name.
    pub parts: [u16; 2],
}

/// Declarations of robtargets with a literal value, one after another in
/// one module, alike in scope, storage and type name as written.
#[derive(Debug, Clone)]
pub(crate) struct DeclRun {
    pub file: usize,
    pub module: Arc<str>,
    pub scope: Option<Scope>,
    pub storage: Storage,
    pub type_name: Arc<str>,
    /// The program's number of the run's first target.
    pub base: usize,
    pub items: Vec<DeclItem>,
}

/// One declaration of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct DeclItem {
    pub at: u32,
    pub line: u32,
    /// The declared name (after `at`, and its length), and the literal's
    /// `[` after `at`.
    pub name: (u16, u8),
    pub literal: u16,
    /// Its identifier is qualified with its module (its name is declared
    /// in another module of the run too).
    pub qualified: bool,
}

/// The robtarget literals of one declared array (`pScan{N} := [...]`).
#[derive(Debug, Clone)]
pub(crate) struct ArrayRun {
    pub file: usize,
    pub module: Arc<str>,
    pub routine: Option<Arc<str>>,
    /// The declared name as written, and its identifiers' prefix (the
    /// name, with its module where qualified).
    pub name: Arc<str>,
    pub prefix: Arc<str>,
    pub storage: Storage,
    /// The program's number of its first element.
    pub base: usize,
    /// Each literal's `[`, and its line.
    pub elements: Vec<u32>,
    pub lines: Vec<u32>,
    /// Where the array's value is, from its `[` through its `]`.
    pub span: std::ops::Range<usize>,
}

impl Runs {
    pub fn name(&self, id: u16) -> Option<&Arc<str>> {
        self.names.get(usize::from(id))
    }
}

/// What `read` reads at `at` of `src`, numbers with their values;
/// `lines`: inside an array, whose line ends are blanks.
fn read_at<T>(
    src: &[u8],
    at: usize,
    lines: bool,
    read: impl FnOnce(&mut Cursor) -> Option<T>,
) -> Option<T> {
    let mut seen = Seen::default();
    let mut c = Cursor {
        s: src,
        p: at,
        values: true,
        lines,
        seen: &mut seen,
    };
    read(&mut c)
}

/// The robtarget literal at `at` of `src`, read again with its values
/// (the lane read its form), into `value` (in place where it holds one
/// already); `lines`: one of an array's, whose line ends are blanks.
/// `false` where the file no longer reads so (and `value` is then not
/// to be read).
fn literal_into(src: &[u8], at: usize, lines: bool, value: &mut Option<RobTargetValue>) -> bool {
    let v = value.get_or_insert_with(|| {
        let zero = || Number::new(0.0, 0..0);
        RobTargetValue {
            trans: std::array::from_fn(|_| zero()),
            rot: std::array::from_fn(|_| zero()),
            robconf: std::array::from_fn(|_| zero()),
            extax: std::array::from_fn(|_| zero()),
        }
    });
    read_at(src, at, lines, |c| c.robtarget_into(v)).is_some()
}

/// The pose numbers of the robtarget literal at `at` of `src`, which the
/// lane read whole (its external axes not read again); `lines` as for
/// [`literal_into`].
pub(crate) fn pose_at(src: &[u8], at: usize, lines: bool) -> Option<PoseNumbers> {
    read_at(src, at, lines, |c| c.pose_numbers())
}

impl MoveRun {
    /// The move holding literal `k` of the run, and which of its literals
    /// it is.
    pub fn move_of(&self, k: usize) -> (usize, usize) {
        let n = usize::from(self.literals.max(1));
        (k / n, k % n)
    }

    /// How many targets (literals) the run holds.
    pub fn targets(&self) -> usize {
        self.items.len() * usize::from(self.literals)
    }

    /// The identifier of literal `k` into `id` (its numbers not read).
    pub fn id_into(&self, k: usize, id: &mut String) {
        inline_id(&self.prefix, self.first as usize + k + 1, id);
    }

    /// Literal `k` of the run into `t`, as the grammar makes it (its
    /// allocations reused); `false` where the file no longer reads so.
    pub fn fill(&self, runs: &Runs, src: &[u8], k: usize, t: &mut Target) -> bool {
        let (m, j) = self.move_of(k);
        let Some(item) = self.items.get(m) else {
            return false;
        };
        let at = item.at as usize + usize::from(item.parts[j]);
        if !literal_into(src, at, false, &mut t.value) {
            return false;
        }
        self.id_into(k, &mut t.id);
        let name = |i: usize| runs.name(item.names[i]);
        let held = HeldBy {
            instruction: name(0),
            tool: name(3),
            wobj: name(5),
        };
        let place = Place {
            file: self.file,
            module: &self.module,
            routine: Some(&self.routine),
        };
        TargetParts::inline(place, pos_on(src, at, item.line), held, None).fill(t);
        true
    }

    /// The pose numbers of literal `k` alone, as [`MoveRun::fill`] reads
    /// them.
    pub fn pose(&self, src: &[u8], k: usize) -> Option<PoseNumbers> {
        let (m, j) = self.move_of(k);
        let item = self.items.get(m)?;
        pose_at(src, item.at as usize + usize::from(item.parts[j]), false)
    }

    /// Move `m` of the run as the grammar makes it: the call, its
    /// literals numbered from `base`.
    pub fn statement(&self, runs: &Runs, src: &[u8], m: usize) -> Option<Statement> {
        let item = self.items.get(m)?;
        let name = |i: usize| runs.name(item.names[i]).cloned();
        let literals = usize::from(self.literals);
        let first = self.base + m * literals;
        let named = match literals {
            0 => {
                let (at, len) = named_span(item);
                let text = std::str::from_utf8(src.get(at..at + len)?).ok()?;
                Some(runs.intern_like(text))
            }
            _ => None,
        };
        let parts = MoveParts {
            pos: pos_on(src, item.at as usize, item.line),
            instruction: name(0)?,
            targets: (first..first + literals).collect(),
            named,
            speed: name(1)?,
            zone: name(2)?,
            tool: name(3)?,
            wobj: name(4).zip(name(5)),
        };
        Some(parts.statement())
    }
}

/// Where a move by name names its target.
pub(crate) fn named_span(item: &MoveItem) -> (usize, usize) {
    (
        item.at as usize + usize::from(item.parts[0]),
        usize::from(item.parts[1]),
    )
}

impl Runs {
    /// `text` as a name: the interned one where it is among the runs'
    /// names (the same `Arc`), else a new one.
    fn intern_like(&self, text: &str) -> Arc<str> {
        self.names
            .iter()
            .find(|n| &***n == text)
            .cloned()
            .unwrap_or_else(|| Arc::from(text))
    }
}

impl DeclRun {
    /// The pose numbers of target `k` alone, where [`DeclRun::fill`]
    /// makes it.
    pub fn pose(&self, src: &[u8], k: usize) -> Option<PoseNumbers> {
        let item = self.items.get(k)?;
        let pose = pose_at(src, item.at as usize + usize::from(item.literal), false)?;
        self.name_of(src, item).map(|_| pose)
    }

    /// Target `k` of the run into `t`, as the grammar makes it.
    pub fn fill(&self, src: &[u8], k: usize, t: &mut Target) -> bool {
        let Some(item) = self.items.get(k) else {
            return false;
        };
        let at = item.at as usize + usize::from(item.literal);
        if !literal_into(src, at, false, &mut t.value) {
            return false;
        }
        let Some(name) = self.name_of(src, item) else {
            return false;
        };
        self.id_of(item, name, &mut t.id);
        let place = Place {
            file: self.file,
            module: &self.module,
            routine: None,
        };
        let pos = pos_on(src, at, item.line);
        TargetParts::declared(place, pos, name, self.storage, false).fill(t);
        true
    }

    /// The identifier of target `k` into `id` (its numbers not read);
    /// `false` where the run has none.
    pub fn id_into(&self, src: &[u8], k: usize, id: &mut String) -> bool {
        let Some(item) = self.items.get(k) else {
            return false;
        };
        let Some(name) = self.name_of(src, item) else {
            return false;
        };
        self.id_of(item, name, id);
        true
    }

    /// The identifier of an item declared `name`: the name, qualified
    /// with the module where the run's identifiers are.
    fn id_of(&self, item: &DeclItem, name: &str, id: &mut String) {
        declared_id(name, &[], id);
        if item.qualified {
            qualify(&self.module, id);
        }
    }

    /// The declared name of an item.
    pub fn name_of<'s>(&self, src: &'s [u8], item: &DeclItem) -> Option<&'s str> {
        let at = item.at as usize + usize::from(item.name.0);
        std::str::from_utf8(src.get(at..at + usize::from(item.name.1))?).ok()
    }

    /// Declaration `k` as the grammar makes it, its target numbered
    /// `base + k`.
    pub fn declaration(&self, src: &[u8], k: usize) -> Option<DataDecl> {
        let item = self.items.get(k)?;
        Some(declaration(DeclParts {
            scope: self.scope,
            storage: self.storage,
            type_name: &self.type_name,
            name: self.name_of(src, item)?,
            dims: Vec::new(),
            init: Some(Expr::Target(self.base + k)),
            pos: pos_on(src, item.at as usize, item.line),
            elements: None,
        }))
    }
}

impl ArrayRun {
    /// The pose numbers of element `k` alone, as [`ArrayRun::fill`] reads
    /// them.
    pub fn pose(&self, src: &[u8], k: usize) -> Option<PoseNumbers> {
        self.lines.get(k)?;
        pose_at(src, *self.elements.get(k)? as usize, true)
    }

    /// The identifier of element `k` into `id` (its numbers not read).
    pub fn id_into(&self, k: usize, id: &mut String) {
        declared_id(&self.prefix, &[k + 1], id);
    }

    /// Element `k` into `t`, as the grammar makes it.
    pub fn fill(&self, src: &[u8], k: usize, t: &mut Target) -> bool {
        let (Some(&at), Some(&line)) = (self.elements.get(k), self.lines.get(k)) else {
            return false;
        };
        if !literal_into(src, at as usize, true, &mut t.value) {
            return false;
        }
        self.id_into(k, &mut t.id);
        let place = Place {
            file: self.file,
            module: &self.module,
            routine: self.routine.as_ref(),
        };
        let pos = pos_on(src, at as usize, line);
        TargetParts::declared(place, pos, &self.name, self.storage, true).fill(t);
        true
    }
}

/// An empty target, to be filled.
pub(crate) fn blank_target() -> Target {
    Target {
        id: String::new(),
        kind: TargetKind::Inline,
        origin: Origin {
            file: 0,
            module: Arc::from(""),
            routine: None,
            pos: Pos::default(),
        },
        name: None,
        storage: None,
        value: None,
        instruction: None,
        tool: None,
        wobj: None,
        derived: None,
    }
}

/// One move of a run, as the walks of the program see it.
#[derive(Clone, Copy)]
pub struct MoveRef<'p> {
    runs: &'p Runs,
    sources: &'p [Source],
    run: &'p MoveRun,
    m: usize,
}

impl<'p> MoveRef<'p> {
    pub(crate) fn new(runs: &'p Runs, sources: &'p [Source], run: &'p MoveRun, m: usize) -> Self {
        MoveRef {
            runs,
            sources,
            run,
            m,
        }
    }

    fn item(&self) -> &'p MoveItem {
        &self.run.items[self.m]
    }

    fn name(&self, i: usize) -> Option<&'p Arc<str>> {
        self.runs.name(self.item().names[i])
    }

    fn src(&self) -> &'p [u8] {
        self.sources.get(self.run.file).map_or(&[], Source::bytes)
    }

    pub fn instruction(&self) -> &'p Arc<str> {
        self.name(0).expect("a run's move has its instruction")
    }
    pub fn speed(&self) -> Option<&'p Arc<str>> {
        self.name(1)
    }
    pub fn zone(&self) -> Option<&'p Arc<str>> {
        self.name(2)
    }
    pub fn tool(&self) -> Option<&'p Arc<str>> {
        self.name(3)
    }
    pub fn wobj(&self) -> Option<&'p Arc<str>> {
        self.name(5)
    }
    /// The program's numbers of its robtarget literals (CirPoint before
    /// ToPoint); empty for a move to a target by name.
    pub fn targets(&self) -> std::ops::Range<usize> {
        let n = usize::from(self.run.literals);
        let first = self.run.base + self.m * n;
        first..first + n
    }
    /// The target's name, for a move to one by name.
    pub fn named(&self) -> Option<&'p str> {
        if self.run.literals > 0 {
            return None;
        }
        let (at, len) = named_span(self.item());
        std::str::from_utf8(self.src().get(at..at + len)?).ok()
    }
    pub fn file(&self) -> usize {
        self.run.file
    }
    pub fn module(&self) -> &'p Arc<str> {
        &self.run.module
    }
    pub fn routine(&self) -> &'p Arc<str> {
        &self.run.routine
    }
    /// Where the statement starts.
    pub fn offset(&self) -> usize {
        self.item().at as usize
    }
    pub fn line(&self) -> u32 {
        self.item().line
    }
    /// Where the statement starts, with its line and column.
    pub fn pos(&self) -> Pos {
        pos_on(self.src(), self.offset(), self.line())
    }
    /// The statement as the grammar makes it.
    pub fn statement(&self) -> Option<Statement> {
        self.run.statement(self.runs, self.src(), self.m)
    }
}
