//! Configuration monitoring along the program: whether the controller
//! holds each move to its target's robconf.
//!
//! `ConfL \Off` switches monitoring off for linear and circular moves,
//! `ConfJ \Off` for joint moves, from where it executes until `ConfL \On`
//! (`ConfJ \On`) switches it back; a program starts with both on. So the
//! state at a move is a matter of the path to it: the routine graph is
//! walked from the entry routine (`main`), each call with the state it is
//! made in, and a routine no path from the entry reaches starts a walk of
//! its own with both on (an operator may call it from the pendant; a
//! library module has no entry at all). Such a routine's `ConfL \Off`
//! changes nothing elsewhere.
//!
//! Where paths disagree (a branch or a loop that switches it, a routine
//! called both with it on and off, a late-bound call), the state is
//! [`Monitor::Unsettled`]: the controller may check the robconf there, so a
//! correction takes monitoring as on and says so.
//!
//! Only a program that switches monitoring off somewhere is walked; every
//! other is on everywhere at no cost.

use crate::rapid::{
    motion_signature, Block, Listed, MotionKind, MoveBatch, Program, Routine, RoutineKind,
    Statement, StatementKind,
};
use std::collections::{BTreeMap, HashMap, HashSet};

/// Configuration monitoring at a place of the program, for one kind of
/// move.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Monitor {
    On,
    Off,
    /// On along some paths and off along others: taken as on.
    Unsettled,
}

impl Monitor {
    fn merge(self, other: Monitor) -> Monitor {
        if self == other {
            self
        } else {
            Monitor::Unsettled
        }
    }
}

/// Monitoring of linear and circular moves (`ConfL`) and of joint moves
/// (`ConfJ`) at one place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct State {
    linear: Monitor,
    joint: Monitor,
}

impl State {
    const ON: State = State {
        linear: Monitor::On,
        joint: Monitor::On,
    };

    fn merge(self, other: State) -> State {
        State {
            linear: self.linear.merge(other.linear),
            joint: self.joint.merge(other.joint),
        }
    }

    /// The state that governs a move of `kind`: `None` for moves to
    /// joints or of external axes (no robconf to hold them to).
    fn governing(self, kind: MotionKind) -> Option<Monitor> {
        match kind {
            MotionKind::Linear | MotionKind::Circular => Some(self.linear),
            MotionKind::Joint => Some(self.joint),
            MotionKind::AbsJoint | MotionKind::ExtJoint => None,
        }
    }
}

/// Configuration monitoring at every move of a program.
#[derive(Debug, Clone, Default)]
pub struct Monitoring {
    /// Nothing switches monitoring off: on at every move.
    never_off: bool,
    /// The state at each move statement the parser made a call of, by
    /// (file, byte offset where the instruction starts).
    moves: BTreeMap<(usize, usize), State>,
    /// The state along each run of moves the fast lane holds: by (file,
    /// first move's offset), the last move's offset and the state.
    runs: BTreeMap<(usize, usize), (usize, State)>,
}

impl Monitoring {
    /// Walk `program` from its `entry` routine (case-insensitive).
    pub fn of(program: &Program, entry: &str) -> Monitoring {
        if !switches_off(program) {
            return Monitoring {
                never_off: true,
                ..Monitoring::default()
            };
        }
        let mut walk = Walk {
            program,
            found: Monitoring::default(),
            exits: HashMap::new(),
            stack: Vec::new(),
            reached: HashSet::new(),
        };
        let routines: Vec<(usize, &Routine)> = program
            .modules
            .iter()
            .enumerate()
            .flat_map(|(m, module)| module.routines.iter().map(move |r| (m, r)))
            .filter(|(_, r)| r.kind == RoutineKind::Proc)
            .collect();
        let entry_routine = routines
            .iter()
            .find(|(_, r)| r.name.eq_ignore_ascii_case(entry))
            .copied();
        if let Some((m, r)) = entry_routine {
            walk.routine(m, r, State::ON);
        }
        for (m, r) in routines {
            if !walk.reached.contains(&std::ptr::from_ref(r)) {
                walk.routine(m, r, State::ON);
            }
        }
        walk.found
    }

    /// Monitoring at the move `instruction` that starts at `offset` of
    /// `file`, or that holds a target written there (an inline or derived
    /// target in its arguments): `None` where the instruction holds no
    /// robconf (MoveAbsJ) or is no move.
    pub fn at(&self, file: usize, offset: usize, instruction: &str) -> Option<Monitor> {
        let kind = motion_signature(instruction)?.kind;
        if self.never_off {
            return State::ON.governing(kind);
        }
        let before =
            |(f, o): (usize, usize)| f == file && o <= offset && offset <= o + MAX_MOVE_BYTES;
        let single = self
            .moves
            .range(..=(file, offset))
            .next_back()
            .filter(|(&k, _)| before(k))
            .map(|(&(_, o), &s)| (o, s));
        let run = self
            .runs
            .range(..=(file, offset))
            .next_back()
            .filter(|(&(f, _), &(last, _))| f == file && offset <= last + MAX_MOVE_BYTES)
            .map(|(&(_, o), &(_, s))| (o, s));
        // The nearer of the two that start before `offset` is the move's
        // own.
        let state = match (single, run) {
            (Some((a, s)), Some((b, r))) => Some(if b > a { r } else { s }),
            (s, r) => s.or(r).map(|(_, s)| s),
        };
        state.unwrap_or(State::ON).governing(kind)
    }

