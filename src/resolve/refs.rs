//! The targets a move's argument reads ([`Refs`]): a name looked up by
//! RAPID's scopes, an array element or record field by its access path, the
//! bases of a derived expression, and what a variable is assigned from.

use super::glob::glob_match;
use super::usage::Through;
use crate::rapid::targets::TargetIndex;
use crate::rapid::{Expr, NoCase, Program, TargetKind};
use std::collections::HashMap;

/// What a move's target argument is.
#[derive(Clone, Copy)]
pub(super) enum Reach<'a> {
    /// An expression of a statement.
    Expr(&'a Expr),
    /// A plain name (a run's move by name).
    Name(&'a str),
}

/// The name of a tool or work-object argument: a plain variable (`tool1`)
/// by its name; anything else (an element of a tool array, a record field,
/// a function's result) by a description no declaration matches, so that
/// its target is refused as having a tool nobody can tell before the run,
/// never corrected for `tool0`.
pub(super) fn describe(expr: &Expr) -> String {
    match expr {
        Expr::Name(n) => n.to_string(),
        Expr::Index(b) => format!("{}{{…}}", describe(&b.0)),
        Expr::Component(b) => format!("{}.{}", describe(&b.0), b.1),
        Expr::Call(c) => format!("{}(…)", c.name),
        _ => "an expression".to_string(),
    }
}

/// What resolving the targets an expression reads needs.
pub(super) struct Refs<'a> {
    program: &'a Program,
    index: &'a TargetIndex<'a>,
    aliases: &'a HashMap<String, Vec<String>>,
    /// Derived targets written in statements (`MoveL Offs(p10, 0, 0, 50)`),
    /// by where their call starts.
    derived_at: HashMap<usize, usize>,
    /// Robtarget parameters and routine data without a value, by
    /// (routine, name), lower case: inside their routine they hide a
    /// module's or the task's target of the same name.
    hiding: std::collections::HashSet<(NoCase<'a>, NoCase<'a>)>,
}

/// Where a name is read: its module and routine.
pub(super) type Scope<'s> = (&'s str, &'s str);

/// What a move reaches: one target, or every target of a stretch (an
/// array's elements through an index known only at run time).
pub(super) enum Reached {
    One(usize),
    All(std::ops::Range<usize>),
}

