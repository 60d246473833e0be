//! The program walker: RAPID executed as far as timing needs it (routine
//! calls, control flow, data), each move timed on the nominal robot. Split
//! by concern: the walker and its statements (here), expressions and
//! values ([`eval`]), motion instructions ([`moves`]), whether a move's
//! target can be reached at all ([`check`]), instructions that take no
//! time ([`instant`]).

mod check;
mod decls;
mod ends;
mod eval;
mod for_loop;
mod instant;
mod moves;
mod poses;
mod reach;
mod settled;

use decls::{Decl, DeclList, RunDecls};
pub use poses::TargetPoses;
pub(crate) use reach::ReachAhead;
use settled::{Settled, SettledSlot};

use instant::is_instant_builtin;

use super::bounds::{FALLBACK_SPEED, MAX_DEPTH, STACK_RED_ZONE, STACK_SEGMENT, STEP_BUDGET};
use super::timing::*;
use super::Schedule;
use crate::error::{Error, ErrorKind, Errors, Remedy, Result};
use crate::rapid::{
    self, Arg, BinaryOp, Block, Call, DataDecl, Expr, FunctionCall, Listed, Motion, MotionKind,
    MoveBatch, NoCase, Program, Routine, RoutineKind, Statement, StatementKind, TargetKind,
    UnaryOp,
};
use crate::resolve::{target_pose, Frames};
use crate::robot::frames::{flange_of_target, target_of_flange};
use crate::robot::{Joints, RobConf, Robot, ToolFrame, WobjFrames};
use nalgebra::{Isometry3, Vector3};
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

/// Targets never reached that the walk's note names (the rest counted).
const SHOWN_MISSED: usize = 8;

/// `f` of `name` in lower case, lowered on the stack where it is short
/// (a lookup at every turn of a loop need not allocate).
pub(super) fn with_lower<R>(name: &str, f: impl FnOnce(&str) -> R) -> R {
    let mut buf = [0u8; 64];
    if let Some(b) = buf.get_mut(..name.len()) {
        b.copy_from_slice(name.as_bytes());
        b.make_ascii_lowercase();
        // Lowering ASCII letters keeps UTF-8 valid.
        if let Ok(key) = std::str::from_utf8(b) {
            return f(key);
        }
    }
    f(&name.to_ascii_lowercase())
}

/// Maps looked up at every statement of a walk (names: a fast hash).
type FastMap<K, V> = foldhash::HashMap<K, V>;

/// A robtarget value met in the walk.
#[derive(Debug, Clone)]
pub(super) struct Rob {
    /// TCP in the work object (the robtarget's own frame).
    pub(super) pose: Isometry3<f64>,
    pub(super) conf: RobConf,
    /// The literal target this value is (index into `Program::targets`):
    /// where set, `pose` and `conf` are that literal's as read
    /// ([`crate::resolve::target_pose`]).
    pub(super) id: Option<usize>,
    /// The derived target that computed it (`Offs(...)`).
    pub(super) derived: Option<usize>,
    /// Literal targets it was derived from.
    pub(super) bases: Vec<usize>,
}

#[derive(Debug, Clone)]
pub(super) enum Value {
    Num(f64),
    Bool(bool),
    Str(String),
    Rob(Box<Rob>),
    /// Joint angles (rad) and the jointtarget literal they are.
    Joint(Box<(Joints, Option<usize>)>),
    Agg(Vec<Value>),
    /// A name the walk does not evaluate (tooldata, wobjdata, speeddata,
    /// signals): resolved by the instruction that uses it.
    Ref(String),
    Unknown,
}

impl Value {
    fn num(&self) -> Option<f64> {
        match self {
            Value::Num(v) => Some(*v),
            _ => None,
        }
    }
    fn boolean(&self) -> Option<bool> {
        match self {
            Value::Bool(b) => Some(*b),
            _ => None,
        }
    }
}

pub(super) enum Flow {
    Normal,
    Return(Value),
    Exit,
    Goto(String),
}

pub(super) struct Frame<'p> {
    module: usize,
    routine: Option<&'p Routine>,
    vars: FastMap<String, Value>,
}

/// Where the robot is.
pub(super) struct Arm {
    flange: Isometry3<f64>,
    joints: Option<Joints>,
    conf: RobConf,
}

