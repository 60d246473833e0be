//! The one builder of what both readers make: the grammar (pest, one
//! statement and declaration at a time) and the fast lane (its compact
//! runs, expanded on demand) describe a move, a declaration or a target
//! by its parts, and these functions alone decide what it is: its names,
//! arguments, position, scope, storage, kind and identifier. As
//! rust-analyzer's parser feeds one tree builder, the two readers agree
//! by construction, not by a test comparing them.
//!
//! What a reader still does on its own is finding the parts: pest pairs
//! for the grammar, byte ranges for the lane (and the lane holds them in
//! a few numbers, read again when asked for: its speed).

use super::motion::{motion_signature, ArgAt, MotionKind};
use super::syntax::{Aggregate, Arg, Call, DataDecl, Expr, Statement, StatementKind};
use super::values::{
    JointTarget, Number, Origin, Pos, RobTargetValue, Scope, Storage, Target, TargetKind,
};
use std::sync::Arc;

/// The scope keywords, in the order the lane matches them.
pub(crate) const SCOPE_WORDS: [&str; 2] = ["LOCAL", "TASK"];
/// The storage keywords, in the order the lane matches them.
pub(crate) const STORAGE_WORDS: [&str; 3] = ["CONST", "PERS", "VAR"];

/// The scope of keyword number `k` of [`SCOPE_WORDS`].
pub(crate) fn scope(k: usize) -> Scope {
    match k {
        0 => Scope::Local,
        _ => Scope::Task,
    }
}

/// The storage of keyword number `k` of [`STORAGE_WORDS`].
pub(crate) fn storage(k: usize) -> Storage {
    match k {
        0 => Storage::Const,
        1 => Storage::Pers,
        _ => Storage::Var,
    }
}

/// The number of `word` among `words` (case-insensitive): where the
/// grammar matched a keyword, which one.
pub(crate) fn keyword_number(words: &[&str], word: &str) -> Option<usize> {
    words.iter().position(|w| w.eq_ignore_ascii_case(word))
}

/// The identifier of an inline (or assigned) literal: the routine (its
/// prefix), `#`, its number in the routine from 1.
#[inline]
pub(crate) fn inline_id(prefix: &str, n: usize, id: &mut String) {
    id.clear();
    id.push_str(prefix);
    id.push('#');
    id.push_str(itoa::Buffer::new().format(n));
}

/// The identifier of a declared target: its name, with its element's
/// index path where it is one of an array's (`arr{2,1}`).
#[inline]
pub(crate) fn declared_id(name: &str, index: &[usize], id: &mut String) {
    id.clear();
    id.push_str(name);
    if let Some((first, rest)) = index.split_first() {
        id.push('{');
        id.push_str(itoa::Buffer::new().format(*first));
        for i in rest {
            id.push(',');
            id.push_str(itoa::Buffer::new().format(*i));
        }
        id.push('}');
    }
}

/// An identifier qualified with its module (`M1:pA`): where the same
/// identifier is another module's too.
pub(crate) fn qualified(module: &str, id: &str) -> String {
    let mut out = id.to_string();
    qualify(module, &mut out);
    out
}

/// [`qualified`] in place.
#[inline]
pub(crate) fn qualify(module: &str, id: &mut String) {
    id.insert(0, ':');
    id.insert_str(0, module);
}

/// An identifier of a routine's own data (`r1/pA`): where its name is
/// declared elsewhere too.
pub(crate) fn in_routine(routine: &str, id: &str) -> String {
    format!("{routine}/{id}")
}

/// The names of the instruction holding a literal: the instruction, its
/// tool and work object.
#[derive(Clone, Copy, Default)]
pub(crate) struct HeldBy<'a> {
    pub instruction: Option<&'a Arc<str>>,
    pub tool: Option<&'a Arc<str>>,
    pub wobj: Option<&'a Arc<str>>,
}

/// A target (or jointtarget) described by its parts.
#[derive(Clone, Copy)]
pub(crate) struct TargetParts<'a> {
    pub kind: TargetKind,
    pub file: usize,
    pub module: &'a Arc<str>,
    pub routine: Option<&'a Arc<str>>,
    /// Where its value starts.
    pub pos: Pos,
    /// The declared (or assigned) variable.
    pub name: Option<&'a str>,
    pub storage: Option<Storage>,
    pub held: HeldBy<'a>,
}

/// Where a target is: its file, module and routine.
#[derive(Clone, Copy)]
pub(crate) struct Place<'a> {
    pub file: usize,
    pub module: &'a Arc<str>,
    pub routine: Option<&'a Arc<str>>,
}

