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
use crate::rapid::{Expr, Listed, Program, StatementKind, TargetKind};
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
    let (index, aliases) = (&lookup.index, &lookup.aliases);
    let refs = Refs::new(program, index, aliases);
    let joints: HashMap<String, usize> = program
        .jointtargets()
        .iter()
        .enumerate()
        .filter(|(_, j)| j.kind != TargetKind::Inline)
        .map(|(i, j)| (j.id.to_ascii_lowercase(), i))
        .collect();
    let joint_named = |name: &str, (module, routine): (&str, &str)| {
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
    };
    // `jCalib{k}`, `cell.park`: the elements the access path can read.
    let joint_elements = |e: &Expr| -> Vec<usize> {
        let Some(pattern) = access_pattern(e) else {
            return Vec::new();
        };
        program
            .jointtargets()
            .iter()
            .enumerate()
            .filter(|(_, j)| {
                matches!(j.kind, TargetKind::ArrayElement | TargetKind::RecordField)
                    && glob_match(&pattern, &j.id)
            })
            .map(|(i, _)| i)
            .collect()
    };
    // What the calls pass for a parameter they settle (`routine/name`).
    let passed = |name: &str, scope: (&str, &str)| -> &[String] {
        match aliases.is_empty() {
            true => &[],
            false => {
                let own = format!("{}/{name}", scope.1).to_ascii_lowercase();
                aliases.get(&own).map_or(&[], Vec::as_slice)
            }
        }
    };
    // A name, or what the calls pass for a parameter they settle.
    let joint_passed = |name: &str, scope: (&str, &str)| -> Vec<usize> {
        let mut out: Vec<usize> = joint_named(name, scope).into_iter().collect();
        if out.is_empty() {
            for p in passed(name, scope) {
                out.extend(joint_named(p, scope));
            }
        }
        out
    };
    // The names passed for a parameter that reach nothing.
    let unread = |e: Option<&Expr>, name: Option<&str>, joints: bool, scope: (&str, &str)| {
        let Some(n) = name.or(e.and_then(Expr::as_name)) else {
            return Vec::new();
        };
        (passed(n, scope).iter())
            .filter(|p| match joints {
                true => joint_named(p, scope).is_none(),
                false => refs.passed(p, scope).is_none(),
            })
            .map(String::as_str)
            .collect()
    };
    // Procedures of the files read and instructions that take targets
    // without moving to them (PDispOn, the tool calibrations).
    let known: std::collections::HashSet<String> = (program.modules.iter())
        .flat_map(|m| &m.routines)
        .map(|r| r.name.to_ascii_lowercase())
        .collect();
    let known = |name: &str| {
        known.contains(name)
            || crate::rapid::builtins::is_instant_instruction(name)
            || crate::rapid::builtins::reads_targets_without_moving(name)
    };
    let reached = |reach: Reach, scope: (&str, &str)| -> Vec<(std::ops::Range<usize>, Through)> {
        refs.targets(reach, scope)
            .into_iter()
            .map(|(r, through)| match r {
                Reached::One(i) => (i..i + 1, through),
                Reached::All(r) => (r, through),
            })
            .collect()
    };
    for module in &program.modules {
        let src = program.source(module.file);
        for routine in &module.routines {
            let scope = (module.name.as_ref(), routine.name.as_ref());
            for body in routine_bodies(routine) {
                walk_items(program, body, &mut |item| match item {
                    Listed::Statement(s) => {
                        let StatementKind::Call(call) = &s.kind else {
                            return;
                        };
                        let Some(m) = call.motion() else {
                            // An instruction the reader does not know
                            // (an option's, or a procedure of a module not
                            // read) given targets: a move for all anyone
                            // can tell, accounted for as such.
                            if call.late_bound || known(&call.name.to_ascii_lowercase()) {
                                return;
                            }
                            let points: Vec<Point> = (call.args.iter())
                                .filter_map(|a| a.value.as_ref())
                                .filter_map(|e| {
                                    let robtargets = match e {
                                        Expr::JointTarget(_) => Vec::new(),
                                        _ => reached(Reach::Expr(e), scope),
                                    };
                                    let jointtargets = match e {
                                        Expr::JointTarget(i) => vec![*i],
                                        Expr::Name(n) => {
                                            joint_named(n, scope).into_iter().collect()
                                        }
                                        _ => Vec::new(),
                                    };
                                    (!robtargets.is_empty() || !jointtargets.is_empty()).then_some(
                                        Point {
                                            expr: Some(e),
                                            name: None,
                                            robtargets,
                                            jointtargets,
                                            unread_passed: Vec::new(),
                                        },
                                    )
                                })
                                .collect();
                            if !points.is_empty() {
                                visit(&Move {
                                    instruction: &call.name,
                                    module: scope.0,
                                    routine: scope.1,
                                    file: module.file,
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
                            return;
                        };
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
                                    reached(Reach::Expr(e), scope)
                                },
                                jointtargets: match e {
                                    _ if !joints => Vec::new(),
                                    Expr::JointTarget(i) => vec![*i],
                                    Expr::Name(n) => joint_passed(n, scope),
                                    _ => joint_elements(e),
                                },
                                unread_passed: unread(Some(e), None, joints, scope),
                            })
                            .collect();
                        visit(&Move {
                            instruction: &call.name,
                            module: scope.0,
                            routine: scope.1,
                            file: module.file,
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
                    Listed::Batch(batch) => {
                        // The targets a run's moves name are looked up a
                        // window at a time on every core: a million names
                        // among a million targets, a cache miss each,
                        // were most of this walk on one core.
                        let mut moves = batch.moves();
                        let mut window = Vec::with_capacity(WINDOW.min(batch.len()));
                        // What the uses found for the run's names, kept.
                        let kept = lookup.named.get(batch.number()).and_then(|n| n.get());
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
                                        None => reached(Reach::Name(name), scope),
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
                                        unread_passed: unread(None, Some(name), false, scope),
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
                                    file: module.file,
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