    /// Whether the program switches monitoring off anywhere.
    pub fn ever_off(&self) -> bool {
        !self.never_off
    }

    /// The moves where the walk cannot settle the monitoring that governs
    /// them, as (file, offset, instruction): taken as on.
    pub fn unsettled(&self, program: &Program) -> Vec<(usize, usize, String)> {
        let mut out: Vec<(usize, usize, String)> = Vec::new();
        for (&(file, offset), state) in &self.moves {
            if let Some(name) = instruction_at(program, file, offset) {
                let gov = motion_signature(&name).and_then(|s| state.governing(s.kind));
                if gov == Some(Monitor::Unsettled) {
                    out.push((file, offset, name));
                }
            }
        }
        out.sort();
        out
    }
}

/// A move instruction's arguments run at most this far past its start
/// (bytes): a target written inside a run's last move still finds it.
const MAX_MOVE_BYTES: usize = 4096;

/// The instruction's name at `offset` of `file`: its first word.
fn instruction_at(program: &Program, file: usize, offset: usize) -> Option<String> {
    let src = program.source(file).get(offset..)?;
    let end = src
        .iter()
        .position(|b| !(b.is_ascii_alphanumeric() || *b == b'_'))
        .unwrap_or(src.len());
    std::str::from_utf8(&src[..end]).ok().map(str::to_string)
}

/// Whether any routine switches monitoring off (`ConfL \Off`, `ConfJ
/// \Off`).
fn switches_off(program: &Program) -> bool {
    let mut off = false;
    for module in &program.modules {
        for routine in &module.routines {
            super::statements::walk_calls(&routine.body, &mut |call, _| {
                if switch_of(call).is_some_and(|(_, on)| !on) {
                    off = true;
                }
            });
        }
    }
    off
}

/// `ConfL \Off` and the like: (linear?, on?).
fn switch_of(call: &crate::rapid::Call) -> Option<(bool, bool)> {
    let name = call.name.as_ref();
    let linear = if name.eq_ignore_ascii_case("ConfL") {
        true
    } else if name.eq_ignore_ascii_case("ConfJ") {
        false
    } else {
        return None;
    };
    Some((linear, call.optional("Off").is_none()))
}

/// Calls followed this deep; deeper ones leave the state unsettled.
const MAX_DEPTH: usize = 64;

struct Walk<'p> {
    program: &'p Program,
    found: Monitoring,
    /// A routine's state at its end for a state at its start.
    exits: HashMap<(*const Routine, StateKey), State>,
    stack: Vec<*const Routine>,
    /// Every routine walked from some root.
    reached: HashSet<*const Routine>,
}

/// A [`State`] as a hash key.
type StateKey = (u8, u8);

fn key(s: State) -> StateKey {
    let k = |m: Monitor| match m {
        Monitor::On => 0,
        Monitor::Off => 1,
        Monitor::Unsettled => 2,
    };
    (k(s.linear), k(s.joint))
}

impl<'p> Walk<'p> {
    /// Walk a routine entered in `state`; its state at the end.
    fn routine(&mut self, module: usize, r: &'p Routine, state: State) -> State {
        let id = std::ptr::from_ref(r);
        self.reached.insert(id);
        if let Some(exit) = self.exits.get(&(id, key(state))) {
            return *exit;
        }
        if self.stack.contains(&id) || self.stack.len() >= MAX_DEPTH {
            return state.merge(unsettled_where_switched(state));
        }
        self.stack.push(id);
        let exit = self.list(module, &r.body, state);
        self.stack.pop();
        self.exits.insert((id, key(state)), exit);
        exit
    }

    fn list(&mut self, module: usize, list: &'p Block, mut state: State) -> State {
        for item in self.program.items(list) {
            state = match item {
                Listed::Statement(s) => self.statement(module, s, state),
                Listed::Batch(b) => self.batch(b, state),
            };
        }
        state
    }

    /// Moves the fast lane read one after another: one state for all,
    /// recorded for the stretch they span.
    fn batch(&mut self, b: MoveBatch<'p>, state: State) -> State {
        if let Some((f, first, last)) = b.span() {
            let entry = self.found.runs.entry((f, first)).or_insert((last, state));
            entry.1 = entry.1.merge(state);
        }
        state
    }