impl<'a> TargetParts<'a> {
    /// A literal in a routine's statement: inline in an instruction, or
    /// assigned to the variable `assigned_to`.
    #[inline]
    pub fn inline(at: Place<'a>, pos: Pos, held: HeldBy<'a>, assigned_to: Option<&'a str>) -> Self {
        TargetParts {
            kind: match assigned_to {
                Some(_) => TargetKind::Assigned,
                None => TargetKind::Inline,
            },
            file: at.file,
            module: at.module,
            routine: at.routine,
            pos,
            name: assigned_to,
            storage: None,
            held,
        }
    }

    /// The value of declaration `name` (`element`: one element of its
    /// array value).
    #[inline]
    pub fn declared(
        at: Place<'a>,
        pos: Pos,
        name: &'a str,
        storage: Storage,
        element: bool,
    ) -> Self {
        TargetParts {
            kind: match element {
                true => TargetKind::ArrayElement,
                false => TargetKind::Declared,
            },
            file: at.file,
            module: at.module,
            routine: at.routine,
            pos,
            name: Some(name),
            storage: Some(storage),
            held: HeldBy::default(),
        }
    }

    /// `t` made this target (its identifier and value are the caller's),
    /// its allocations kept where the same.
    #[inline]
    pub fn fill(&self, t: &mut Target) {
        t.kind = self.kind;
        set_origin(&mut t.origin, self);
        match (&mut t.name, self.name) {
            (Some(n), Some(name)) => {
                if n != name {
                    n.clear();
                    n.push_str(name);
                }
            }
            (slot, name) => *slot = name.map(str::to_string),
        }
        t.storage = self.storage;
        renew(&mut t.instruction, self.held.instruction);
        renew(&mut t.tool, self.held.tool);
        renew(&mut t.wobj, self.held.wobj);
        t.derived = None;
    }

    /// This target, its identifier `id` and value `value`.
    pub fn target(&self, id: String, value: Option<RobTargetValue>) -> Target {
        let mut t = Target {
            id,
            kind: self.kind,
            origin: self.origin(),
            name: None,
            storage: None,
            value,
            instruction: None,
            tool: None,
            wobj: None,
            derived: None,
        };
        self.fill(&mut t);
        t
    }

    /// This jointtarget, its identifier `id` and numbers.
    pub fn jointtarget(
        &self,
        id: String,
        (robax, extax): ([Number; 6], [Number; 6]),
    ) -> JointTarget {
        JointTarget {
            id,
            kind: self.kind,
            origin: self.origin(),
            name: self.name.map(str::to_string),
            storage: self.storage,
            robax,
            extax,
            instruction: self.held.instruction.cloned(),
            tool: self.held.tool.cloned(),
            wobj: self.held.wobj.cloned(),
        }
    }

    fn origin(&self) -> Origin {
        Origin {
            file: self.file,
            module: self.module.clone(),
            routine: self.routine.cloned(),
            pos: self.pos,
        }
    }
}

/// A target's origin set in place (the names' `Arc`s kept where the same).
#[inline]
fn set_origin(o: &mut Origin, t: &TargetParts) {
    o.file = t.file;
    if !Arc::ptr_eq(&o.module, t.module) {
        o.module = t.module.clone();
    }
    match (t.routine, &o.routine) {
        (Some(r), Some(have)) if Arc::ptr_eq(r, have) => {}
        _ => o.routine = t.routine.cloned(),
    }
    o.pos = t.pos;
}

/// Set a name, keeping the one it holds when it is the same.
#[inline]
fn renew(slot: &mut Option<Arc<str>>, name: Option<&Arc<str>>) {
    match (&*slot, name) {
        (Some(a), Some(b)) if Arc::ptr_eq(a, b) => {}
        _ => *slot = name.cloned(),
    }
}

/// A data declaration described by its parts.
pub(crate) struct DeclParts<'a> {
    pub scope: Option<Scope>,
    pub storage: Storage,
    pub type_name: &'a str,
    pub name: &'a str,
    pub dims: Vec<Expr>,
    pub init: Option<Expr>,
    pub pos: Pos,
    /// The number of the lane's array run holding its value.
    pub elements: Option<usize>,
}

/// The declaration of `parts`.
pub(crate) fn declaration(parts: DeclParts) -> DataDecl {
    DataDecl {
        scope: parts.scope,
        storage: parts.storage,
        type_name: parts.type_name.to_string(),
        name: parts.name.to_string(),
        dims: parts.dims,
        init: parts.init,
        pos: parts.pos,
        elements: parts.elements,
    }
}

/// An aggregate value `[a, b, ...]` spanning `span`.
pub(crate) fn aggregate_of(items: Vec<Expr>, span: std::ops::Range<usize>) -> Expr {
    Expr::Aggregate(Box::new(Aggregate { items, span }))
}

/// An argument of a call.
pub(crate) fn arg(optional: bool, name: Option<Arc<str>>, value: Option<Expr>) -> Arg {
    Arg {
        optional,
        name,
        value,
    }
}

