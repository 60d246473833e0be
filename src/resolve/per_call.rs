//! What each call of a procedure passes for its target, tool and work
//! object parameters. A procedure `PROC Go(robtarget ToPoint, PERS
//! tooldata Tool)` called as `Go p1, tA;` and `Go p2, tB;` moves to p1
//! with tA and to p2 with tB: the target a call passes goes with the
//! frames of the same call, never with another call's (pairing every
//! passed target with every passed tool would correct, or refuse, targets
//! in frames the program never moves them in). The settled parameters of
//! [`params`](super::params) and [`frame_vars`](super::frame_vars) are
//! read from the same calls.

use crate::rapid::{Expr, Program, RoutineKind};
use std::collections::{HashMap, HashSet};

/// A procedure's parameters the calls can settle, and each call's
/// arguments for them.
pub(super) struct ProcCalls {
    /// Its tooldata and wobjdata parameters (lower case), each with
    /// whether it is a tool.
    pub frames: Vec<(String, bool)>,
    /// Its required robtarget and jointtarget parameters (lower case).
    pub targets: Vec<String>,
    pub calls: Vec<CallArgs>,
}

/// One call's arguments.
pub(super) struct CallArgs {
    /// For each frame parameter, the declared tool or work object it
    /// passes as written (the default, `tool0`/`wobj0`, for an optional
    /// one left out); `None`: anything else, which only the run decides.
    pub frames: Vec<Option<String>>,
    /// For each target parameter, the plain name it passes, as written.
    pub targets: Vec<Option<String>>,
}

impl ProcCalls {
    /// The place among [`Self::frames`] of the frame parameter `name`, if
    /// every call settles it.
    pub fn settled_frame(&self, name: &str) -> Option<usize> {
        let k = self
            .frames
            .iter()
            .position(|(p, _)| p.eq_ignore_ascii_case(name))?;
        let all = !self.calls.is_empty() && self.calls.iter().all(|c| c.frames[k].is_some());
        all.then_some(k)
    }
}

/// The tool and work object names of the program, lower case, with the
/// defaults: (tools, work objects).
pub(super) fn declared_frames(program: &Program) -> (HashSet<String>, HashSet<String>) {
    let tools = program
        .tools()
        .iter()
        .map(|t| t.name.to_ascii_lowercase())
        .chain(["tool0".to_string()])
        .collect();
    let wobjs = program
        .wobjs()
        .iter()
        .map(|w| w.name.to_ascii_lowercase())
        .chain(["wobj0".to_string()])
        .collect();
    (tools, wobjs)
}

/// Every procedure with target or frame parameters, with its calls, by
/// lower-case name. `None` where some call by a name computed at run time
/// (`%name% ...`) passes arguments: any procedure's parameters may then
/// be what it passes, and none is settled by the calls seen.
///
/// A frame parameter that shares its name with declared data is left to
/// the data's rules (one name could not tell them apart), and so is left
/// out.
pub(super) fn proc_calls(program: &Program) -> Option<HashMap<String, ProcCalls>> {
    let (tools, wobjs) = declared_frames(program);
    // Per procedure: (frame parameter, its place among the required ones
    // or None for an optional one), (target parameter, its place).
    type Places = (Vec<Option<usize>>, Vec<usize>);
    let mut procs: HashMap<String, (ProcCalls, Places)> = HashMap::new();
    for routine in program.modules.iter().flat_map(|m| &m.routines) {
        if routine.kind != RoutineKind::Proc {
            continue;
        }
        let mut pc = ProcCalls {
            frames: Vec::new(),
            targets: Vec::new(),
            calls: Vec::new(),
        };
        let mut places: Places = (Vec::new(), Vec::new());
        let mut required = 0;
        for p in routine.params.iter().filter(|p| p.array_dims == 0) {
            let place = (!p.optional).then_some(required);
            required += usize::from(!p.optional);
            let t = p.type_name.to_ascii_lowercase();
            let name = p.name.to_ascii_lowercase();
            let taken = tools.contains(&name) || wobjs.contains(&name);
            match t.as_str() {
                "tooldata" | "wobjdata" if !taken => {
                    pc.frames.push((name, t == "tooldata"));
                    places.0.push(place);
                }
                "robtarget" | "jointtarget" if !p.optional => {
                    pc.targets.push(name);
                    places.1.push(place.unwrap_or_default());
                }
                _ => {}
            }
        }
        if !pc.frames.is_empty() || !pc.targets.is_empty() {
            procs.insert(routine.name.to_ascii_lowercase(), (pc, places));
        }
    }
    if procs.is_empty() {
        return Some(HashMap::new());
    }
    let bound = super::calls::each_call(program, &mut |call| {
        let Some((pc, (frame_places, target_places))) =
            procs.get_mut(&*call.name.to_ascii_lowercase())
        else {
            return;
        };
        let args: Vec<&Expr> = call.positional().collect();
        let frames = pc
            .frames
            .iter()
            .zip(frame_places.iter())
            .map(|((name, is_tool), place)| {
                let (declared, default) = match is_tool {
                    true => (&tools, "tool0"),
                    false => (&wobjs, "wobj0"),
                };
                let value = match place {
                    Some(k) => args.get(*k).copied().map(Some),
                    None => match call.optional(name) {
                        None => Some(None),
                        Some(a) => a.value.as_ref().map(Some),
                    },
                };
                match value {
                    Some(None) => Some(default.to_string()),
                    Some(Some(Expr::Name(n))) if declared.contains(&n.to_ascii_lowercase()) => {
                        Some(n.to_string())
                    }
                    _ => None,
                }
            })
            .collect();
        let targets = target_places
            .iter()
            .map(|k| match args.get(*k) {
                Some(Expr::Name(n)) => Some(n.to_string()),
                _ => None,
            })
            .collect();
        pc.calls.push(CallArgs { frames, targets });
    });
    bound.then(|| procs.into_iter().map(|(k, (pc, _))| (k, pc)).collect())
}

