//! The walker's state (what the program has, where the robot and the
//! clock are, what the walk has found), made once for a program, and the
//! frame of the routine being walked.

use super::decls::{self, Decl, DeclList, RunDecls};
use super::poses::TargetPoses;
use super::reach::ReachAhead;
use super::settled::Settled;
use super::value::Value;
use crate::error::{Errors, Result};
use crate::rapid::{Call, Expr, NoCase, Program, Routine, TargetKind};
use crate::resolve::Frames;
use crate::robot::{Joints, RobConf, Robot, ToolFrame, WobjFrames};
use crate::schedule::timing::*;
use crate::schedule::Schedule;
use nalgebra::Isometry3;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

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
pub(super) type FastMap<K, V> = foldhash::HashMap<K, V>;

pub(super) struct Frame<'p> {
    pub(super) module: usize,
    pub(super) routine: Option<&'p Routine>,
    pub(super) vars: FastMap<String, Value>,
}

/// Where the robot is.
pub(super) struct Arm {
    pub(super) flange: Isometry3<f64>,
    pub(super) joints: Option<Joints>,
    pub(super) conf: RobConf,
}

pub(crate) struct Walker<'p> {
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
    pub(super) decls: FastMap<NoCase<'p>, DeclList<'p>>,
    /// The declaration runs, in the order of their targets.
    pub(super) run_decls: Vec<RunDecls<'p>>,
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
    pub(crate) steps: u64,
    pub(crate) clock: f64,
    pub(crate) robot_free: f64,
    pub(super) arm: Arm,
    /// VelSet: override (fraction) and max TCP speed (mm/s).
    pub(super) velset: (f64, f64),
    pub(crate) schedule: Schedule,
    pub(crate) joint_schedule: Schedule,
    /// Visits of bases through derived targets: (base, minutes).
    pub(super) base_visits: Vec<(usize, f64)>,
    /// The target a move's literal is read into ([`Self::target_value`]).
    pub(super) slot: std::cell::RefCell<crate::rapid::Target>,
    pub(crate) notes: Vec<String>,
    /// Targets that cannot be timed (not finite, out of reach), each once:
    /// the walk goes on to find them all, and the estimate is refused.
    pub(crate) errors: Errors,
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
    pub(crate) deferred: Option<ReachAhead>,
    /// The pairs of tool and work object the deferred poses were placed
    /// by, by number from 1 ([`crate::schedule::ColdJoints`]).
    pub(crate) pairs: Vec<(ToolFrame, WobjFrames)>,
    /// The last move's frames and their pair's number.
    pub(super) last_pair: Option<(std::rc::Rc<(ToolFrame, WobjFrames)>, u32)>,
    /// Each robtarget's pose and robconf, read before the walk on every
    /// core ([`TargetPoses::read`]); empty: read as the walk meets them.
    pub(crate) poses: std::sync::Arc<TargetPoses>,
    /// Bumped wherever a name may come to stand for something else (see
    /// [`settled`]), and what each move statement settled (by address).
    pub(super) scope: u64,
    pub(super) settled: FastMap<*const Call, Box<Settled<'p>>>,
    /// The last move statement's, kept out of the map: a loop's move is
    /// the next one again, and a million turns took it out of the map
    /// and put it back (a fifteenth of the walk).
    pub(super) last_settled: Option<(*const Call, Box<Settled<'p>>)>,
}

/// Names as written, in a module and routine.
#[derive(PartialEq)]
pub(super) struct NamesAt {
    pub(super) module: usize,
    pub(super) routine: Option<*const Routine>,
    pub(super) names: [Option<Arc<str>>; 2],
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
    pub(crate) fn new(
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
        let joint_ids: FastMap<String, usize> = program.jointtargets_by_id().collect();
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
}