    fn statement(&mut self, module: usize, s: &'p Statement, state: State) -> State {
        match &s.kind {
            StatementKind::Call(call) => {
                if let Some((linear, on)) = switch_of(call) {
                    let m = if on { Monitor::On } else { Monitor::Off };
                    return if linear {
                        State { linear: m, ..state }
                    } else {
                        State { joint: m, ..state }
                    };
                }
                if call.motion().is_some() {
                    self.record(self.file(module), s.pos.offset, state);
                    return state;
                }
                if call.late_bound {
                    return unsettled_where_switched(state);
                }
                match self.find(module, &call.name) {
                    Some((m, r)) => self.routine(m, r, state),
                    None => state,
                }
            }
            StatementKind::If {
                branches,
                otherwise,
            } => {
                let mut out: Option<State> = None;
                for (_, body) in branches {
                    let after = self.list(module, body, state);
                    out = Some(out.map_or(after, |o| o.merge(after)));
                }
                let after = match otherwise {
                    Some(body) => self.list(module, body, state),
                    None => state,
                };
                out.map_or(after, |o| o.merge(after))
            }
            StatementKind::CompactIf { then, .. } => {
                let after = self.statement(module, then, state);
                state.merge(after)
            }
            StatementKind::For { body, .. } | StatementKind::While { body, .. } => {
                // A body run any number of times: walked until the state
                // at its start stops changing (twice at most: a merge only
                // loses what it knew).
                let mut at_start = state;
                for _ in 0..3 {
                    let after = self.list(module, body, at_start);
                    let next = at_start.merge(after);
                    if next == at_start {
                        break;
                    }
                    at_start = next;
                }
                at_start
            }
            StatementKind::Test { cases, default, .. } => {
                let mut out = match default {
                    Some(body) => self.list(module, body, state),
                    None => state,
                };
                for (_, body) in cases {
                    out = out.merge(self.list(module, body, state));
                }
                out
            }
            _ => state,
        }
    }

    fn record(&mut self, file: usize, offset: usize, state: State) {
        self.found
            .moves
            .entry((file, offset))
            .and_modify(|s| *s = s.merge(state))
            .or_insert(state);
    }

    fn file(&self, module: usize) -> usize {
        self.program.modules.get(module).map_or(0, |m| m.file)
    }

    /// The procedure a call in `module` names: the module's own first,
    /// then a global one.
    fn find(&self, module: usize, name: &str) -> Option<(usize, &'p Routine)> {
        let program = self.program;
        let own = program.modules.get(module).and_then(|m| {
            m.routines
                .iter()
                .find(|r| r.kind == RoutineKind::Proc && r.name.eq_ignore_ascii_case(name))
        });
        if let Some(r) = own {
            return Some((module, r));
        }
        program.modules.iter().enumerate().find_map(|(mi, m)| {
            m.routines
                .iter()
                .find(|r| {
                    r.kind == RoutineKind::Proc && !r.local && r.name.eq_ignore_ascii_case(name)
                })
                .map(|r| (mi, r))
        })
    }
}

/// After a call the walk cannot follow: every kind the program switches
/// may have been switched.
fn unsettled_where_switched(state: State) -> State {
    State {
        linear: state.linear.merge(Monitor::Unsettled),
        joint: state.joint.merge(Monitor::Unsettled),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Monitoring at the move starting at the first occurrence of `at`.
    fn at(src: &str, at: &str) -> Option<Monitor> {
        let program = crate::rapid::parse("a.mod", src.as_bytes()).unwrap();
        let offset = src.find(at).unwrap();
        let name = at.split_whitespace().next().unwrap();
        Monitoring::of(&program, "main").at(0, offset, name)
    }

    const CELL: &str = "MODULE A
  PROC main()
    MoveL pBefore, v100, fine, tool0;
    rPlace;
    MoveL pAfter, v100, fine, tool0;
  ENDPROC
  PROC rPlace()
    ConfL\\Off;
    MoveJ pJoint, v100, fine, tool0;
    MoveL pOff, v100, fine, tool0;
    IF di1=1 THEN
      ConfL\\On;
    ENDIF
    MoveL pMaybe, v100, fine, tool0;
    ConfL\\On;
  ENDPROC
  PROC rService()
    ConfJ\\Off;
    MoveJ pService, v100, fine, tool0;
  ENDPROC
ENDMODULE
";

    #[test]
    fn monitoring_follows_the_walk_from_main() {
        assert_eq!(at(CELL, "MoveL pBefore"), Some(Monitor::On));
        assert_eq!(at(CELL, "MoveL pOff"), Some(Monitor::Off));
        // ConfL governs linear moves only.
        assert_eq!(at(CELL, "MoveJ pJoint"), Some(Monitor::On));
        assert_eq!(at(CELL, "MoveL pMaybe"), Some(Monitor::Unsettled));
        assert_eq!(at(CELL, "MoveL pAfter"), Some(Monitor::On));
        // A routine never called switches only its own moves.
        assert_eq!(at(CELL, "MoveJ pService"), Some(Monitor::Off));
    }

    #[test]
    fn a_routine_called_both_ways_is_unsettled() {
        let src = "MODULE A
  PROC main()
    rMove;
    ConfL\\Off;
    rMove;
  ENDPROC
  PROC rMove()
    MoveL pMove, v100, fine, tool0;
  ENDPROC
ENDMODULE
";
        assert_eq!(at(src, "MoveL pMove"), Some(Monitor::Unsettled));
        let never = src.replace("ConfL\\Off;", "ConfL\\On;");
        assert_eq!(at(&never, "MoveL pMove"), Some(Monitor::On));
    }
}
