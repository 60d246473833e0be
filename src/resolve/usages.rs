//! Every target's uses: the walk over the program's moves that says, for
//! each target, the instructions that move to it and their tool and work
//! object ([`Uses`]), looked up once in a [`MoveLookup`].

use super::dataflow;
use super::each_move::{self, each_move, reached_by_routine};
use super::frame_vars::frame_variables;
use super::params::settled_parameters;
use super::per_call;
use super::refs::{Reach, Reached, Refs};
use super::usage::{Through, Usage};
use super::uses::{offset32, Packed, Site, Uses, UsesBuilder};
use crate::rapid::targets::TargetIndex;
use crate::rapid::{Expr, Program, TargetKind};
use std::collections::HashMap;

/// Every target's uses (see [`Uses`]): inline targets have the one
/// instruction they are written in; declared targets (and array elements
/// with a literal index, or every element of an array its index reads at
/// run time) every move that names them; the bases of a derived target
/// (`Offs(p10, ...)`) the moves to the derived pose, since the offset is
/// taken in the same frame.
pub fn uses(program: &Program) -> Uses<'_> {
    uses_with(program, &MoveLookup::new(program))
}

/// What a move's target argument is looked up in: the targets a move can
/// name by identifier, and what variables and settled parameters are
/// assigned from. A job that goes over the moves more than once ([`uses`],
/// then [`each_move_instruction`]) builds it once: for a million declared
/// targets each build was a second on one core.
pub struct MoveLookup<'p> {
    pub(super) index: TargetIndex<'p>,
    pub(super) aliases: HashMap<String, Vec<String>>,
    /// What the moves by name of each run reach, kept by the first walk
    /// ([`uses_with`]) for the next ([`each_move_instruction_with`]): a
    /// million names looked up among a million targets, a cache miss
    /// each, once instead of twice.
    pub(super) named: Vec<each_move::Named>,
}

impl<'p> MoveLookup<'p> {
    pub fn new(program: &'p Program) -> MoveLookup<'p> {
        MoveLookup {
            index: move_index(program),
            aliases: aliases_and_parameters(program),
            named: (0..program.move_batches())
                .map(|_| Default::default())
                .collect(),
        }
    }

    /// How many runs' answers are kept.
    pub fn runs_kept(&self) -> usize {
        self.named.iter().filter(|n| n.get().is_some()).count()
    }
}

/// [`uses`], looked up in `lookup` (built for `program`).
pub fn uses_with<'p>(program: &'p Program, lookup: &MoveLookup<'p>) -> Uses<'p> {
    let (index, aliases) = (&lookup.index, &lookup.aliases);
    let refs = Refs::new(program, index, aliases);
    let mut b = UsesBuilder::new(program.targets());
    // A tool or work object assigned at run time moves with each tool or
    // work object it is assigned from.
    let frame_vars = frame_variables(program);
    let sources = |name: Option<&str>| match (name, frame_vars.is_empty()) {
        (Some(n), false) => frame_vars.get(&n.to_ascii_lowercase()),
        _ => None,
    };
    let pairing = per_call::Pairing::new(program);
    let mut reached_all = reached_by_routine(program, &refs, &lookup.named);
    each_move(program, &mut |module, reach, at| {
        let reached = reached_all.next().unwrap_or_default();
        if reached.is_empty() {
            return;
        }
        // A tool or work object that is a parameter the calls pass
        // differently: each target with the frames of the calls that pass
        // it (or of every call, for a target no call passes).
        let paired = match pairing.is_empty() {
            true => None,
            false => pairing.of_move(at.routine, at.tool, at.wobj),
        };
        if let Some(mp) = paired {
            let read = read_names(reach);
            let places = mp.target_places(&read);
            let passed: Vec<Vec<usize>> = (mp.calls().iter())
                .map(|c| {
                    (places.iter())
                        .filter_map(|&k| c.targets[k].as_deref())
                        .filter_map(|n| refs.passed(n, (module, at.routine)))
                        .collect()
                })
                .collect();
            for (reached, through) in &reached {
                let by = |c: usize| match reached {
                    Reached::One(i) => passed[c].contains(i),
                    Reached::All(_) => false,
                };
                let passing = (0..passed.len()).any(by);
                // Each (tool, work object) once: calls passing the same
                // frames make one use.
                let mut pairs: Vec<(u32, u32)> = Vec::new();
                for (c, call) in mp.calls().iter().enumerate() {
                    if passing && !by(c) {
                        continue;
                    }
                    let (tool, wobj) = mp.frames(call, (at.tool, at.wobj));
                    let expand = |n: Option<&'_ str>| -> Vec<Option<String>> {
                        match sources(n) {
                            Some(list) => list.iter().map(|s| Some(s.clone())).collect(),
                            None => vec![n.map(str::to_string)],
                        }
                    };
                    for t in expand(tool) {
                        for w in expand(wobj) {
                            let (t, w) = (b.name(t.as_deref()), b.name(w.as_deref()));
                            if pairs.contains(&(t, w)) {
                                continue;
                            }
                            pairs.push((t, w));
                            let site = Site {
                                through: Packed::from(*through),
                                tool: t,
                                wobj: w,
                                instruction: b.name(Some(at.instruction)),
                                routine: b.name(Some(at.routine)),
                                line: at.line,
                                file: at.file as u32,
                                offset: offset32(at.offset),
                            };
                            let s = b.site(site);
                            match reached {
                                Reached::One(i) => b.reach(*i, s),
                                Reached::All(r) => b.reach_all(r.clone(), s),
                            }
                        }
                    }
                }
            }
            return;
        }
        let (one_tool, one_wobj) = ([at.tool], [at.wobj]);
        let (many_tools, many_wobjs): (Vec<Option<&str>>, Vec<Option<&str>>);
        let tools: &[Option<&str>] = match sources(at.tool) {
            Some(list) => {
                many_tools = list.iter().map(|s| Some(s.as_str())).collect();
                &many_tools
            }
            None => &one_tool,
        };
        let wobjs: &[Option<&str>] = match sources(at.wobj) {
            Some(list) => {
                many_wobjs = list.iter().map(|s| Some(s.as_str())).collect();
                &many_wobjs
            }
            None => &one_wobj,
        };
        for &tool in tools {
            for &wobj in wobjs {
                let mut site = Site {
                    through: Packed::from(Through::Direct),
                    tool: b.name(tool),
                    wobj: b.name(wobj),
                    instruction: b.name(Some(at.instruction)),
                    routine: b.name(Some(at.routine)),
                    line: at.line,
                    file: at.file as u32,
                    offset: offset32(at.offset),
                };
                for (reached, through) in &reached {
                    site.through = Packed::from(*through);
                    let s = b.site(site);
                    match reached {
                        Reached::One(i) => b.reach(*i, s),
                        Reached::All(r) => b.reach_all(r.clone(), s),
                    }
                }
            }
        }
    });
    b.finish()
}

