//! Every move instruction of a program, one at a time, with what each of
//! its target arguments reads: the robtargets it reaches (as [`uses`]
//! finds them: by name, literal, array element, the bases of a derived
//! expression, what a variable or a settled parameter is assigned from)
//! and the jointtarget it names. The job decides each move's fate from
//! this; a move whose argument reaches nothing is the job's to explain.
//!
//! [`uses`]: super::uses

use super::each_move::NOT_KEPT;
use super::glob::glob_match;
use super::refs::{access_pattern, describe, Reach, Reached, Refs};
use super::statements::{routine_bodies, walk_items};
use super::usage::Through;
use super::usages::MoveLookup;
use crate::rapid::{
    Call, Expr, Listed, Module, Motion, MoveBatch, Program, Statement, StatementKind, TargetKind,
};
use rayon::prelude::*;
use std::borrow::Cow;
use std::collections::HashMap;

/// One target argument of a move (its ToPoint, or the CirPoint of a
/// circular move).
pub struct Point<'a> {
    /// The argument as written: an expression of a statement, or a plain
    /// name (a move of a run the fast lane read).
    pub expr: Option<&'a Expr>,
    pub name: Option<&'a str>,
    /// The robtargets it reaches, and how.
    pub robtargets: Vec<(std::ops::Range<usize>, Through)>,
    /// The jointtargets it names (MoveAbsJ, MoveExtJ): one, or every
    /// element of an array its index reads at run time.
    pub jointtargets: Vec<usize>,
    /// Where the argument is a parameter its calls settle: the names some
    /// call passes that reach no target of the files read (a variable the
    /// run fills, a name declared elsewhere). The move is the run's there.
    pub unread_passed: Vec<&'a str>,
}

/// One move instruction.
pub struct Move<'a> {
    pub instruction: &'a str,
    pub module: &'a str,
    pub routine: &'a str,
    pub file: usize,
    pub line: u32,
    pub col: u32,
    /// Where the instruction starts in its file.
    pub offset: usize,
    /// Tool and work object as written (`None`: the move names none):
    /// borrowed from a run's names (a million moves copy none).
    pub tool: Option<Cow<'a, str>>,
    pub wobj: Option<Cow<'a, str>>,
    /// Whether it moves to a jointtarget (its targets are joints).
    pub joints: bool,
    /// Whether the instruction is one the reader knows the arguments of;
    /// `false`: a call of neither a procedure of the files read nor a
    /// known instruction, given targets.
    pub known: bool,
    pub points: Vec<Point<'a>>,
}

/// Every move instruction of `program`, in program order (module by
/// module, routine by routine, statements in source order).
pub fn each_move_instruction(program: &Program, visit: &mut dyn FnMut(&Move)) {
    each_move_instruction_with(program, &MoveLookup::new(program), visit);
}

/// [`each_move_instruction`], looked up in `lookup` (built for `program`).
pub fn each_move_instruction_with<'p>(
    program: &'p Program,
    lookup: &MoveLookup<'p>,
    visit: &mut dyn FnMut(&Move),
) {
    let args = Args::new(program, lookup);
    for module in &program.modules {
        for routine in &module.routines {
            let scope = (module.name.as_ref(), routine.name.as_ref());
            let at = At { module, scope };
            for body in routine_bodies(routine) {
                walk_items(program, body, &mut |item| match item {
                    Listed::Statement(s) => {
                        let StatementKind::Call(call) = &s.kind else {
                            return;
                        };
                        match call.motion() {
                            Some(m) => args.motion(call, m, s, &at, visit),
                            None => args.unknown_instruction(call, s, &at, visit),
                        }
                    }
                    Listed::Batch(batch) => args.batch(batch, &at, visit),
                });
            }
        }
    }
}

/// Where the moves being walked stand: their module, and its name and
/// the routine's.
struct At<'p> {
    module: &'p Module,
    scope: (&'p str, &'p str),
}

/// What a move's arguments are looked up in: the targets a move can
/// name ([`Refs`]), the jointtargets by identifier, what the calls pass
/// for a parameter they settle, and the procedures of the files read.
struct Args<'a, 'p> {
    program: &'p Program,
    lookup: &'a MoveLookup<'p>,
    refs: Refs<'a>,
    joints: HashMap<String, usize>,
    /// Procedures of the files read, by lower-case name.
    procedures: std::collections::HashSet<String>,
}

