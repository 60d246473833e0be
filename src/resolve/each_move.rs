//! Every move of a program, one target argument at a time, with where
//! the move is and what it moves with: what [`uses`](super::uses) goes
//! through.

use super::refs::{describe, Reach, Reached, Refs};
use super::statements::{routine_bodies, walk_items};
use super::usage::{Through, Usage};
use crate::rapid::{Listed, Module, Program, Routine, StatementKind};

/// Where a move is, and what it moves with.
pub(super) struct MoveAt<'a> {
    pub tool: Option<&'a str>,
    pub wobj: Option<&'a str>,
    pub instruction: &'a str,
    pub routine: &'a str,
    pub line: u32,
    pub file: usize,
    pub offset: usize,
    /// A move by name of a batch the fast lane read: the batch's number,
    /// the move's place in it and the batch's length.
    pub run_move: Option<(usize, usize, usize)>,
}

impl MoveAt<'_> {
    pub(super) fn usage(&self, through: Through) -> Usage {
        Usage {
            through,
            tool: self.tool.map(str::to_string),
            wobj: self.wobj.map(str::to_string),
            instruction: self.instruction.to_string(),
            routine: self.routine.to_string(),
            line: self.line,
            file: self.file,
            offset: self.offset,
        }
    }
}

/// Every target argument of every move instruction (ToPoint, and the
/// CirPoint of circular moves) with its module's name and where the move
/// is: the statements of every routine, and the moves by name of the
/// runs (a run's literals are reached by their own move alone, and left
/// out).
pub(super) fn each_move(program: &Program, visit: &mut dyn FnMut(&str, Reach, &MoveAt)) {
    for module in &program.modules {
        for routine in &module.routines {
            each_move_of(program, module, routine, visit);
        }
    }
}

/// What each move's target arguments reach ([`Refs::targets`]), in the
/// order [`each_move`] visits them: looked up a few routines at a time on
/// every core. A million moves by name are a million lookups among a
/// million names, a cache miss each, and were a tenth of correcting such
/// a program on one core. The routines are taken a group at a time, so
/// that what is held is a group's answers, not a million small vectors
/// (about 80 MB).
pub(super) fn reached_by_routine<'a>(
    program: &'a Program,
    refs: &'a Refs<'a>,
    named: &'a [Named],
) -> impl Iterator<Item = Vec<(Reached, Through)>> + 'a {
    use rayon::prelude::*;
    let routines: Vec<(&Module, &Routine)> = (program.modules.iter())
        .flat_map(|m| m.routines.iter().map(move |r| (m, r)))
        .collect();
    let group = 4 * rayon::current_num_threads().max(1);
    let groups: Vec<Vec<(&Module, &Routine)>> = routines.chunks(group).map(<[_]>::to_vec).collect();
    groups.into_iter().flat_map(move |group| {
        let found: Vec<Vec<Vec<(Reached, Through)>>> = group
            .par_iter()
            .map(|&(module, routine)| {
                let mut out = Vec::new();
                // The run being read, and the targets its moves' names reach.
                let mut run: Option<(usize, Vec<u32>)> = None;
                each_move_of(program, module, routine, &mut |m, reach, at| {
                    let found = refs.targets(reach, (m, at.routine));
                    if let Some((r, k, len)) = at.run_move {
                        if run.as_ref().map(|x| x.0) != Some(r) {
                            keep_named(named, run.take());
                            run = Some((r, vec![NOT_KEPT; len]));
                        }
                        if let (Some((_, kept)), [(Reached::One(i), Through::Direct)]) =
                            (&mut run, found.as_slice())
                        {
                            if let (Some(slot), Ok(i)) = (kept.get_mut(k), u32::try_from(*i)) {
                                *slot = i;
                            }
                        }
                    }
                    out.push(found);
                });
                keep_named(named, run);
                out
            })
            .collect();
        found.into_iter().flatten()
    })
}

/// What a run's moves by name reach, kept for a second walk over the
/// moves: for each move, the one target its name reaches directly, or
/// [`NOT_KEPT`] (anything else: looked up again).
pub type Named = std::sync::OnceLock<Box<[u32]>>;

/// A move whose answer is not kept.
pub const NOT_KEPT: u32 = u32::MAX;

fn keep_named(named: &[Named], run: Option<(usize, Vec<u32>)>) {
    if let Some((r, kept)) = run {
        if let Some(slot) = named.get(r) {
            // A run is in one routine, read once: set at most once.
            let _ = slot.set(kept.into_boxed_slice());
        }
    }
}

/// [`each_move`] in one routine.
fn each_move_of(
    program: &Program,
    module: &Module,
    routine: &Routine,
    visit: &mut dyn FnMut(&str, Reach, &MoveAt),
) {
    for body in routine_bodies(routine) {
        walk_items(program, body, &mut |item| match item {
            Listed::Statement(s) => {
                let StatementKind::Call(call) = &s.kind else {
                    return;
                };
                let Some(m) = call.motion() else { return };
                let tool = m.tool.map(describe);
                let wobj = m.wobj.map(describe);
                let at = MoveAt {
                    tool: tool.as_deref(),
                    wobj: wobj.as_deref(),
                    instruction: &call.name,
                    routine: &routine.name,
                    line: s.pos.line,
                    file: module.file,
                    offset: s.pos.offset,
                    run_move: None,
                };
                for expr in [m.via, m.to].into_iter().flatten() {
                    visit(module.name.as_ref(), Reach::Expr(expr), &at);
                }
            }
            Listed::Batch(batch) => {
                for (k, mv) in batch.moves().enumerate() {
                    let Some(name) = mv.named() else { continue };
                    let at = MoveAt {
                        tool: mv.tool().map(|t| &**t),
                        wobj: mv.wobj().map(|w| &**w),
                        instruction: mv.instruction(),
                        routine: &routine.name,
                        line: mv.line(),
                        file: module.file,
                        offset: mv.offset(),
                        run_move: Some((batch.number(), k, batch.len())),
                    };
                    visit(module.name.as_ref(), Reach::Name(name), &at);
                }
            }
        });
    }
}