/// The plain names a move's target argument reads: the name itself, or
/// the names a derived expression is given (`Offs(ToPoint, 0, 0, 50)`).
fn read_names<'e>(reach: Reach<'e>) -> Vec<&'e str> {
    match reach {
        Reach::Name(n) => vec![n],
        Reach::Expr(Expr::Name(n)) => vec![&**n],
        Reach::Expr(Expr::Call(c)) => (c.args.iter())
            .filter(|a| !a.optional)
            .filter_map(|a| a.value.as_ref().and_then(Expr::as_name))
            .collect(),
        Reach::Expr(_) => Vec::new(),
    }
}

/// The targets a move can name: every one but inline literals and
/// derived expressions (whose bases are reached instead).
fn move_index(program: &Program) -> TargetIndex<'_> {
    program.target_index(|t| {
        t.kind != TargetKind::Inline
            && (t.kind != TargetKind::Derived || t.written_with_expressions())
    })
}

/// What a variable is assigned from ([`dataflow::aliases`]), and what
/// the calls of a routine pass for its settled robtarget parameters
/// ([`settled_parameters`], by `routine/parameter`).
fn aliases_and_parameters(program: &Program) -> HashMap<String, Vec<String>> {
    let mut aliases = dataflow::aliases(program);
    aliases.extend(settled_parameters(program));
    aliases
}

/// For every target of the program (by its number), the motion
/// instructions that move to it with their tool and work object: [`uses`]
/// as a map of [`Usage`]s, for callers that walk few targets.
pub fn usages(program: &Program) -> HashMap<usize, Vec<Usage>> {
    uses(program).to_map()
}

/// The moves that name a derived target declared as data (`CONST
/// robtarget p20 := Offs(p10, 0, 0, 50);` and `MoveL p20, ...`), by its
/// index: [`usages`] leaves them out (the base's correction carries the
/// derived pose), but a listing says what the target is moved with.
pub fn declared_derived_usages(program: &Program) -> HashMap<usize, Vec<Usage>> {
    let by_id: HashMap<String, usize> = program
        .targets()
        .one_by_one_all()
        .filter(|(_, t)| {
            t.kind == TargetKind::Derived
                && !t.written_with_expressions()
                && t.instruction.is_none()
        })
        .map(|(i, t)| (t.id.to_ascii_lowercase(), i))
        .collect();
    let mut out: HashMap<usize, Vec<Usage>> = HashMap::new();
    if by_id.is_empty() {
        return out;
    }
    each_move(program, &mut |module, reach, at| {
        let name = match reach {
            Reach::Expr(e) => e.as_name(),
            Reach::Name(n) => Some(n),
        };
        let Some(name) = name else { return };
        let found = by_id
            .get(&name.to_ascii_lowercase())
            .or_else(|| by_id.get(&format!("{module}:{name}").to_ascii_lowercase()));
        if let Some(&i) = found {
            out.entry(i).or_default().push(at.usage(Through::Direct));
        }
    });
    out
}