/// How many robtarget arguments lead the positional arguments of a move
/// instruction whose other arguments are exactly speed, zone and tool;
/// `None` for any other instruction.
pub(crate) fn leading_targets(name: &str) -> Option<usize> {
    let sig = motion_signature(name)?;
    let k = sig.robtargets.len();
    let plain = matches!(
        sig.kind,
        MotionKind::Linear | MotionKind::Joint | MotionKind::Circular
    ) && sig.robtargets.iter().enumerate().all(|(i, &at)| i == at)
        && sig.speed == Some(ArgAt::Index(k))
        && sig.zone == Some(ArgAt::Index(k + 1))
        && sig.tool == Some(ArgAt::Index(k + 2));
    plain.then_some(k)
}

/// A move the lane covers described by its parts: a motion instruction
/// whose positional arguments are its targets, speed, zone and tool, and
/// which may name its work object.
pub(crate) struct MoveParts {
    pub pos: Pos,
    pub instruction: Arc<str>,
    /// The program's numbers of its robtarget literals (CirPoint before
    /// ToPoint); empty for a move to a target by name.
    pub targets: Vec<usize>,
    pub named: Option<Arc<str>>,
    pub speed: Arc<str>,
    pub zone: Arc<str>,
    pub tool: Arc<str>,
    /// `\WObj:=name`: the argument's name as written, and the work
    /// object's.
    pub wobj: Option<(Arc<str>, Arc<str>)>,
}

impl MoveParts {
    /// The parts of a call the grammar read, where it is such a move (its
    /// position left to the statement).
    pub fn of_call(call: &Call) -> Option<MoveParts> {
        let k = leading_targets(&call.name)?;
        if call.late_bound || !call.jointtargets.is_empty() || call.targets.len() > k {
            return None;
        }
        let (wobj, positional) = match call.args.split_last()? {
            (last, rest) if last.optional => (Some(last), rest),
            _ => (None, &call.args[..]),
        };
        let name = |a: &Arg| match (a.optional, &a.name, &a.value) {
            (false, None, Some(Expr::Name(n))) => Some(n.clone()),
            _ => None,
        };
        let [lead @ .., speed, zone, tool] = positional else {
            return None;
        };
        if lead.len() != k {
            return None;
        }
        let named = match call.targets.len() {
            0 if k == 1 => Some(name(&lead[0])?),
            n if n == k => {
                let at = |(a, &t): (&Arg, &usize)| matches!(a, Arg { optional: false, name: None, value: Some(Expr::Target(i)) } if *i == t);
                lead.iter().zip(&call.targets).all(at).then_some(())?;
                None
            }
            _ => return None,
        };
        let wobj = match wobj {
            Some(Arg {
                optional: true,
                name: Some(word),
                value: Some(Expr::Name(w)),
            }) if word.eq_ignore_ascii_case("WObj") => Some((word.clone(), w.clone())),
            Some(_) => return None,
            None => None,
        };
        Some(MoveParts {
            pos: Pos::default(),
            instruction: call.name.clone(),
            targets: call.targets.clone(),
            named,
            speed: name(speed)?,
            zone: name(zone)?,
            tool: name(tool)?,
            wobj,
        })
    }

    /// The move's statement.
    pub fn statement(self) -> Statement {
        Statement {
            pos: self.pos,
            kind: StatementKind::Call(self.call()),
        }
    }