impl<'a, 'p> Args<'a, 'p> {
    fn new(program: &'p Program, lookup: &'a MoveLookup<'p>) -> Args<'a, 'p> {
        let (index, aliases) = (&lookup.index, &lookup.aliases);
        let refs = Refs::new(program, index, aliases);
        let joints: HashMap<String, usize> = program.jointtargets_by_id().collect();
        let procedures = (program.modules.iter())
            .flat_map(|m| &m.routines)
            .map(|r| r.name.to_ascii_lowercase())
            .collect();
        Args {
            program,
            lookup,
            refs,
            joints,
            procedures,
        }
    }

    fn joint_named(&self, name: &str, (module, routine): (&str, &str)) -> Option<usize> {
        let joints = &self.joints;
        let name = name.to_ascii_lowercase();
        let (module, routine) = (module.to_ascii_lowercase(), routine.to_ascii_lowercase());
        [
            format!("{routine}/{name}"),
            format!("{module}:{routine}/{name}"),
            format!("{module}:{name}"),
            name,
        ]
        .iter()
        .find_map(|k| joints.get(k).copied())
    }

    /// `jCalib{k}`, `cell.park`: the elements the access path can read.
    fn joint_elements(&self, e: &Expr) -> Vec<usize> {
        let Some(pattern) = access_pattern(e) else {
            return Vec::new();
        };
        self.program
            .jointtargets()
            .iter()
            .enumerate()
            .filter(|(_, j)| {
                matches!(j.kind, TargetKind::ArrayElement | TargetKind::RecordField)
                    && glob_match(&pattern, &j.id)
            })
            .map(|(i, _)| i)
            .collect()
    }