/// The frame parameters (routine, parameter; lower case) that some call
/// leaves to the run, or that no call passes: a move with one moves with a
/// tool or work object only the run knows, so its targets are left alone.
pub fn unsettled_frame_parameters(program: &Program) -> HashSet<(String, String)> {
    let mut out = HashSet::new();
    match proc_calls(program) {
        Some(procs) => {
            for (routine, pc) in &procs {
                for (name, _) in &pc.frames {
                    if pc.settled_frame(name).is_none() {
                        out.insert((routine.clone(), name.clone()));
                    }
                }
            }
        }
        // A call by a computed name passes arguments: no frame parameter
        // is settled (those named as declared data are the data's).
        None => {
            let (tools, wobjs) = declared_frames(program);
            for routine in program.modules.iter().flat_map(|m| &m.routines) {
                for p in &routine.params {
                    let t = p.type_name.to_ascii_lowercase();
                    let name = p.name.to_ascii_lowercase();
                    let taken = tools.contains(&name) || wobjs.contains(&name);
                    if (t == "tooldata" || t == "wobjdata") && !taken {
                        out.insert((routine.name.to_ascii_lowercase(), name));
                    }
                }
            }
        }
    }
    out
}

/// The procedures whose moves pair each target with the frames of the
/// call that passes it: those with a frame parameter every call settles,
/// to more than one name (one name is the same for every call, and
/// [`frame_variables`](super::frame_variables) gives it).
pub(super) struct Pairing {
    procs: HashMap<String, ProcCalls>,
}

/// One move's pairing: its procedure's calls, and which of its frame
/// parameters the move's tool and work object are.
pub(super) struct MovePairing<'a> {
    procs: &'a ProcCalls,
    tool: Option<usize>,
    wobj: Option<usize>,
}

impl Pairing {
    pub fn new(program: &Program) -> Pairing {
        let mut procs = proc_calls(program).unwrap_or_default();
        procs.retain(|_, pc| {
            pc.frames.iter().enumerate().any(|(k, (name, _))| {
                pc.settled_frame(name).is_some() && {
                    let mut names: Vec<String> = pc
                        .calls
                        .iter()
                        .filter_map(|c| c.frames[k].as_deref())
                        .map(str::to_ascii_lowercase)
                        .collect();
                    names.sort();
                    names.dedup();
                    names.len() > 1
                }
            })
        });
        Pairing { procs }
    }

    pub fn is_empty(&self) -> bool {
        self.procs.is_empty()
    }

    /// The pairing of a move in `routine` with this tool and work object
    /// (as written), where either is a parameter every call settles.
    pub fn of_move(
        &self,
        routine: &str,
        tool: Option<&str>,
        wobj: Option<&str>,
    ) -> Option<MovePairing<'_>> {
        let procs = self.procs.get(&routine.to_ascii_lowercase())?;
        let tool = tool.and_then(|t| procs.settled_frame(t));
        let wobj = wobj.and_then(|w| procs.settled_frame(w));
        (tool.is_some() || wobj.is_some()).then_some(MovePairing { procs, tool, wobj })
    }
}

impl<'a> MovePairing<'a> {
    pub fn calls(&self) -> &'a [CallArgs] {
        &self.procs.calls
    }

    /// The places among the procedure's target parameters of those the
    /// move's argument reads (`read`: the names it reads, as written).
    pub fn target_places(&self, read: &[&str]) -> Vec<usize> {
        (self.procs.targets.iter().enumerate())
            .filter(|(_, p)| read.iter().any(|r| r.eq_ignore_ascii_case(p)))
            .map(|(k, _)| k)
            .collect()
    }

    /// The tool and work object of the move when `call` runs it: the
    /// call's for a parameter, the move's own (as written) otherwise.
    pub fn frames<'c>(
        &self,
        call: &'c CallArgs,
        own: (Option<&'c str>, Option<&'c str>),
    ) -> (Option<&'c str>, Option<&'c str>) {
        (
            match self.tool {
                Some(k) => call.frames[k].as_deref(),
                None => own.0,
            },
            match self.wobj {
                Some(k) => call.frames[k].as_deref(),
                None => own.1,
            },
        )
    }
}