pub(super) struct Walker<'p> {
    pub(super) program: &'p Program,
    pub(super) robot: &'p Robot,
    pub(super) frames: Frames,
    /// Non-inline robtargets by identifier (compared without case).
    pub(super) target_ids: crate::rapid::targets::TargetIndex<'p>,
    pub(super) joint_ids: FastMap<String, usize>,
    /// Whether some id of `target_ids` or `joint_ids` carries its routine
    /// (`r1/pa`) or its module (`m:pa`): only then does a name's lookup
    /// build those keys.
    pub(super) ids_scoped: bool,
    pub(super) ids_qualified: bool,
    /// (file, byte offset) of a derived expression → its target.
    pub(super) derived_at: HashMap<(usize, usize), usize>,
    /// Module data by lower-case name: (module, declaration).
    decls: FastMap<NoCase<'p>, DeclList<'p>>,
    /// The declaration runs, in the order of their targets.
    run_decls: Vec<RunDecls<'p>>,
    /// Targets of declaration runs whose name has another declaration.
    pub(super) shadowed: std::collections::HashSet<usize>,
    /// The target after the last declaration of a run a name was found
    /// to be (`usize::MAX`: none): asked first ([`Walker::module_decl`]).
    pub(super) next_decl: std::cell::Cell<usize>,
    /// Procedures and functions by lower-case name: (module, routine).
    pub(super) routines: FastMap<String, Vec<(usize, &'p Routine)>>,
    /// Robtarget variables assigned during the walk (module data).
    pub(super) globals: HashMap<String, Value>,
    /// Routines being walked (by identity: two modules may each have a
    /// LOCAL routine of one name).
    pub(super) stack: Vec<*const Routine>,
    pub(super) steps: u64,
    pub(super) clock: f64,
    pub(super) robot_free: f64,
    pub(super) arm: Arm,
    /// VelSet: override (fraction) and max TCP speed (mm/s).
    pub(super) velset: (f64, f64),
    pub(super) schedule: Schedule,
    pub(super) joint_schedule: Schedule,
    /// Visits of bases through derived targets: (base, minutes).
    pub(super) base_visits: Vec<(usize, f64)>,
    /// The target a move's literal is read into ([`Self::target_value`]).
    pub(super) slot: std::cell::RefCell<crate::rapid::Target>,
    pub(super) notes: Vec<String>,
    /// Targets that cannot be timed (not finite, out of reach), each once:
    /// the walk goes on to find them all, and the estimate is refused.
    pub(super) errors: Errors,
    /// Places (`file:line:col`) of the targets in `errors`.
    pub(super) failed: HashSet<String>,
    /// Flange poses (bits) known to be reachable: one IK per pose.
    pub(super) reachable: foldhash::HashSet<[u64; 7]>,
    pub(super) noted: HashSet<String>,
    pub(super) evaluating: HashSet<String>,
    /// The last move's speed and frames by their names, reused by the
    /// next move naming them alike where no variable can shadow a name
    /// (see [`Walker::static_names`]): a CAM program names the same ones
    /// a million times.
    pub(super) last_speed: Option<(NamesAt, MoveSpeed)>,
    pub(super) last_frames: Option<(NamesAt, std::rc::Rc<(ToolFrame, WobjFrames)>)>,
    /// Flange poses whose reach is asked on another core, and the
    /// robconf of their targets; `None`: asked at each move.
    pub(super) deferred: Option<ReachAhead>,
    /// The pairs of tool and work object the deferred poses were placed
    /// by, by number from 1 ([`crate::schedule::ColdJoints`]).
    pub(super) pairs: Vec<(ToolFrame, WobjFrames)>,
    /// The last move's frames and their pair's number.
    pub(super) last_pair: Option<(std::rc::Rc<(ToolFrame, WobjFrames)>, u32)>,
    /// Each robtarget's pose and robconf, read before the walk on every
    /// core ([`TargetPoses::read`]); empty: read as the walk meets them.
    pub(super) poses: std::sync::Arc<TargetPoses>,
    /// Bumped wherever a name may come to stand for something else (see
    /// [`settled`]), and what each move statement settled (by address).
    scope: u64,
    settled: FastMap<*const Call, Box<Settled<'p>>>,
    /// The last move statement's, kept out of the map: a loop's move is
    /// the next one again, and a million turns took it out of the map
    /// and put it back (a fifteenth of the walk).
    last_settled: Option<(*const Call, Box<Settled<'p>>)>,
}

/// Names as written, in a module and routine.
#[derive(PartialEq)]
pub(super) struct NamesAt {
    module: usize,
    routine: Option<*const Routine>,
    names: [Option<Arc<str>>; 2],
}

impl NamesAt {
    /// The names of `exprs` where each is a plain name or absent.
    pub(super) fn of(frame: &Frame, exprs: [Option<&Expr>; 2]) -> Option<NamesAt> {
        let name = |e: Option<&Expr>| match e {
            None => Some(None),
            Some(Expr::Name(n)) => Some(Some(n.clone())),
            Some(_) => None,
        };
        Some(NamesAt {
            module: frame.module,
            routine: frame.routine.map(std::ptr::from_ref),
            names: [name(exprs[0])?, name(exprs[1])?],
        })
    }
}

impl<'p> Walker<'p> {
    pub(super) fn new(
        program: &'p Program,
        robot: &'p Robot,
        base_frame: Option<&nalgebra::Isometry3<f64>>,
    ) -> Result<Walker<'p>> {
        // Identifiers only, and those of the fast lane's runs borrowed:
        // making every target to learn its identifier read each literal's
        // numbers once more (a tenth of timing a declared program).
        // The two tables by name, each a million entries of a declared
        // program, filled on a core each.
        let (target_ids, (decls, routines, run_decls)) = rayon::join(
            || {
                program.target_index(|t| {
                    t.kind != TargetKind::Inline
                        && !(t.kind == TargetKind::Derived && t.name.is_none())
                })
            },
            || decls::declarations(program),
        );
        let derived_at = program
            .targets()
            .one_by_one_all()
            .filter(|(_, t)| t.kind == TargetKind::Derived)
            .map(|(i, t)| ((t.origin.file, t.origin.pos.offset), i))
            .collect();
        let joint_ids = program
            .jointtargets()
            .iter()
            .enumerate()
            .filter(|(_, j)| j.kind != TargetKind::Inline)
            .map(|(i, j)| (j.id.to_ascii_lowercase(), i))
            .collect();
        let joint_ids: FastMap<String, usize> = joint_ids;
        let ids_scoped =
            target_ids.has_routine_scoped() || joint_ids.keys().any(|k| k.contains('/'));
        let ids_qualified = target_ids.has_qualified() || joint_ids.keys().any(|k| k.contains(':'));
        let shadowed = (decls.values())
            .filter(|list| list.len() > 1)
            .flat_map(|list| list.iter())
            .filter_map(|(_, d)| match d {
                Decl::Run { target, .. } => Some(*target),
                Decl::Tree(_) => None,
            })
            .collect();
        let zero = [0.0; 6];
        Ok(Walker {
            program,
            robot,
            frames: match base_frame {
                Some(base) => Frames::of_program(program)?.placed(base),
                None => Frames::of_program(program)?,
            },
            ids_scoped,
            ids_qualified,
            target_ids,
            joint_ids,
            derived_at,
            decls,
            run_decls,
            shadowed,
            next_decl: std::cell::Cell::new(usize::MAX),
            routines,
            globals: HashMap::new(),
            stack: Vec::new(),
            steps: 0,
            clock: 0.0,
            robot_free: 0.0,
            arm: Arm {
                flange: robot.fk(&zero),
                joints: Some(zero),
                conf: robot.conf_of(&zero),
            },
            velset: (1.0, f64::INFINITY),
            // Every robtarget is mostly reached: room for each at once
            // (a million grown by doubling were rehashed twenty times).
            schedule: {
                let mut s = Schedule::new();
                s.reserve(program.targets().len());
                s
            },
            joint_schedule: Schedule::new(),
            base_visits: Vec::new(),
            slot: std::cell::RefCell::new(crate::rapid::targets::blank()),
            notes: Vec::new(),
            noted: HashSet::new(),
            errors: Errors::default(),
            failed: HashSet::new(),
            reachable: foldhash::HashSet::default(),
            evaluating: HashSet::new(),
            last_speed: None,
            last_frames: None,
            deferred: None,
            pairs: Vec::new(),
            last_pair: None,
            poses: std::sync::Arc::default(),
            scope: 0,
            settled: FastMap::default(),
            last_settled: None,
        })
    }

    /// Whether the names of `at` resolve to the program's declarations
    /// alone: none is a routine parameter or variable, or data assigned
    /// in the walk (which could shadow or change it). A FOR loop's
    /// variable shadows only its own name.
    pub(super) fn static_names(&self, frame: &Frame, at: &NamesAt) -> bool {
        at.names.iter().flatten().all(|name| {
            !with_lower(name, |key| {
                frame.vars.contains_key(key) || self.globals.contains_key(key)
            })
        })
    }

    pub(super) fn note(&mut self, frame: &Frame, line: u32, msg: impl Into<String>) {
        let msg = msg.into();
        let file = self
            .program
            .modules
            .get(frame.module)
            .and_then(|m| self.program.files.get(m.file))
            .map(String::as_str)
            .unwrap_or("");
        let routine = frame.routine.map(|r| r.name.as_ref()).unwrap_or("");
        let text = format!("{file}:{line} ({routine}): {msg}");
        if self.noted.insert(text.clone()) {
            self.notes.push(text);
        }
    }

    /// Bases reached only through derived targets get those visits;
    /// a summary of targets never reached.
    pub(super) fn finish(&mut self) {
        let targets = self.program.targets();
        self.schedule.name_targets(|i| {
            let mut id = String::new();
            targets.id_into(i, &mut id);
            Arc::from(id)
        });
        let visits = std::mem::take(&mut self.base_visits);
        let visited = |s: &Schedule, i: usize| {
            let mut id = String::new();
            targets.id_into(i, &mut id).is_some() && s.times_of(i, &id).is_some()
        };
        let direct: HashSet<usize> = visits
            .iter()
            .map(|&(b, _)| b)
            .filter(|&b| visited(&self.schedule, b))
            .collect();
        for (b, t) in visits {
            if direct.contains(&b) || b >= targets.len() {
                continue;
            }
            self.schedule.visit_target(b, t, || {
                let mut id = String::new();
                targets.id_into(b, &mut id);
                Arc::from(id)
            });
        }
        let mut count = 0;
        let mut shown: Vec<String> = Vec::new();
        // Identifiers only: the targets' numbers are not read for this.
        let mut id = String::new();
        for i in 0..targets.len() {
            // Visited by number (nearly all): named above, found by
            // number, with no identifier to make.
            if self.schedule.has_number(i) {
                continue;
            }
            if targets.id_into(i, &mut id) == Some(true) && self.schedule.times_of(i, &id).is_none()
            {
                count += 1;
                if shown.len() < SHOWN_MISSED {
                    shown.push(id.clone());
                }
            }
        }
        if count > 0 {
            let more = if count > shown.len() {
                format!(", ... ({count} in all)")
            } else {
                String::new()
            };
            self.notes.push(format!(
                "{count} robtarget(s) never reached from the entry routine: {}{more}",
                shown.join(", ")
            ));
        }
    }

    // ---------------------------------------------------------- routines

    pub(super) fn find_routine(&self, module: usize, name: &str) -> Option<(usize, &'p Routine)> {
        let list = self.routines.get(&name.to_ascii_lowercase())?;
        list.iter()
            .find(|(m, _)| *m == module)
            .or_else(|| list.iter().find(|(_, r)| !r.local))
            .copied()
    }

    pub(super) fn call_routine(
        &mut self,
        module: usize,
        routine: &'p Routine,
        vars: Vec<(String, Value)>,
        line: u32,
    ) -> Result<Flow> {
        self.rescope();
        let mut frame = Frame {
            module,
            routine: Some(routine),
            vars: vars.into_iter().collect(),
        };
        let why = if self.stack.contains(&std::ptr::from_ref(routine)) {
            Some("recursive call")
        } else if self.stack.len() >= MAX_DEPTH {
            Some("calls nested too deep: call")
        } else {
            None
        };
        if let Some(why) = why {
            self.note(
                &frame,
                line,
                format!("{why} of {} not followed", routine.name),
            );
            return Ok(Flow::Normal);
        }
        self.stack.push(std::ptr::from_ref(routine));
        let flow = self.exec_list(&routine.body, &mut frame);
        self.stack.pop();
        Ok(match flow? {
            Flow::Goto(label) => {
                self.note(
                    &frame,
                    routine.pos.line,
                    format!("GOTO {label}: no such label, ignored"),
                );
                Flow::Normal
            }
            other => other,
        })
    }

    /// Bind a call's arguments (evaluated in the caller's frame) to the
    /// routine's parameters.
    pub(super) fn bind(
        &mut self,
        routine: &Routine,
        args: &[Arg],
        caller: &mut Frame<'p>,
    ) -> Result<Vec<(String, Value)>> {
        let mut out = Vec::new();
        let mut required = routine.params.iter().filter(|p| !p.optional);
        for a in args {
            let param = if a.optional {
                a.name.as_deref().and_then(|n| {
                    routine
                        .params
                        .iter()
                        .find(|p| p.optional && p.name.eq_ignore_ascii_case(n))
                })
            } else {
                required.next()
            };
            let Some(param) = param else { continue };
            let value = match &a.value {
                Some(e) => self.eval(e, caller)?,
                None => Value::Bool(true),
            };
            out.push((param.name.to_ascii_lowercase(), value));
        }
        Ok(out)
    }

    // -------------------------------------------------------- statements

    pub(super) fn exec_list(&mut self, stmts: &'p Block, frame: &mut Frame<'p>) -> Result<Flow> {
        let program = self.program;
        let mut items = program.items(stmts);
        // The statement held one by one being walked (labels are).
        let mut pc = 0;
        while let Some(item) = items.next() {
            let s = match item {
                Listed::Statement(s) => s,
                Listed::Batch(b) => {
                    self.exec_moves(b, frame)?;
                    continue;
                }
            };
            match self.exec(s, frame)? {
                Flow::Normal => pc += 1,
                Flow::Goto(label) => {
                    let at = stmts.iter().position(|s| {
                        matches!(&s.kind, StatementKind::Label(l) if l.eq_ignore_ascii_case(&label))
                    });
                    match at {
                        Some(j) if j > pc => {
                            pc = j;
                            items = program.items_from(stmts, j);
                        }
                        Some(_) => {
                            self.note(
                                frame,
                                s.pos.line,
                                format!("GOTO {label} jumps back: not taken (the loop it makes is timed once)"),
                            );
                            pc += 1;
                        }
                        None => return Ok(Flow::Goto(label)),
                    }
                }
                other => return Ok(other),
            }
        }
        Ok(Flow::Normal)
    }

    /// One statement. Deeply nested programs (blocks in routines in
    /// blocks...) grow the stack on the heap instead of overflowing it.
    pub(super) fn exec(&mut self, s: &'p Statement, frame: &mut Frame<'p>) -> Result<Flow> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_SEGMENT, || self.exec_inner(s, frame))
    }

    pub(super) fn exec_inner(&mut self, s: &'p Statement, frame: &mut Frame<'p>) -> Result<Flow> {
        self.count_step(frame, s)?;
        let line = s.pos.line;
        match &s.kind {
            StatementKind::Call(call) => self.exec_call(call, s, frame),
            StatementKind::Assign { target, value } => {
                let v = self.eval(value, frame)?;
                if let Some(name) = target.as_name() {
                    let key = name.to_ascii_lowercase();
                    let local = frame.vars.contains_key(&key)
                        || frame.routine.is_some_and(|r| {
                            r.data.iter().any(|d| d.name.eq_ignore_ascii_case(name))
                        });
                    // Numbers are run-time values; robtargets are followed.
                    let v = match v {
                        Value::Rob(_) | Value::Joint(_) => v,
                        _ => Value::Unknown,
                    };
                    let new = if local {
                        frame.vars.insert(key, v)
                    } else {
                        self.globals.insert(key, v)
                    };
                    if new.is_none() {
                        self.rescope();
                    }
                }
                Ok(Flow::Normal)
            }
            StatementKind::If {
                branches,
                otherwise,
            } => {
                for (i, (cond, body)) in branches.iter().enumerate() {
                    match self.eval(cond, frame)?.boolean() {
                        Some(false) => continue,
                        Some(true) => return self.exec_list(body, frame),
                        None => {
                            let which = if i == 0 {
                                "IF".to_string()
                            } else {
                                format!("ELSEIF #{i}")
                            };
                            if self.list_ends(body, frame.module, 0) {
                                self.note(
                                    frame,
                                    line,
                                    format!(
                                        "IF: condition known only at run time; the {which} branch ends the program (EXIT), so the walk takes its condition as false"
                                    ),
                                );
                                continue;
                            }
                            self.note(
                                frame,
                                line,
                                format!(
                                    "IF: condition known only at run time, took the {which} branch"
                                ),
                            );
                            return self.exec_list(body, frame);
                        }
                    }
                }
                match otherwise {
                    Some(body) => self.exec_list(body, frame),
                    None => Ok(Flow::Normal),
                }
            }
            StatementKind::CompactIf { cond, then } => match self.eval(cond, frame)?.boolean() {
                Some(false) => Ok(Flow::Normal),
                Some(true) => self.exec(then, frame),
                None if self.ends_program(then, frame.module) => {
                    self.note(
                        frame,
                        line,
                        "IF: condition known only at run time; the statement ends the program (EXIT), so the walk carries on past it",
                    );
                    Ok(Flow::Normal)
                }
                None => {
                    self.note(
                        frame,
                        line,
                        "IF: condition known only at run time, statement taken",
                    );
                    self.exec(then, frame)
                }
            },
            StatementKind::For {
                var,
                from,
                to,
                step,
                body,
            } => self.exec_for(var, from, to, step.as_deref(), body, s, frame),
            StatementKind::While { cond, body } => match self.eval(cond, frame)?.boolean() {
                Some(false) => Ok(Flow::Normal),
                _ => {
                    self.note(frame, line, "WHILE: body timed once");
                    self.exec_list(body, frame)
                }
            },
            StatementKind::Test {
                value,
                cases,
                default,
            } => {
                let v = self.eval(value, frame)?;
                let mut unknown = v.num().is_none() && v.boolean().is_none();
                if !unknown {
                    for (values, body) in cases {
                        for e in values {
                            let c = self.eval(e, frame)?;
                            match (&v, &c) {
                                (Value::Num(a), Value::Num(b)) if a == b => {
                                    return self.exec_list(body, frame)
                                }
                                (Value::Bool(a), Value::Bool(b)) if a == b => {
                                    return self.exec_list(body, frame)
                                }
                                (_, Value::Num(_) | Value::Bool(_)) => {}
                                _ => unknown = true,
                            }
                        }
                        if unknown {
                            break;
                        }
                    }
                }
                if unknown {
                    self.note(
                        frame,
                        line,
                        "TEST: value known only at run time, took the first CASE",
                    );
                    return match cases.first() {
                        Some((_, body)) => self.exec_list(body, frame),
                        None => match default {
                            Some(body) => self.exec_list(body, frame),
                            None => Ok(Flow::Normal),
                        },
                    };
                }
                match default {
                    Some(body) => self.exec_list(body, frame),
                    None => Ok(Flow::Normal),
                }
            }
            StatementKind::Goto(label) => Ok(Flow::Goto(label.clone())),
            StatementKind::Return(value) => Ok(Flow::Return(match value {
                Some(e) => self.eval(e, frame)?,
                None => Value::Unknown,
            })),
            StatementKind::Exit => {
                self.note(frame, line, "EXIT: the program ends here");
                Ok(Flow::Exit)
            }
            StatementKind::Raise(_) => {
                self.note(
                    frame,
                    line,
                    "RAISE: error handlers are not walked, carried on",
                );
                Ok(Flow::Normal)
            }
            StatementKind::Label(_)
            | StatementKind::Retry
            | StatementKind::TryNext
            | StatementKind::Connect { .. }
            | StatementKind::Placeholder(_) => Ok(Flow::Normal),
        }
    }

    /// One more statement (or loop turn) walked: refuse walks that would
    /// run for hours.
    pub(super) fn count_step(&mut self, frame: &Frame, s: &Statement) -> Result<()> {
        self.steps += 1;
        if self.steps > STEP_BUDGET {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!("the walk of the program passed {STEP_BUDGET} statements (a loop with a very large count?)"),
            )
            .with_remedy(Remedy::GiveSchedule)
            .at(self.location(frame, s)));
        }
        Ok(())
    }

    pub(super) fn location(&self, frame: &Frame, s: &Statement) -> crate::error::Location {
        let file = self
            .program
            .modules
            .get(frame.module)
            .map(|m| m.file)
            .unwrap_or(0);
        crate::error::Location {
            file: self.program.files.get(file).cloned().unwrap_or_default(),
            line: s.pos.line as usize,
            col: s.pos.col as usize,
            line_text: Box::default(),
        }
    }

    pub(super) fn exec_call(
        &mut self,
        call: &'p Call,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        let line = s.pos.line;
        if self.exec_settled(call, s, frame)? {
            return Ok(Flow::Normal);
        }
        let name = call.name.to_ascii_lowercase();
        if call.late_bound {
            let target = call
                .name
                .trim()
                .trim_start_matches('%')
                .trim_end_matches('%');
            let target = target.trim();
            let resolved = target
                .strip_prefix('"')
                .and_then(|t| t.strip_suffix('"'))
                .and_then(|n| self.find_routine(frame.module, n));
            return match resolved {
                Some((mi, r)) => {
                    let vars = self.bind(r, &call.args, frame)?;
                    self.call_routine(mi, r, vars, line).map(|f| match f {
                        Flow::Exit => Flow::Exit,
                        _ => Flow::Normal,
                    })
                }
                None => {
                    self.note(
                        frame,
                        line,
                        format!("late-bound call %{target}%: procedure known only at run time, taken as instantaneous"),
                    );
                    Ok(Flow::Normal)
                }
            };
        }
        match name.as_str() {
            "waittime" => {
                let secs = call
                    .positional()
                    .next()
                    .map(|e| self.eval(e, frame))
                    .transpose()?
                    .and_then(|v| v.num());
                match secs {
                    Some(t) if t.is_finite() && t >= 0.0 => {
                        if call.optional("InPos").is_some() {
                            self.clock = self.clock.max(self.robot_free);
                        }
                        self.clock += t;
                    }
                    _ => self.note(
                        frame,
                        line,
                        "WaitTime: time known only at run time, taken as 0 s",
                    ),
                }
                return Ok(Flow::Normal);
            }
            "waituntil" | "waitdi" | "waitdo" | "waitai" | "waitao" | "waitgi" | "waitgo"
            | "waitsynctask" | "waittestandset" | "waitload" | "waitsensor" | "waitwobj" => {
                if call.optional("InPos").is_some() {
                    self.clock = self.clock.max(self.robot_free);
                }
                self.note(
                    frame,
                    line,
                    format!("{}: waits on a run-time condition, taken as 0 s", call.name),
                );
                return Ok(Flow::Normal);
            }
            // MultiMove: the task waits for the others at its
            // synchronisation point, with its robot at rest (the
            // instructions need a stop point before them); the other
            // tasks' time is not modelled here.
            "syncmoveon" | "syncmoveoff" | "syncmoveundo" | "syncmovesuspend"
            | "syncmoveresume" => {
                self.clock = self.clock.max(self.robot_free);
                self.note(
                    frame,
                    line,
                    format!(
                        "{}: waits for the other motion tasks (MultiMove), taken as 0 s",
                        call.name
                    ),
                );
                return Ok(Flow::Normal);
            }
            "waitrob" => {
                self.clock = self.clock.max(self.robot_free);
                return Ok(Flow::Normal);
            }
            "velset" => {
                let mut pos = call.positional();
                let ov = pos.next().map(|e| self.eval(e, frame)).transpose()?;
                let max = pos.next().map(|e| self.eval(e, frame)).transpose()?;
                match (ov.and_then(|v| v.num()), max.and_then(|v| v.num())) {
                    (Some(o), Some(m)) if o > 0.0 && m > 0.0 => self.velset = (o / 100.0, m),
                    _ => self.note(
                        frame,
                        line,
                        "VelSet: values known only at run time, ignored",
                    ),
                }
                return Ok(Flow::Normal);
            }
            "stop" | "break" => {
                self.note(
                    frame,
                    line,
                    format!(
                        "{}: the time until the operator restarts is not counted",
                        call.name
                    ),
                );
                return Ok(Flow::Normal);
            }
            _ => {}
        }
        match self.find_routine(frame.module, &call.name) {
            Some((mi, r)) if r.kind == RoutineKind::Proc => {
                let vars = self.bind(r, &call.args, frame)?;
                Ok(match self.call_routine(mi, r, vars, line)? {
                    Flow::Exit => Flow::Exit,
                    _ => Flow::Normal,
                })
            }
            _ => {
                if !is_instant_builtin(&name) {
                    self.note(
                        frame,
                        line,
                        format!(
                            "{}: not a procedure of the program, taken as instantaneous",
                            call.name
                        ),
                    );
                }
                Ok(Flow::Normal)
            }
        }
    }
}