    /// The move's call.
    pub fn call(self) -> Call {
        let mut args = Vec::with_capacity(self.targets.len() + 4);
        let positional = |e: Expr| arg(false, None, Some(e));
        args.extend(self.targets.iter().map(|&i| positional(Expr::Target(i))));
        args.extend(self.named.map(|n| positional(Expr::Name(n))));
        for n in [self.speed, self.zone, self.tool] {
            args.push(positional(Expr::Name(n)));
        }
        if let Some((word, w)) = self.wobj {
            args.push(arg(true, Some(word), Some(Expr::Name(w))));
        }
        Call {
            name: self.instruction,
            late_bound: false,
            args,
            targets: self.targets,
            jointtargets: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn name(n: &str) -> Option<Expr> {
        Some(Expr::Name(Arc::from(n)))
    }

    /// `MoveL <first>, v100, fine, tool0\WObj:=wobj1` as the grammar
    /// reads it, its literal (if any) numbered 7.
    fn move_l(first: Expr, wobj: Option<Arg>) -> Call {
        let targets = match first {
            Expr::Target(_) => vec![7],
            _ => Vec::new(),
        };
        let mut args = vec![arg(false, None, Some(first))];
        for n in ["v100", "fine", "tool0"] {
            args.push(arg(false, None, name(n)));
        }
        args.extend(wobj);
        Call {
            name: Arc::from("MoveL"),
            late_bound: false,
            args,
            targets,
            jointtargets: Vec::new(),
        }
    }

    fn wobj() -> Option<Arg> {
        Some(arg(true, Some(Arc::from("WObj")), name("wobj1")))
    }

    #[test]
    fn identifiers_are_written_as_the_module_docs_say() {
        let mut id = String::from("old");
        declared_id("pScan", &[2, 1], &mut id);
        assert_eq!(id, "pScan{2,1}");
        declared_id("pA", &[], &mut id);
        assert_eq!(id, "pA");
        inline_id("main", 3, &mut id);
        assert_eq!(id, "main#3");
        assert_eq!(qualified("M1", "pA"), "M1:pA");
        assert_eq!(in_routine("r1", "arr{2}"), "r1/arr{2}");
    }

    #[test]
    fn keywords_are_matched_whatever_their_case() {
        let k = |words: &[&str], w| keyword_number(words, w);
        assert_eq!(k(&SCOPE_WORDS, "local").map(scope), Some(Scope::Local));
        assert_eq!(k(&SCOPE_WORDS, "Task").map(scope), Some(Scope::Task));
        assert_eq!(k(&STORAGE_WORDS, "pers").map(storage), Some(Storage::Pers));
        assert_eq!(
            k(&STORAGE_WORDS, "CONST").map(storage),
            Some(Storage::Const)
        );
        assert_eq!(k(&STORAGE_WORDS, "VAR").map(storage), Some(Storage::Var));
        assert_eq!(k(&STORAGE_WORDS, "ALIAS"), None);
    }

    /// A plain move the grammar reads is made again, the same, by the
    /// constructor the lane's moves are made by.
    #[test]
    fn a_plain_move_is_made_by_the_one_constructor() {
        for call in [
            move_l(Expr::Target(7), wobj()),
            move_l(Expr::Target(7), None),
            move_l(Expr::Name(Arc::from("pA")), wobj()),
        ] {
            let parts = MoveParts::of_call(&call).expect("a plain move");
            assert_eq!(parts.call(), call);
        }
        let parts = MoveParts::of_call(&move_l(Expr::Name(Arc::from("pA")), wobj())).unwrap();
        assert_eq!(parts.named.as_deref(), Some("pA"));
        assert_eq!(parts.wobj.map(|w| w.1).as_deref(), Some("wobj1"));
    }

    /// Where the lane would not read the move, the grammar keeps its own
    /// call: another optional argument, a late-bound name, an instruction
    /// of another signature, a target that is no plain name.
    #[test]
    fn other_calls_are_not_moves() {
        let conc = Some(arg(true, Some(Arc::from("Conc")), None));
        assert!(MoveParts::of_call(&move_l(Expr::Target(7), conc)).is_none());
        let mut late = move_l(Expr::Target(7), None);
        late.late_bound = true;
        assert!(MoveParts::of_call(&late).is_none());
        let mut abs = move_l(Expr::Target(7), None);
        abs.name = Arc::from("MoveAbsJ");
        assert!(MoveParts::of_call(&abs).is_none());
        let index = Expr::Index(Box::new((
            Expr::Name(Arc::from("p")),
            vec![Expr::Num(Number::new(1.0, 0..1))],
        )));
        assert!(MoveParts::of_call(&move_l(index, None)).is_none());
    }

    #[test]
    fn a_target_filled_again_is_what_its_parts_say() {
        let module: Arc<str> = Arc::from("M");
        let routine: Arc<str> = Arc::from("main");
        let tool: Arc<str> = Arc::from("tool0");
        let place = Place {
            file: 1,
            module: &module,
            routine: Some(&routine),
        };
        let pos = Pos::default();
        let declared = TargetParts::declared(place, pos, "pS", Storage::Pers, true);
        let mut t = declared.target("pS{1}".into(), None);
        assert_eq!(t.kind, TargetKind::ArrayElement);
        assert_eq!(
            (t.name.as_deref(), t.storage),
            (Some("pS"), Some(Storage::Pers))
        );
        let held = HeldBy {
            instruction: None,
            tool: Some(&tool),
            wobj: None,
        };
        TargetParts::inline(place, pos, held, None).fill(&mut t);
        assert_eq!(t.kind, TargetKind::Inline);
        assert_eq!((t.name.as_deref(), t.storage), (None, None));
        assert_eq!(t.tool.as_deref(), Some("tool0"));
        TargetParts::inline(place, pos, HeldBy::default(), Some("p1")).fill(&mut t);
        assert_eq!(
            (t.kind, t.name.as_deref()),
            (TargetKind::Assigned, Some("p1"))
        );
        assert_eq!(t.origin.routine.as_deref(), Some("main"));
    }
}