impl<'a> Refs<'a> {
    pub(super) fn new(
        program: &'a Program,
        index: &'a TargetIndex<'a>,
        aliases: &'a HashMap<String, Vec<String>>,
    ) -> Refs<'a> {
        Refs {
            program,
            index,
            aliases,
            derived_at: program
                .targets()
                .one_by_one_all()
                .filter(|(_, t)| t.kind == TargetKind::Derived)
                .map(|(i, t)| (t.origin.pos.offset, i))
                .collect(),
            hiding: (program.modules.iter())
                .flat_map(|m| &m.routines)
                .flat_map(|r| {
                    let params = (r.params.iter())
                        .filter(|p| p.type_name.eq_ignore_ascii_case("robtarget"))
                        .map(|p| &p.name);
                    let unset = (r.data.iter())
                        .filter(|d| d.init.is_none())
                        .filter(|d| d.type_name.eq_ignore_ascii_case("robtarget"))
                        .map(|d| &d.name);
                    params
                        .chain(unset)
                        .map(|n| (NoCase(r.name.as_bytes()), NoCase(n.as_bytes())))
                })
                .collect(),
        }
    }

    /// The target a name reads in `routine` of `module`: the routine's own
    /// data first (its identifier carries the routine where the name is
    /// declared elsewhere too), then the module's, then the task's.
    fn lookup(&self, id: &str, (module, routine): Scope) -> Option<usize> {
        // The scoped and qualified keys are built only where the index
        // holds such identifiers: a move by name is looked up a million
        // times on a large program, and three allocations each showed.
        // A parameter or a routine's own variable of that name hides the
        // module's and the task's: the move goes where the run puts it.
        // Names borrowed, not lowered: a million moves look their
        // targets up here.
        let hiding: &std::collections::HashSet<(NoCase, NoCase)> = &self.hiding;
        if !hiding.is_empty()
            && hiding.contains(&(NoCase(routine.as_bytes()), NoCase(id.as_bytes())))
        {
            return None;
        }
        self.passed(id, (module, routine))
    }

    /// The target a name a call passes reads: looked up as a name of the
    /// routine's module or the task (a parameter of the same name, which
    /// it is passed to, does not hide it).
    pub(super) fn passed(&self, id: &str, (module, routine): Scope) -> Option<usize> {
        let scoped = self.index.has_routine_scoped();
        let qualified = self.index.has_qualified();
        let own = || format!("{routine}/{id}");
        scoped
            .then(|| self.index.get(&own()))
            .flatten()
            .or_else(|| {
                (scoped && qualified)
                    .then(|| self.index.get(&format!("{module}:{}", own())))
                    .flatten()
            })
            .or_else(|| {
                qualified
                    .then(|| self.index.get(&format!("{module}:{id}")))
                    .flatten()
            })
            .or_else(|| self.index.get(id))
    }

    /// A name read by a move or a derived expression: the target itself,
    /// and what a variable of that name is assigned from at run time.
    fn named(&self, name: &str, module: Scope, through: Through) -> Vec<(Reached, Through)> {
        let mut out: Vec<(Reached, Through)> = self
            .lookup(name, module)
            .map(|i| (Reached::One(i), through))
            .into_iter()
            .collect();
        if self.aliases.is_empty() {
            return out;
        }
        // A variable's assignments, and a parameter's calls (by routine).
        let own = format!("{}/{name}", module.1).to_ascii_lowercase();
        let assigned = self.aliases.get(&name.to_ascii_lowercase());
        if let Some(bases) = assigned {
            out.extend(
                bases
                    .iter()
                    .filter_map(|b| self.lookup(b, module))
                    .map(|i| (Reached::One(i), Through::Variable)),
            );
        }
        if let Some(bases) = self.aliases.get(&own) {
            out.extend(
                bases
                    .iter()
                    .filter_map(|b| self.passed(b, module))
                    .map(|i| (Reached::One(i), Through::Variable)),
            );
        }
        out
    }

    /// Targets a move's argument reads: a literal, a declared name, an
    /// array element with literal indices (every element where an index
    /// is read at run time), the bases of a derived expression, and what
    /// a variable read is assigned from.
    pub(super) fn targets(&self, reach: Reach, module: Scope) -> Vec<(Reached, Through)> {
        let expr = match reach {
            Reach::Name(n) => return self.named(n, module, Through::Direct),
            Reach::Expr(e) => e,
        };
        let program = self.program;
        match expr {
            Expr::Target(i) => {
                let Some(t) = program.targets().get(*i) else {
                    return Vec::new();
                };
                match &t.derived {
                    Some(_) if t.written_with_expressions() => {
                        vec![(Reached::One(*i), Through::Direct)]
                    }
                    Some(d) => d
                        .bases
                        .iter()
                        .flat_map(|b| self.named(b, module, Through::Derived(*i)))
                        .collect(),
                    None => vec![(Reached::One(*i), Through::Direct)],
                }
            }
            Expr::Call(c) => match self.derived_at.get(&c.span.start) {
                Some(&i) => {
                    let mut out = self.targets(Reach::Expr(&Expr::Target(i)), module);
                    if out.is_empty() && !self.aliases.is_empty() {
                        // A base the reader does not hold as a target: a
                        // parameter its calls settle (`Offs(pAt, ...)`).
                        for n in c.args.iter().filter(|a| !a.optional) {
                            let Some(n) = n.value.as_ref().and_then(Expr::as_name) else {
                                continue;
                            };
                            let own = format!("{}/{n}", module.1).to_ascii_lowercase();
                            for b in self.aliases.get(&own).into_iter().flatten() {
                                if let Some(j) = self.passed(b, module) {
                                    out.push((Reached::One(j), Through::Derived(i)));
                                }
                            }
                        }
                    }
                    out
                }
                None => Vec::new(),
            },
            Expr::Name(n) => self.named(n, module, Through::Direct),
            // `arr{2,1}`, `rec.pos`, `cell{i}.path.start`: the access path as
            // a pattern over target identifiers, an index that is not a
            // literal matching every element.
            Expr::Index(_) | Expr::Component(_) => {
                let Some(pattern) = access_pattern(expr) else {
                    return Vec::new();
                };
                if !pattern.contains('*') {
                    if let Some(i) = self.lookup(&pattern, module) {
                        return vec![(Reached::One(i), Through::Direct)];
                    }
                }
                let mut out: Vec<(Reached, Through)> = Vec::new();
                // An array the fast lane read: its elements, all at once.
                let (module, routine) = module;
                // The routine's own array first, as for a name.
                let own = format!("{routine}/{pattern}");
                let qualified = format!("{module}:{pattern}");
                let qualified_own = format!("{module}:{own}");
                let mut patterns = [own, qualified_own, qualified, pattern].into_iter();
                for pattern in patterns.by_ref() {
                    if let Some(prefix) = pattern.strip_suffix("{*}") {
                        if let Some((first, n)) = self.index.array(prefix) {
                            out.push((Reached::All(first..first + n), Through::Direct));
                        }
                    }
                    out.extend(
                        program
                            .targets()
                            .one_by_one_all()
                            .filter(|(_, t)| {
                                matches!(t.kind, TargetKind::ArrayElement | TargetKind::RecordField)
                                    && glob_match(&pattern, &t.id)
                            })
                            .map(|(i, _)| (Reached::One(i), Through::Direct)),
                    );
                    if !out.is_empty() {
                        break;
                    }
                }
                out
            }
            _ => Vec::new(),
        }
    }
}

/// The identifier pattern of an access path: `a{2,1}` for literal
/// indices, `a{*}` where an index is computed at run time.
pub(super) fn access_pattern(expr: &Expr) -> Option<String> {
    match expr {
        Expr::Name(n) => Some(n.to_string()),
        Expr::Index(b) => {
            let (base, indices) = b.as_ref();
            let idx: Vec<String> = indices
                .iter()
                .map(|e| match e.as_num() {
                    Some(v) if v.fract() == 0.0 => format!("{}", v as i64),
                    _ => "*".to_string(),
                })
                .collect();
            Some(format!("{}{{{}}}", access_pattern(base)?, idx.join(",")))
        }
        Expr::Component(b) => {
            let (base, field) = b.as_ref();
            Some(format!("{}.{}", access_pattern(base)?, field))
        }
        _ => None,
    }
}