    /// What the calls pass for a parameter they settle (`routine/name`).
    fn passed(&self, name: &str, scope: (&str, &str)) -> &'a [String] {
        let aliases: &'a HashMap<String, Vec<String>> = &self.lookup.aliases;
        match aliases.is_empty() {
            true => &[],
            false => {
                let own = format!("{}/{name}", scope.1).to_ascii_lowercase();
                aliases.get(&own).map_or(&[], Vec::as_slice)
            }
        }
    }

    /// A name, or what the calls pass for a parameter they settle.
    fn joint_passed(&self, name: &str, scope: (&str, &str)) -> Vec<usize> {
        let mut out: Vec<usize> = self.joint_named(name, scope).into_iter().collect();
        if out.is_empty() {
            for p in self.passed(name, scope) {
                out.extend(self.joint_named(p, scope));
            }
        }
        out
    }

    /// The names passed for a parameter that reach nothing.
    fn unread(
        &self,
        e: Option<&Expr>,
        name: Option<&str>,
        joints: bool,
        scope: (&str, &str),
    ) -> Vec<&'a str> {
        let Some(n) = name.or(e.and_then(Expr::as_name)) else {
            return Vec::new();
        };
        (self.passed(n, scope).iter())
            .filter(|p| match joints {
                true => self.joint_named(p, scope).is_none(),
                false => self.refs.passed(p, scope).is_none(),
            })
            .map(String::as_str)
            .collect()
    }

    /// Procedures of the files read and instructions that take targets
    /// without moving to them (PDispOn, the tool calibrations).
    fn known(&self, name: &str) -> bool {
        self.procedures.contains(name)
            || crate::rapid::builtins::is_instant_instruction(name)
            || crate::rapid::builtins::reads_targets_without_moving(name)
    }

    fn reached(&self, reach: Reach, scope: (&str, &str)) -> Vec<(std::ops::Range<usize>, Through)> {
        self.refs
            .targets(reach, scope)
            .into_iter()
            .map(|(r, through)| match r {
                Reached::One(i) => (i..i + 1, through),
                Reached::All(r) => (r, through),
            })
            .collect()
    }

    /// An instruction the reader does not know (an option's, or a
    /// procedure of a module not read) given targets: a move for all
    /// anyone can tell, accounted for as such.
    fn unknown_instruction(
        &self,
        call: &'p Call,
        s: &'p Statement,
        at: &At<'p>,
        visit: &mut dyn FnMut(&Move),
    ) {
        let scope = at.scope;
        if call.late_bound || self.known(&call.name.to_ascii_lowercase()) {
            return;
        }
        let points: Vec<Point> = (call.args.iter())
            .filter_map(|a| a.value.as_ref())
            .filter_map(|e| {
                let robtargets = match e {
                    Expr::JointTarget(_) => Vec::new(),
                    _ => self.reached(Reach::Expr(e), scope),
                };
                let jointtargets = match e {
                    Expr::JointTarget(i) => vec![*i],
                    Expr::Name(n) => self.joint_named(n, scope).into_iter().collect(),
                    _ => Vec::new(),
                };
                (!robtargets.is_empty() || !jointtargets.is_empty()).then_some(Point {
                    expr: Some(e),
                    name: None,
                    robtargets,
                    jointtargets,
                    unread_passed: Vec::new(),
                })
            })
            .collect();
        if !points.is_empty() {
            visit(&Move {
                instruction: &call.name,
                module: scope.0,
                routine: scope.1,
                file: at.module.file,
                line: s.pos.line,
                col: s.pos.col,
                offset: s.pos.offset,
                tool: None,
                wobj: None,
                joints: false,
                known: false,
                points,
            });
        }
    }

    /// A motion instruction written as a statement.
    fn motion(
        &self,
        call: &'p Call,
        m: Motion<'p>,
        s: &'p Statement,
        at: &At<'p>,
        visit: &mut dyn FnMut(&Move),
    ) {
        let scope = at.scope;
        let joints = m.signature.robtargets.is_empty();
        let points = [m.via, m.to]
            .into_iter()
            .flatten()
            .map(|e| Point {
                expr: Some(e),
                name: None,
                robtargets: if joints {
                    Vec::new()
                } else {
                    self.reached(Reach::Expr(e), scope)
                },
                jointtargets: match e {
                    _ if !joints => Vec::new(),
                    Expr::JointTarget(i) => vec![*i],
                    Expr::Name(n) => self.joint_passed(n, scope),
                    _ => self.joint_elements(e),
                },
                unread_passed: self.unread(Some(e), None, joints, scope),
            })
            .collect();
        visit(&Move {
            instruction: &call.name,
            module: scope.0,
            routine: scope.1,
            file: at.module.file,
            line: s.pos.line,
            col: s.pos.col,
            offset: s.pos.offset,
            tool: m.tool.map(|t| Cow::Owned(describe(t))),
            wobj: m.wobj.map(|w| Cow::Owned(describe(w))),
            joints,
            known: true,
            points,
        });
    }

    /// The moves of a run the fast lane read. The targets they name are
    /// looked up a window at a time on every core: a million names among
    /// a million targets, a cache miss each, were most of this walk on
    /// one core.
    fn batch(&self, batch: MoveBatch<'p>, at: &At<'p>, visit: &mut dyn FnMut(&Move)) {
        let scope = at.scope;
        let src = self.program.source(at.module.file);
        let mut moves = batch.moves();
        let mut window = Vec::with_capacity(WINDOW.min(batch.len()));
        // What the uses found for the run's names, kept.
        let kept = self.lookup.named.get(batch.number()).and_then(|n| n.get());
        let mut taken = 0;
        loop {
            window.clear();
            window.extend(moves.by_ref().take(WINDOW));
            if window.is_empty() {
                break;
            }
            let found: Vec<Option<Vec<_>>> = (window.par_iter().enumerate())
                .with_min_len(256)
                .map(|(j, mv)| {
                    let name = mv.named()?;
                    let kept = kept.and_then(|k| k.get(taken + j));
                    Some(match kept.copied().filter(|&i| i != NOT_KEPT) {
                        Some(i) => {
                            let i = i as usize;
                            vec![(i..i + 1, Through::Direct)]
                        }
                        None => self.reached(Reach::Name(name), scope),
                    })
                })
                .collect();
            taken += window.len();
            for (mv, found) in window.iter().zip(found) {
                let points = match (mv.named(), found) {
                    (Some(name), Some(robtargets)) => vec![Point {
                        expr: None,
                        name: Some(name),
                        robtargets,
                        jointtargets: Vec::new(),
                        unread_passed: self.unread(None, Some(name), false, scope),
                    }],
                    _ => mv
                        .targets()
                        .map(|i| Point {
                            expr: None,
                            name: None,
                            robtargets: vec![(i..i + 1, Through::Direct)],
                            jointtargets: Vec::new(),
                            unread_passed: Vec::new(),
                        })
                        .collect(),
                };
                visit(&Move {
                    instruction: mv.instruction(),
                    module: scope.0,
                    routine: scope.1,
                    file: at.module.file,
                    line: mv.line(),
                    col: col_of(src, mv.offset()),
                    offset: mv.offset(),
                    tool: mv.tool().map(|t| Cow::Borrowed(&**t)),
                    wobj: mv.wobj().map(|w| Cow::Borrowed(&**w)),
                    joints: false,
                    known: true,
                    points,
                });
            }
        }
    }
}

/// Moves of a run looked up at once, on every core.
const WINDOW: usize = 1 << 16;

/// The column (1-based, in bytes: RAPID is written in Latin-1) of byte
/// `offset` of `src`.
fn col_of(src: &[u8], offset: usize) -> u32 {
    let start = src[..offset.min(src.len())]
        .iter()
        .rposition(|&b| b == b'\n' || b == b'\r')
        .map_or(0, |p| p + 1);
    (offset - start + 1) as u32
}
