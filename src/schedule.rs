//! When each target is reached: a fixed time (`--at`), the user's schedule
//! file (`--schedule`), or an estimate from the program itself (walking
//! the entry routine and timing each move). Times are minutes since the
//! robot's cold start; target identifiers are those of
//! `shared/spec/formats.md`.
//!
//! - [`SpeedData`], [`predefined_speed`], [`linear_move_seconds`],
//!   [`joint_move_seconds`]: timing one move.
//! - [`Schedule`]: every visit of every target; [`Schedule::read`] and
//!   [`Schedule::to_csv`] are the `target,time_min` file.
//! - [`Visit`]: which of a target's visits its correction is for.
//! - [`estimate`] with [`EstimateOptions`] → [`Estimate`]: walk the program
//!   (see its docs for every choice made where run-time values decide).

use crate::csv_table::CsvTable;
use crate::error::{Error, ErrorKind, Result};
use crate::rapid::{
    self, Arg, BinaryOp, Call, DataDecl, Expr, FunctionCall, Motion, MotionKind, Program, Routine,
    RoutineKind, Statement, StatementKind, TargetKind, UnaryOp,
};
use crate::resolve::{target_pose, Frames};
use crate::robot::frames::{flange_of_target, target_of_flange};
use crate::robot::{Joints, RobConf, Robot, ToolData, WobjData};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::collections::{BTreeMap, HashMap, HashSet};

/// RAPID `speeddata`: TCP speed (mm/s), reorientation speed (°/s), linear
/// and rotational external-axis speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedData {
    pub v_tcp: f64,
    pub v_ori: f64,
    pub v_leax: f64,
    pub v_reax: f64,
}

/// The predefined speeddata of the RAPID reference manual: `v5` … `v7000`
/// are `[n, 500, 5000, 1000]`; `vmax` is the robot's maximum TCP speed,
/// taken as 5000 mm/s for this family.
pub fn predefined_speed(name: &str) -> Option<SpeedData> {
    const NAMED: [u32; 25] = [
        5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000, 1500, 2000,
        2500, 3000, 4000, 5000, 6000, 7000,
    ];
    let lower = name.to_ascii_lowercase();
    let v_tcp = if lower == "vmax" {
        5000.0
    } else {
        let n: u32 = lower.strip_prefix('v')?.parse().ok()?;
        if !NAMED.contains(&n) {
            return None;
        }
        f64::from(n)
    };
    Some(SpeedData {
        v_tcp,
        v_ori: 500.0,
        v_leax: 5000.0,
        v_reax: 1000.0,
    })
}

/// Seconds for a linear move (MoveL, MoveC approximated by its chord
/// unless the caller passes the arc length): the slower of the TCP path at
/// `v_tcp` and the reorientation at `v_ori`, as the controller does.
/// Acceleration phases are ignored: at the minute scale of a warm-up they
/// shift times by well under a second per move.
pub fn linear_move_seconds(from: &Isometry3<f64>, to: &Isometry3<f64>, speed: &SpeedData) -> f64 {
    let dist = (to.translation.vector - from.translation.vector).norm();
    let angle = from.rotation.angle_to(&to.rotation).to_degrees();
    seconds_for(dist, speed.v_tcp).max(seconds_for(angle, speed.v_ori))
}

/// Seconds for a joint move (MoveJ, MoveAbsJ): the axis that needs longest
/// at its maximum speed sets the time, and the TCP may not exceed `v_tcp`
/// along the straight line between the two poses (a lower bound of its
/// true path).
pub fn joint_move_seconds(
    from: &Joints,
    to: &Joints,
    max_speed_deg_s: &[f64; 6],
    tcp_distance_mm: f64,
    speed: &SpeedData,
) -> f64 {
    let axes = (0..6)
        .map(|i| seconds_for((to[i] - from[i]).abs().to_degrees(), max_speed_deg_s[i]))
        .fold(0.0, f64::max);
    axes.max(seconds_for(tcp_distance_mm, speed.v_tcp))
}

fn seconds_for(amount: f64, rate: f64) -> f64 {
    if rate > 0.0 {
        amount / rate
    } else {
        0.0
    }
}

/// Which of a target's several visits its correction is computed for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Visit {
    First,
    #[default]
    Mean,
    Last,
}

impl Visit {
    /// The time chosen among `times` (which must not be empty).
    pub fn pick(self, times: &[f64]) -> f64 {
        match self {
            Visit::First => times.iter().copied().fold(f64::INFINITY, f64::min),
            Visit::Last => times.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Visit::Mean => times.iter().sum::<f64>() / times.len() as f64,
        }
    }
}

/// When each target is reached: every visit of every target, in minutes.
/// Keys are target identifiers as written (lookups ignore case, as RAPID
/// does).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Schedule {
    visits: BTreeMap<String, Vec<f64>>,
    /// Identifiers in first-visit order, for stable output.
    order: Vec<String>,
}

impl Schedule {
    pub fn new() -> Schedule {
        Schedule::default()
    }

    /// Record one visit of `target` at `time_min`.
    pub fn visit(&mut self, target: &str, time_min: f64) {
        let key = target.to_ascii_lowercase();
        let entry = self.visits.entry(key).or_default();
        if entry.is_empty() {
            self.order.push(target.to_string());
        }
        entry.push(time_min);
    }

    /// All visit times of a target, in the order recorded.
    pub fn times(&self, target: &str) -> Option<&[f64]> {
        self.visits
            .get(&target.to_ascii_lowercase())
            .map(Vec::as_slice)
    }

    /// Target identifiers in the order they were first visited.
    pub fn targets(&self) -> &[String] {
        &self.order
    }

    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// Number of visits of all targets.
    pub fn visit_count(&self) -> usize {
        self.visits.values().map(Vec::len).sum()
    }

    /// Read a schedule file (`target,time_min`). Several rows may name one
    /// target: each is a visit.
    pub fn read(file: &str, bytes: &[u8]) -> Result<Schedule> {
        let table = CsvTable::parse(file, bytes)?;
        let target = table.require("target")?;
        let time = table.require("time_min")?;
        let mut schedule = Schedule::new();
        for row in &table.rows {
            let name = table.text(row, target)?;
            if name.is_empty() {
                return Err(
                    Error::input("empty target identifier").at(table.field_location(row, target))
                );
            }
            let t = table.number(row, time)?;
            if t < 0.0 {
                return Err(Error::input(format!(
                    "time {t} min is before the cold start (times are minutes since it)"
                ))
                .at(table.field_location(row, time)));
            }
            schedule.visit(name, t);
        }
        Ok(schedule)
    }

    /// The schedule as CSV, one row per visit in time order: the format
    /// [`Schedule::read`] takes back.
    pub fn to_csv(&self) -> String {
        let mut rows: Vec<(f64, usize, &str)> = Vec::new();
        for (i, name) in self.order.iter().enumerate() {
            if let Some(times) = self.times(name) {
                rows.extend(times.iter().map(|&t| (t, i, name.as_str())));
            }
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut out = String::from("target,time_min\n");
        for (t, _, name) in rows {
            out.push_str(&csv_field(name));
            out.push_str(&format!(",{t:.4}\n"));
        }
        out
    }
}

// ------------------------------------------------------------ estimation

/// What [`estimate`] walks: the entry routine, the start time, how many
/// times the entry routine runs.
#[derive(Debug, Clone, PartialEq)]
pub struct EstimateOptions {
    /// Entry routine (case-insensitive), `main` by default.
    pub entry: String,
    /// Minutes since the cold start at which the program starts.
    pub start_min: f64,
    /// How many times the entry routine runs back to back.
    pub cycles: u32,
}

impl Default for EstimateOptions {
    fn default() -> Self {
        EstimateOptions {
            entry: "main".to_string(),
            start_min: 0.0,
            cycles: 1,
        }
    }
}

/// The estimated schedule of a program.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Estimate {
    /// Every visit of every robtarget (identifiers of [`Program::targets`]).
    pub schedule: Schedule,
    /// Every visit of every jointtarget (MoveAbsJ), identifiers of
    /// [`Program::jointtargets`] (their own name space).
    pub joint_schedule: Schedule,
    /// From the start to the end of the last motion, minutes.
    pub duration_min: f64,
    /// The choices made where the program's run-time values decide (branch
    /// taken, loop counts, unknown procedures, ...), each with its place.
    pub notes: Vec<String>,
}

impl Estimate {
    /// The schedule as CSV (the format [`Schedule::read`] takes back):
    /// robtargets and jointtargets together, in time order. A jointtarget
    /// whose identifier is also a robtarget's (inline `main#1` of both
    /// kinds) is left out: one file has one name space.
    pub fn to_csv(&self) -> String {
        let mut all = self.schedule.clone();
        for id in self.joint_schedule.targets() {
            if self.schedule.times(id).is_some() {
                continue;
            }
            for &t in self.joint_schedule.times(id).unwrap_or(&[]) {
                all.visit(id, t);
            }
        }
        all.to_csv()
    }
}

/// Statements executed before the walk gives up (a FOR loop of a billion
/// turns would otherwise run for hours).
const STEP_BUDGET: u64 = 50_000_000;
/// Nested routine calls followed (the controller's own limit is lower).
const MAX_DEPTH: usize = 256;
/// Stack left before the walk grows it, and by how much.
const STACK_RED_ZONE: usize = 64 * 1024;
const STACK_SEGMENT: usize = 1024 * 1024;
/// The speed assumed where a move's speeddata cannot be resolved.
const FALLBACK_SPEED: &str = "v1000";

/// Estimate when each target of `program` is reached by walking the entry
/// routine from `opts.start_min`, timing each move from its distance and
/// speed on the nominal (cold) `robot`.
///
/// Documented choices (each one made is listed in [`Estimate::notes`]):
/// - the robot starts at the calibration pose (all joints 0);
/// - IF/ELSEIF/TEST: conditions the program fixes (constants, FOR
///   variables, arguments, `Present`) are evaluated; otherwise the first
///   branch whose condition may be true is taken;
/// - WHILE runs its body once unless its condition is known FALSE; a
///   backward GOTO is not taken (its loop is timed once); forward GOTOs are;
/// - FOR loops with bounds the program fixes run in full, others once;
/// - VAR and PERS numbers are run-time values (unknown); robtarget
///   variables assigned in the walk (`p := Offs(...)`) are followed;
/// - WaitTime counts; WaitUntil, WaitDI and other waits on signals take 0 s;
/// - a move with `\Conc` lets the program run on while the robot moves;
/// - acceleration and zones are ignored (each move at its programmed speed,
///   `VelSet` applied);
/// - a move to a derived target (`Offs(p10,...)`, `main@2`) is a visit of
///   that derived target; a base (`p10`) never reached itself gets the
///   visits of the targets derived from it.
///
/// Errors: no entry routine, a MoveJ target out of reach, a program whose
/// walk exceeds 50 million statements.
pub fn estimate(program: &Program, robot: &Robot, opts: &EstimateOptions) -> Result<Estimate> {
    if !opts.start_min.is_finite() || opts.start_min < 0.0 {
        return Err(Error::usage(format!(
            "start time {} min: must be a finite number of minutes since the cold start, not negative",
            opts.start_min
        )));
    }
    let (module, routine) = find_entry(program, &opts.entry)?;
    let mut w = Walker::new(program, robot)?;
    let start_s = opts.start_min * 60.0;
    w.clock = start_s;
    w.robot_free = start_s;
    for _ in 0..opts.cycles {
        let flow = w.call_routine(module, routine, Vec::new(), 0)?;
        if matches!(flow, Flow::Exit) {
            break;
        }
    }
    let end_s = w.clock.max(w.robot_free);
    if !end_s.is_finite() {
        return Err(Error::input(
            "the program's waits add up to more time than can be counted (a WaitTime of astronomic length?)",
        ));
    }
    w.finish();
    for id in w.joint_schedule.targets() {
        if w.schedule.times(id).is_some() {
            w.notes.push(format!(
                "jointtarget {id} has the identifier of robtarget {id} (two name spaces, one schedule file): the CSV lists the robtarget's visits only"
            ));
        }
    }
    Ok(Estimate {
        schedule: w.schedule,
        joint_schedule: w.joint_schedule,
        duration_min: (end_s - start_s) / 60.0,
        notes: w.notes,
    })
}

fn find_entry<'p>(program: &'p Program, entry: &str) -> Result<(usize, &'p Routine)> {
    for (mi, m) in program.modules.iter().enumerate() {
        if let Some(r) = m
            .routines
            .iter()
            .find(|r| r.kind == RoutineKind::Proc && r.name.eq_ignore_ascii_case(entry))
        {
            return Ok((mi, r));
        }
    }
    let procs: Vec<&str> = program
        .modules
        .iter()
        .flat_map(|m| &m.routines)
        .filter(|r| r.kind == RoutineKind::Proc && r.params.is_empty())
        .map(|r| r.name.as_ref())
        .collect();
    let mut e = Error::input(format!(
        "no procedure `{entry}` in the program: nothing to walk"
    ));
    if !procs.is_empty() {
        e = e.with_note(format!(
            "procedures without parameters: {} (choose one with --entry)",
            procs.join(", ")
        ));
    }
    Err(e)
}

/// A robtarget value met in the walk.
#[derive(Debug, Clone)]
struct Rob {
    /// TCP in the work object (the robtarget's own frame).
    pose: Isometry3<f64>,
    conf: RobConf,
    /// The literal target this value is (index into `Program::targets`).
    id: Option<usize>,
    /// The derived target that computed it (`Offs(...)`).
    derived: Option<usize>,
    /// Literal targets it was derived from.
    bases: Vec<usize>,
}

#[derive(Debug, Clone)]
enum Value {
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

enum Flow {
    Normal,
    Return(Value),
    Exit,
    Goto(String),
}

struct Frame<'p> {
    module: usize,
    routine: Option<&'p Routine>,
    vars: HashMap<String, Value>,
}

/// Where the robot is.
struct Arm {
    flange: Isometry3<f64>,
    joints: Option<Joints>,
    conf: RobConf,
}

struct Walker<'p> {
    program: &'p Program,
    robot: &'p Robot,
    frames: Frames,
    /// Non-inline robtarget ids (lower case) → index.
    target_ids: HashMap<String, usize>,
    joint_ids: HashMap<String, usize>,
    /// (file, byte offset) of a derived expression → its target.
    derived_at: HashMap<(usize, usize), usize>,
    /// Module data by lower-case name: (module, declaration).
    decls: HashMap<String, Vec<(usize, &'p DataDecl)>>,
    /// Procedures and functions by lower-case name: (module, routine).
    routines: HashMap<String, Vec<(usize, &'p Routine)>>,
    /// Robtarget variables assigned during the walk (module data).
    globals: HashMap<String, Value>,
    /// Routines being walked (by identity: two modules may each have a
    /// LOCAL routine of one name).
    stack: Vec<*const Routine>,
    steps: u64,
    clock: f64,
    robot_free: f64,
    arm: Arm,
    /// VelSet: override (fraction) and max TCP speed (mm/s).
    velset: (f64, f64),
    schedule: Schedule,
    joint_schedule: Schedule,
    /// Visits of bases through derived targets: (base, minutes).
    base_visits: Vec<(usize, f64)>,
    notes: Vec<String>,
    noted: HashSet<String>,
    evaluating: HashSet<String>,
}

impl<'p> Walker<'p> {
    fn new(program: &'p Program, robot: &'p Robot) -> Result<Walker<'p>> {
        let mut target_ids = HashMap::new();
        let mut derived_at = HashMap::new();
        for (i, t) in program.targets().iter().enumerate() {
            if t.kind == TargetKind::Derived {
                derived_at.insert((t.origin.file, t.origin.pos.offset), i);
            }
            if t.kind != TargetKind::Inline && !(t.kind == TargetKind::Derived && t.name.is_none())
            {
                target_ids.entry(t.id.to_ascii_lowercase()).or_insert(i);
            }
        }
        let joint_ids = program
            .jointtargets()
            .iter()
            .enumerate()
            .filter(|(_, j)| j.kind != TargetKind::Inline)
            .map(|(i, j)| (j.id.to_ascii_lowercase(), i))
            .collect();
        let mut decls: HashMap<String, Vec<(usize, &DataDecl)>> = HashMap::new();
        let mut routines: HashMap<String, Vec<(usize, &Routine)>> = HashMap::new();
        for (mi, m) in program.modules.iter().enumerate() {
            for d in &m.data {
                decls
                    .entry(d.name.to_ascii_lowercase())
                    .or_default()
                    .push((mi, d));
            }
            for r in &m.routines {
                routines
                    .entry(r.name.to_ascii_lowercase())
                    .or_default()
                    .push((mi, r));
            }
        }
        let zero = [0.0; 6];
        Ok(Walker {
            program,
            robot,
            frames: Frames::of_program(program)?,
            target_ids,
            joint_ids,
            derived_at,
            decls,
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
            schedule: Schedule::new(),
            joint_schedule: Schedule::new(),
            base_visits: Vec::new(),
            notes: Vec::new(),
            noted: HashSet::new(),
            evaluating: HashSet::new(),
        })
    }

    fn note(&mut self, frame: &Frame, line: u32, msg: impl Into<String>) {
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
    fn finish(&mut self) {
        let visits = std::mem::take(&mut self.base_visits);
        let direct: HashSet<usize> = visits
            .iter()
            .map(|&(b, _)| b)
            .filter(|&b| {
                self.program
                    .targets()
                    .get(b)
                    .is_some_and(|t| self.schedule.times(&t.id).is_some())
            })
            .collect();
        for (b, t) in visits {
            if direct.contains(&b) {
                continue;
            }
            if let Some(target) = self.program.targets().get(b) {
                self.schedule.visit(&target.id, t);
            }
        }
        let missed: Vec<&str> = self
            .program
            .targets()
            .iter()
            .filter(|t| t.value.is_some() && self.schedule.times(&t.id).is_none())
            .map(|t| t.id.as_str())
            .collect();
        if !missed.is_empty() {
            let shown: Vec<&str> = missed.iter().take(8).copied().collect();
            let more = if missed.len() > shown.len() {
                format!(", ... ({} in all)", missed.len())
            } else {
                String::new()
            };
            self.notes.push(format!(
                "{} robtarget(s) never reached from the entry routine: {}{more}",
                missed.len(),
                shown.join(", ")
            ));
        }
    }

    // ---------------------------------------------------------- routines

    fn find_routine(&self, module: usize, name: &str) -> Option<(usize, &'p Routine)> {
        let list = self.routines.get(&name.to_ascii_lowercase())?;
        list.iter()
            .find(|(m, _)| *m == module)
            .or_else(|| list.iter().find(|(_, r)| !r.local))
            .copied()
    }

    fn call_routine(
        &mut self,
        module: usize,
        routine: &'p Routine,
        vars: Vec<(String, Value)>,
        line: u32,
    ) -> Result<Flow> {
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
    fn bind(
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

    fn exec_list(&mut self, stmts: &'p [Statement], frame: &mut Frame<'p>) -> Result<Flow> {
        let mut pc = 0;
        while let Some(s) = stmts.get(pc) {
            match self.exec(s, frame)? {
                Flow::Normal => pc += 1,
                Flow::Goto(label) => {
                    let at = stmts.iter().position(|s| {
                        matches!(&s.kind, StatementKind::Label(l) if l.eq_ignore_ascii_case(&label))
                    });
                    match at {
                        Some(j) if j > pc => pc = j,
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
    fn exec(&mut self, s: &'p Statement, frame: &mut Frame<'p>) -> Result<Flow> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_SEGMENT, || self.exec_inner(s, frame))
    }

    fn exec_inner(&mut self, s: &'p Statement, frame: &mut Frame<'p>) -> Result<Flow> {
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
                    if local {
                        frame.vars.insert(key, v);
                    } else {
                        self.globals.insert(key, v);
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
    fn count_step(&mut self, frame: &Frame, s: &Statement) -> Result<()> {
        self.steps += 1;
        if self.steps > STEP_BUDGET {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!("the walk of the program passed {STEP_BUDGET} statements (a loop with a very large count?): give the schedule with --schedule instead"),
            )
            .at(self.location(frame, s)));
        }
        Ok(())
    }

    fn location(&self, frame: &Frame, s: &Statement) -> crate::error::Location {
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
            line_text: String::new(),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn exec_for(
        &mut self,
        var: &str,
        from: &Expr,
        to: &Expr,
        step: Option<&Expr>,
        body: &'p [Statement],
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        let key = var.to_ascii_lowercase();
        let a = self.eval(from, frame)?.num();
        let b = self.eval(to, frame)?.num();
        let st = match step {
            Some(e) => self.eval(e, frame)?.num(),
            None => match (a, b) {
                (Some(a), Some(b)) => Some(if b < a { -1.0 } else { 1.0 }),
                _ => None,
            },
        };
        let saved = frame.vars.remove(&key);
        let flow = match (a, b, st) {
            (Some(a), Some(b), Some(st)) if st != 0.0 => {
                let mut v = a;
                let mut flow = Flow::Normal;
                while (st > 0.0 && v <= b) || (st < 0.0 && v >= b) {
                    self.count_step(frame, s)?;
                    frame.vars.insert(key.clone(), Value::Num(v));
                    match self.exec_list(body, frame)? {
                        Flow::Normal => {}
                        other => {
                            flow = other;
                            break;
                        }
                    }
                    v += st;
                }
                flow
            }
            _ => {
                let why = if st == Some(0.0) {
                    "STEP 0"
                } else {
                    "bounds known only at run time"
                };
                self.note(
                    frame,
                    s.pos.line,
                    format!("FOR {var}: {why}, body timed once"),
                );
                frame.vars.insert(key.clone(), Value::Unknown);
                self.exec_list(body, frame)?
            }
        };
        frame.vars.remove(&key);
        if let Some(v) = saved {
            frame.vars.insert(key, v);
        }
        Ok(flow)
    }

    fn exec_call(&mut self, call: &'p Call, s: &Statement, frame: &mut Frame<'p>) -> Result<Flow> {
        let line = s.pos.line;
        if let Some(m) = call.motion() {
            self.exec_move(call, &m, s, frame)?;
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

    // ------------------------------------------------------------- moves

    fn speed_of(
        &mut self,
        expr: Option<&Expr>,
        frame: &mut Frame<'p>,
        line: u32,
    ) -> Result<SpeedData> {
        let v = match expr {
            Some(e) => self.eval(e, frame)?,
            None => Value::Unknown,
        };
        let found = match &v {
            Value::Ref(name) => self.named_speed(frame.module, name),
            Value::Agg(items) => {
                let n: Option<Vec<f64>> = items.iter().map(Value::num).collect();
                match n.as_deref() {
                    Some(&[v_tcp, v_ori, v_leax, v_reax]) => Some(SpeedData {
                        v_tcp,
                        v_ori,
                        v_leax,
                        v_reax,
                    }),
                    _ => None,
                }
            }
            _ => None,
        };
        match found {
            Some(s) => Ok(s),
            None => {
                let what = match &v {
                    Value::Ref(name) => format!("speeddata `{name}` is not in the program"),
                    _ => "speed known only at run time".to_string(),
                };
                self.note(frame, line, format!("{what}: taken as {FALLBACK_SPEED}"));
                Ok(predefined_speed(FALLBACK_SPEED).unwrap_or(SpeedData {
                    v_tcp: 1000.0,
                    v_ori: 500.0,
                    v_leax: 5000.0,
                    v_reax: 1000.0,
                }))
            }
        }
    }

    fn named_speed(&self, module: usize, name: &str) -> Option<SpeedData> {
        let module_name = self.program.modules.get(module).map(|m| m.name.clone());
        let mut matching = self
            .program
            .speeds()
            .iter()
            .filter(|s| s.name.eq_ignore_ascii_case(name));
        let own = matching
            .clone()
            .find(|s| Some(&s.origin.module) == module_name.as_ref());
        own.or_else(|| matching.next())
            .map(|s| SpeedData {
                v_tcp: s.v_tcp.value,
                v_ori: s.v_ori.value,
                v_leax: s.v_leax.value,
                v_reax: s.v_reax.value,
            })
            .or_else(|| predefined_speed(name))
    }

    fn frame_names(
        &mut self,
        tool: Option<&Expr>,
        wobj: Option<&Expr>,
        frame: &mut Frame<'p>,
        line: u32,
    ) -> Result<(ToolData, WobjData)> {
        let name_of =
            |w: &mut Self, e: Option<&Expr>, frame: &mut Frame<'p>| -> Result<Option<String>> {
                Ok(match e {
                    None => None,
                    Some(e) => match w.eval(e, frame)? {
                        Value::Ref(n) => Some(n),
                        _ => Some(String::from("?")),
                    },
                })
            };
        let t = name_of(self, tool, frame)?;
        let o = name_of(self, wobj, frame)?;
        let tool = match self.frames.tool(t.as_deref()) {
            Some(t) => t.clone(),
            None => {
                self.note(
                    frame,
                    line,
                    format!(
                        "tool {} unknown here, timed with tool0",
                        t.as_deref().unwrap_or("?")
                    ),
                );
                ToolData::tool0()
            }
        };
        let wobj = match self.frames.wobj(o.as_deref()) {
            Some(w) => w.clone(),
            None => {
                self.note(
                    frame,
                    line,
                    format!(
                        "work object {} unknown here, timed with wobj0",
                        o.as_deref().unwrap_or("?")
                    ),
                );
                WobjData::wobj0()
            }
        };
        Ok((tool, wobj))
    }

    fn exec_move(
        &mut self,
        call: &'p Call,
        m: &Motion<'p>,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<()> {
        let line = s.pos.line;
        let kind = m.signature.kind;
        if kind == MotionKind::ExtJoint {
            self.note(
                frame,
                line,
                format!(
                    "{}: external axes are not modelled, taken as 0 s",
                    call.name
                ),
            );
            return Ok(());
        }
        let mut speed = self.speed_of(m.speed, frame, line)?;
        if let Some(v) = m.v {
            match self.eval(v, frame)?.num() {
                Some(v) => speed.v_tcp = v,
                None => self.note(frame, line, "\\V: value known only at run time, ignored"),
            }
        }
        let (ov, vmax) = self.velset;
        speed.v_tcp = (speed.v_tcp * ov).min(vmax);
        speed.v_ori *= ov;
        let t_override = match m.t {
            Some(t) => match self.eval(t, frame)?.num() {
                Some(t) => Some(t / ov),
                None => {
                    self.note(frame, line, "\\T: value known only at run time, ignored");
                    None
                }
            },
            None => None,
        };
        let (tool, wobj) = self.frame_names(m.tool, m.wobj, frame, line)?;
        let to = match m.to {
            Some(e) => self.eval(e, frame)?,
            None => Value::Unknown,
        };
        let from = target_of_flange(&self.arm.flange, &tool, &wobj);
        let max_speed = self.robot.max_speed_deg_s.map(|v| v * ov);
        match (kind, to) {
            (MotionKind::AbsJoint, Value::Joint(j)) => {
                let (q, id) = *j;
                let q_from = self.current_joints();
                let flange = self.robot.fk(&q);
                let tcp = match (&from, target_of_flange(&flange, &tool, &wobj)) {
                    (Ok(a), Ok(b)) => (b.translation.vector - a.translation.vector).norm(),
                    _ => 0.0,
                };
                let secs = match q_from {
                    Some(qf) => joint_move_seconds(&qf, &q, &max_speed, tcp, &speed),
                    None => seconds_for(tcp, speed.v_tcp),
                };
                let secs = t_override.unwrap_or(secs);
                self.advance(secs, m.conc);
                self.arm = Arm {
                    flange,
                    joints: Some(q),
                    conf: self.robot.conf_of(&q),
                };
                if let Some(i) = id {
                    if let Some(jt) = self.program.jointtargets().get(i) {
                        self.joint_schedule.visit(&jt.id, self.robot_free / 60.0);
                    }
                }
                return Ok(());
            }
            (MotionKind::AbsJoint, _) => {
                self.note(
                    frame,
                    line,
                    format!(
                        "{}: jointtarget known only at run time, taken as 0 s",
                        call.name
                    ),
                );
                return Ok(());
            }
            (_, Value::Rob(rob)) => {
                let flange = match flange_of_target(&rob.pose, &tool, &wobj) {
                    Ok(f) => f,
                    Err(e) => {
                        self.note(
                            frame,
                            line,
                            format!("{}: {}; taken as 0 s", call.name, e.message),
                        );
                        self.visit(&rob, self.robot_free);
                        return Ok(());
                    }
                };
                let from = from.unwrap_or(rob.pose);
                let mut via_info = None;
                let secs = match kind {
                    MotionKind::Joint => {
                        let q = self.joint_goal(&flange, &rob, &max_speed, call, frame, s)?;
                        let tcp = (rob.pose.translation.vector - from.translation.vector).norm();
                        let secs = match self.current_joints() {
                            Some(qf) => joint_move_seconds(&qf, &q, &max_speed, tcp, &speed),
                            None => seconds_for(tcp, speed.v_tcp),
                        };
                        self.arm.joints = Some(q);
                        secs
                    }
                    MotionKind::Circular => {
                        let cir = match m.via {
                            Some(e) => self.eval(e, frame)?,
                            None => Value::Unknown,
                        };
                        let angle = from.rotation.angle_to(&rob.pose.rotation).to_degrees();
                        let (len, frac, cir) = match cir {
                            Value::Rob(c) => {
                                let (len, to_via) = arc_length(
                                    &from.translation.vector,
                                    &c.pose.translation.vector,
                                    &rob.pose.translation.vector,
                                );
                                (len, if len > 0.0 { to_via / len } else { 0.5 }, Some(c))
                            }
                            _ => {
                                self.note(frame, line, format!("{}: CirPoint known only at run time, timed along the chord", call.name));
                                (
                                    (rob.pose.translation.vector - from.translation.vector).norm(),
                                    0.5,
                                    None,
                                )
                            }
                        };
                        via_info = cir.map(|c| (frac, c));
                        self.arm.joints = None;
                        seconds_for(len, speed.v_tcp).max(seconds_for(angle, speed.v_ori))
                    }
                    _ => {
                        self.arm.joints = None;
                        linear_move_seconds(&from, &rob.pose, &speed)
                    }
                };
                self.arm.flange = flange;
                self.arm.conf = rob.conf;
                let secs = t_override.unwrap_or(secs);
                let start = self.clock.max(self.robot_free);
                self.advance(secs, m.conc);
                if let Some((frac, c)) = via_info {
                    self.visit(&c, start + secs * frac);
                }
                self.visit(&rob, self.robot_free);
                return Ok(());
            }
            _ => {}
        }
        self.note(
            frame,
            line,
            format!(
                "{}: target known only at run time, not scheduled, taken as 0 s",
                call.name
            ),
        );
        self.arm.joints = None;
        Ok(())
    }

    /// Joints for a MoveJ target: the solution with its robconf, else (a
    /// robconf the pose does not have: taught loosely) the quickest
    /// solution from where the robot is, noted. No solution at all is an
    /// error naming the target.
    fn joint_goal(
        &mut self,
        flange: &Isometry3<f64>,
        rob: &Rob,
        max_speed: &[f64; 6],
        call: &Call,
        frame: &Frame,
        s: &Statement,
    ) -> Result<Joints> {
        let err = match self.robot.ik_conf(flange, &rob.conf) {
            Ok(q) => return Ok(q),
            Err(e) => e,
        };
        let sols = match self.robot.ik(flange) {
            Ok(sols) if !sols.is_empty() => sols,
            Ok(_) => return Err(self.unreachable(rob, call, frame, s, err)),
            Err(e) => return Err(self.unreachable(rob, call, frame, s, e)),
        };
        let from = self.current_joints().unwrap_or([0.0; 6]);
        let v = SpeedData {
            v_tcp: f64::INFINITY,
            v_ori: f64::INFINITY,
            v_leax: 0.0,
            v_reax: 0.0,
        };
        let best = sols
            .iter()
            .map(|sol| (joint_move_seconds(&from, &sol.q, max_speed, 0.0, &v), sol))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, sol)| *sol);
        let Some(best) = best else {
            return Err(self.unreachable(rob, call, frame, s, err));
        };
        let name = self.rob_name(rob);
        self.note(
            frame,
            s.pos.line,
            format!(
                "{} {name}: no solution with robconf {}; timed with the quickest reachable configuration {}",
                call.name, rob.conf, best.conf
            ),
        );
        Ok(best.q)
    }

    fn rob_name(&self, rob: &Rob) -> String {
        rob.id
            .or(rob.derived)
            .and_then(|i| self.program.targets().get(i))
            .map_or_else(|| "(computed target)".to_string(), |t| t.id.clone())
    }

    fn unreachable(&self, rob: &Rob, call: &Call, frame: &Frame, s: &Statement, e: Error) -> Error {
        let id = rob
            .id
            .or(rob.derived)
            .and_then(|i| self.program.targets().get(i));
        let name = id.map(|t| t.id.as_str()).unwrap_or("(computed)");
        let mut err = Error::new(
            ErrorKind::Unreachable,
            format!(
                "target {name} ({} at line {}): {}",
                call.name, s.pos.line, e.message
            ),
        );
        err = match id {
            Some(t) => err.at(self.program.location(&t.origin)),
            None => err.at(self.location(frame, s)),
        };
        for n in e.notes {
            err = err.with_note(n);
        }
        err
    }

    /// The robot's joints now, by IK of where it is if it came there on a
    /// linear path (one IK per joint move at most).
    fn current_joints(&mut self) -> Option<Joints> {
        if self.arm.joints.is_none() {
            // A robconf the pose does not have (ConfL \Off, loosely taught
            // targets): a solution on the same side of axis 1, else any.
            self.arm.joints = self
                .robot
                .ik_conf(&self.arm.flange, &self.arm.conf)
                .ok()
                .or_else(|| {
                    let sols = self.robot.ik(&self.arm.flange).ok()?;
                    let cf1 = self.arm.conf.cf1;
                    sols.iter()
                        .find(|s| s.conf.cf1 == cf1)
                        .or_else(|| sols.iter().next())
                        .map(|s| s.q)
                });
        }
        self.arm.joints
    }

    /// A motion of `secs` seconds: it starts when the robot is free and the
    /// program has got there; with `\Conc` the program runs on at once.
    fn advance(&mut self, secs: f64, conc: bool) {
        let start = self.clock.max(self.robot_free);
        // Absurd speeds (0, negative, overflowing arithmetic) add no time.
        let secs = if secs.is_finite() { secs.max(0.0) } else { 0.0 };
        self.robot_free = start + secs;
        self.clock = if conc { start } else { self.robot_free };
    }

    fn visit(&mut self, rob: &Rob, at_s: f64) {
        let t = at_s / 60.0;
        let targets = self.program.targets();
        if let Some(target) = rob.id.and_then(|i| targets.get(i)) {
            self.schedule.visit(&target.id, t);
        } else if let Some(target) = rob.derived.and_then(|i| targets.get(i)) {
            self.schedule.visit(&target.id, t);
            for &b in &rob.bases {
                self.base_visits.push((b, t));
            }
        }
    }

    // ------------------------------------------------------- expressions

    fn eval(&mut self, e: &Expr, frame: &mut Frame<'p>) -> Result<Value> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_SEGMENT, || self.eval_inner(e, frame))
    }

    fn eval_inner(&mut self, e: &Expr, frame: &mut Frame<'p>) -> Result<Value> {
        Ok(match e {
            Expr::Num(n) => Value::Num(n.value),
            Expr::Bool(b) => Value::Bool(*b),
            Expr::Str(s) => Value::Str(s.to_string()),
            Expr::Placeholder(_) => Value::Unknown,
            Expr::Target(i) => self.target_value(*i)?,
            Expr::JointTarget(i) => self.joint_value(*i),
            Expr::Name(n) => self.name_value(n, frame)?,
            Expr::Index(_) | Expr::Component(_) => match self.path_of(e, frame)? {
                Some(path) => self.path_value(&path, frame.module)?,
                None => Value::Unknown,
            },
            Expr::Aggregate(a) => {
                let mut items = Vec::with_capacity(a.items.len());
                for it in &a.items {
                    items.push(self.eval(it, frame)?);
                }
                Value::Agg(items)
            }
            Expr::Unary(op, x) => {
                let v = self.eval(x, frame)?;
                match (op, v) {
                    (UnaryOp::Neg, Value::Num(v)) => Value::Num(-v),
                    (UnaryOp::Plus, Value::Num(v)) => Value::Num(v),
                    (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
                    _ => Value::Unknown,
                }
            }
            Expr::Binary(b) => {
                let (op, l, r) = b.as_ref();
                let l = self.eval(l, frame)?;
                let r = self.eval(r, frame)?;
                binary(*op, &l, &r)
            }
            Expr::Call(c) => self.call_value(c, frame)?,
        })
    }

    fn target_value(&self, i: usize) -> Result<Value> {
        let Some(t) = self.program.targets().get(i) else {
            return Ok(Value::Unknown);
        };
        Ok(match target_pose(self.program, t)? {
            Some((pose, conf)) => Value::Rob(Box::new(Rob {
                pose,
                conf,
                id: Some(i),
                derived: None,
                bases: Vec::new(),
            })),
            None => Value::Unknown,
        })
    }

    fn joint_value(&self, i: usize) -> Value {
        match self.program.jointtargets().get(i) {
            Some(j) => Value::Joint(Box::new((
                j.robax.each_ref().map(|n| n.value.to_radians()),
                Some(i),
            ))),
            None => Value::Unknown,
        }
    }

    /// `arr{2}.pos` with its indices evaluated, or `None` where an index is
    /// not known or the root is a routine's own variable.
    fn path_of(&mut self, e: &Expr, frame: &mut Frame<'p>) -> Result<Option<String>> {
        Ok(match e {
            Expr::Name(n) => {
                if frame.vars.contains_key(&n.to_ascii_lowercase()) {
                    None
                } else {
                    Some(n.to_string())
                }
            }
            Expr::Index(b) => {
                let (base, idx) = b.as_ref();
                let Some(base) = self.path_of(base, frame)? else {
                    return Ok(None);
                };
                let mut parts = Vec::new();
                for i in idx {
                    match self.eval(i, frame)?.num() {
                        Some(v) if v.fract() == 0.0 && v.abs() < 1e12 => {
                            parts.push((v as i64).to_string())
                        }
                        _ => return Ok(None),
                    }
                }
                Some(format!("{base}{{{}}}", parts.join(",")))
            }
            Expr::Component(b) => {
                let (base, field) = b.as_ref();
                self.path_of(base, frame)?.map(|p| format!("{p}.{field}"))
            }
            _ => None,
        })
    }

    /// The target or jointtarget with this path, seen from `module`.
    fn path_value(&mut self, path: &str, module: usize) -> Result<Value> {
        let lower = path.to_ascii_lowercase();
        let module_name = self
            .program
            .modules
            .get(module)
            .map(|m| m.name.to_ascii_lowercase())
            .unwrap_or_default();
        let qualified = format!("{module_name}:{lower}");
        let hit = self
            .target_ids
            .get(&qualified)
            .or_else(|| self.target_ids.get(&lower))
            .copied();
        if let Some(i) = hit {
            if let Some(t) = self.program.targets().get(i) {
                if t.value.is_some() {
                    return self.target_value(i);
                }
            }
        }
        let jhit = self
            .joint_ids
            .get(&qualified)
            .or_else(|| self.joint_ids.get(&lower))
            .copied();
        if let Some(i) = jhit {
            return Ok(self.joint_value(i));
        }
        Ok(Value::Unknown)
    }

    fn name_value(&mut self, name: &str, frame: &mut Frame<'p>) -> Result<Value> {
        let key = name.to_ascii_lowercase();
        if let Some(v) = frame.vars.get(&key) {
            return Ok(v.clone());
        }
        if let Some(r) = frame.routine {
            if let Some(d) = r.data.iter().find(|d| d.name.eq_ignore_ascii_case(name)) {
                return self.decl_value(frame.module, Some(r), d);
            }
        }
        if let Some(v) = self.globals.get(&key) {
            return Ok(v.clone());
        }
        match key.as_str() {
            "true" => return Ok(Value::Bool(true)),
            "false" => return Ok(Value::Bool(false)),
            _ => {}
        }
        let decl = self.decls.get(&key).and_then(|list| {
            list.iter()
                .find(|(m, _)| *m == frame.module)
                .or_else(|| {
                    list.iter()
                        .find(|(_, d)| d.scope != Some(rapid::Scope::Local))
                })
                .copied()
        });
        match decl {
            Some((m, d)) => self.decl_value(m, None, d),
            None => Ok(Value::Ref(name.to_string())),
        }
    }

    fn decl_value(
        &mut self,
        module: usize,
        routine: Option<&'p Routine>,
        d: &'p DataDecl,
    ) -> Result<Value> {
        let ty = d.type_name.to_ascii_lowercase();
        match ty.as_str() {
            "robtarget" | "jointtarget" if d.dims.is_empty() => {
                let v = self.path_value(&d.name, module)?;
                if !matches!(v, Value::Unknown) {
                    return Ok(v);
                }
                // A declared derived target: evaluate its expression.
                if d.storage == rapid::Storage::Const {
                    if let Some(init) = &d.init {
                        return self.eval_decl(module, routine, d, init);
                    }
                }
                Ok(Value::Unknown)
            }
            "num" | "dnum" | "bool" | "string" if d.storage == rapid::Storage::Const => {
                match &d.init {
                    Some(init) if d.dims.is_empty() => self.eval_decl(module, routine, d, init),
                    _ => Ok(Value::Unknown),
                }
            }
            "num" | "dnum" | "bool" | "string" | "robtarget" | "jointtarget" => Ok(Value::Unknown),
            _ => Ok(Value::Ref(d.name.clone())),
        }
    }

    fn eval_decl(
        &mut self,
        module: usize,
        routine: Option<&'p Routine>,
        d: &DataDecl,
        init: &Expr,
    ) -> Result<Value> {
        let key = format!("{module}:{}", d.name.to_ascii_lowercase());
        if !self.evaluating.insert(key.clone()) {
            return Ok(Value::Unknown);
        }
        let mut f = Frame {
            module,
            routine,
            vars: HashMap::new(),
        };
        let v = self.eval(init, &mut f);
        self.evaluating.remove(&key);
        v
    }

    fn call_value(&mut self, c: &FunctionCall, frame: &mut Frame<'p>) -> Result<Value> {
        let name = c.name.to_ascii_lowercase();
        let positional: Vec<&Expr> = c
            .args
            .iter()
            .filter(|a| !a.optional)
            .filter_map(|a| a.value.as_ref())
            .collect();
        let optional = |n: &str| {
            c.args.iter().find(|a| {
                a.optional && a.name.as_deref().is_some_and(|x| x.eq_ignore_ascii_case(n))
            })
        };
        let file = self.program.modules.get(frame.module).map_or(0, |m| m.file);
        let derived = self.derived_at.get(&(file, c.span.start)).copied();
        match name.as_str() {
            "offs" | "reltool" => {
                let mut vals = Vec::new();
                for e in &positional {
                    vals.push(self.eval(e, frame)?);
                }
                let (Some(Value::Rob(p)), Some(dx), Some(dy), Some(dz)) = (
                    vals.first(),
                    vals.get(1).and_then(Value::num),
                    vals.get(2).and_then(Value::num),
                    vals.get(3).and_then(Value::num),
                ) else {
                    return Ok(Value::Unknown);
                };
                let pose = if name == "offs" {
                    Translation3::new(dx, dy, dz) * p.pose
                } else {
                    let mut rot = [0.0; 3];
                    for (k, axis) in ["Rx", "Ry", "Rz"].iter().enumerate() {
                        if let Some(a) = optional(axis).and_then(|a| a.value.as_ref()) {
                            match self.eval(a, frame)?.num() {
                                Some(v) => rot[k] = v.to_radians(),
                                None => return Ok(Value::Unknown),
                            }
                        }
                    }
                    let r = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), rot[0])
                        * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), rot[1])
                        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), rot[2]);
                    p.pose * Isometry3::from_parts(Translation3::new(dx, dy, dz), r)
                };
                let bases = match p.id {
                    Some(i) => vec![i],
                    None => p.bases.clone(),
                };
                Ok(Value::Rob(Box::new(Rob {
                    pose,
                    conf: p.conf,
                    id: None,
                    derived,
                    bases,
                })))
            }
            "crobt" => {
                let tool = optional("Tool").and_then(|a| a.value.as_ref());
                let wobj = optional("WObj").and_then(|a| a.value.as_ref());
                let (tool, wobj) = self.frame_names(tool, wobj, frame, 0)?;
                Ok(match target_of_flange(&self.arm.flange, &tool, &wobj) {
                    Ok(pose) => Value::Rob(Box::new(Rob {
                        pose,
                        conf: self.arm.conf,
                        id: None,
                        derived,
                        bases: Vec::new(),
                    })),
                    Err(_) => Value::Unknown,
                })
            }
            "cjointt" => Ok(match self.current_joints() {
                Some(q) => Value::Joint(Box::new((q, None))),
                None => Value::Unknown,
            }),
            "present" => Ok(match positional.first().and_then(|e| e.as_name()) {
                Some(n) => {
                    if frame.vars.contains_key(&n.to_ascii_lowercase()) {
                        Value::Bool(true)
                    } else if frame.routine.is_some_and(|r| {
                        r.params
                            .iter()
                            .any(|p| p.optional && p.name.eq_ignore_ascii_case(n))
                    }) {
                        Value::Bool(false)
                    } else {
                        Value::Unknown
                    }
                }
                None => Value::Unknown,
            }),
            "dim" => {
                let which = match positional.get(1) {
                    Some(e) => self.eval(e, frame)?.num(),
                    None => None,
                };
                let Some(n) = positional.first().and_then(|e| e.as_name()) else {
                    return Ok(Value::Unknown);
                };
                let decl = frame
                    .routine
                    .and_then(|r| {
                        r.data
                            .iter()
                            .find(|d| d.name.eq_ignore_ascii_case(n))
                            .map(|d| (frame.module, d))
                    })
                    .or_else(|| {
                        self.decls.get(&n.to_ascii_lowercase()).and_then(|l| {
                            l.iter()
                                .find(|(m, _)| *m == frame.module)
                                .or_else(|| l.first())
                                .copied()
                        })
                    });
                let (Some((m, d)), Some(k)) = (decl, which) else {
                    return Ok(Value::Unknown);
                };
                let Some(dim) = (k >= 1.0).then(|| d.dims.get(k as usize - 1)).flatten() else {
                    return Ok(Value::Unknown);
                };
                let mut f = Frame {
                    module: m,
                    routine: None,
                    vars: HashMap::new(),
                };
                self.eval(dim, &mut f)
            }
            "abs" | "sqrt" | "round" | "trunc" | "sin" | "cos" | "tan" => {
                let x = match positional.first() {
                    Some(e) => self.eval(e, frame)?.num(),
                    None => None,
                };
                Ok(match x {
                    Some(x) => Value::Num(match name.as_str() {
                        "abs" => x.abs(),
                        "sqrt" => x.sqrt(),
                        "round" => x.round(),
                        "trunc" => x.trunc(),
                        "sin" => x.to_radians().sin(),
                        "cos" => x.to_radians().cos(),
                        _ => x.to_radians().tan(),
                    }),
                    None => Value::Unknown,
                })
            }
            _ => match self.find_routine(frame.module, &c.name) {
                Some((mi, r)) if r.kind == RoutineKind::Func => {
                    let vars = self.bind(r, &c.args, frame)?;
                    let v = match self.call_routine(mi, r, vars, r.pos.line)? {
                        Flow::Return(v) => v,
                        _ => Value::Unknown,
                    };
                    Ok(match v {
                        Value::Rob(mut rob) if rob.id.is_none() => {
                            rob.derived = derived.or(rob.derived);
                            Value::Rob(rob)
                        }
                        v => v,
                    })
                }
                _ => Ok(Value::Unknown),
            },
        }
    }
}

fn binary(op: BinaryOp, l: &Value, r: &Value) -> Value {
    use BinaryOp::*;
    match (l, r) {
        (Value::Num(a), Value::Num(b)) => {
            let (a, b) = (*a, *b);
            match op {
                Add => Value::Num(a + b),
                Sub => Value::Num(a - b),
                Mul => Value::Num(a * b),
                Div if b != 0.0 => Value::Num(a / b),
                IntDiv if b != 0.0 => Value::Num((a / b).trunc()),
                Mod if b != 0.0 => Value::Num(a % b),
                Lt => Value::Bool(a < b),
                Le => Value::Bool(a <= b),
                Eq => Value::Bool(a == b),
                Ne => Value::Bool(a != b),
                Ge => Value::Bool(a >= b),
                Gt => Value::Bool(a > b),
                _ => Value::Unknown,
            }
        }
        (Value::Bool(a), Value::Bool(b)) => match op {
            And => Value::Bool(*a && *b),
            Or => Value::Bool(*a || *b),
            Xor => Value::Bool(a != b),
            Eq => Value::Bool(a == b),
            Ne => Value::Bool(a != b),
            _ => Value::Unknown,
        },
        // FALSE AND anything, TRUE OR anything.
        (Value::Bool(false), _) | (_, Value::Bool(false)) if op == And => Value::Bool(false),
        (Value::Bool(true), _) | (_, Value::Bool(true)) if op == Or => Value::Bool(true),
        (Value::Str(a), Value::Str(b)) => match op {
            Add => Value::Str(format!("{a}{b}")),
            Eq => Value::Bool(a == b),
            Ne => Value::Bool(a != b),
            _ => Value::Unknown,
        },
        _ => Value::Unknown,
    }
}

/// Instructions that take no time worth counting (I/O, messages,
/// settings, interrupts): not noted when met.
fn is_instant_builtin(name: &str) -> bool {
    const INSTANT: &[&str] = &[
        "tpwrite",
        "tperase",
        "tpshow",
        "errwrite",
        "setdo",
        "setao",
        "setgo",
        "set",
        "reset",
        "pulsedo",
        "invertdo",
        "incr",
        "decr",
        "add",
        "clear",
        "confl",
        "confj",
        "singarea",
        "accset",
        "pathacclim",
        "worldacclim",
        "gripload",
        "stopmove",
        "startmove",
        "startmoveretry",
        "stopmovereset",
        "clearpath",
        "isignaldi",
        "isignaldo",
        "isignalai",
        "isignalao",
        "isignalgi",
        "isignalgo",
        "itimer",
        "idelete",
        "isleep",
        "iwatch",
        "ienable",
        "idisable",
        "ierror",
        "ipers",
        "triggio",
        "triggequip",
        "triggint",
        "triggcheckio",
        "triggspeed",
        "movelsync",
        "tunereset",
        "pdispoff",
        "pdispon",
        "pdispset",
        "eoffsoff",
        "eoffson",
        "eoffsset",
        "cornerpathwarning",
        "skipwarn",
        "errlog",
        "raisetouser",
        "close",
        "open",
        "write",
        "writebin",
        "writestrbin",
        "rewind",
        "load",
        "unload",
        "startload",
        "waitload",
        "erase",
        "setsysdata",
        "tpreadfk",
        "tpreadnum",
        "stoptrigg",
        "resetretrycount",
        "bookerrno",
        "errraise",
        "velset",
        "softact",
        "softdeact",
        "activateunit",
        "deactunit",
        "mechunitload",
        "ccwtimeout",
        "setdataval",
        "getdataval",
        "stpathfollow",
        "arcrefresh",
    ];
    INSTANT.contains(&name)
}

/// Length of the circular arc from `a` through `b` to `c`, and of its part
/// from `a` to `b` (mm). Collinear points: the two straight segments.
fn arc_length(a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>) -> (f64, f64) {
    let u = b - a;
    let v = c - a;
    let w = u.cross(&v);
    let w2 = w.norm_squared();
    if w2 <= 1e-12 * u.norm_squared().max(1.0) * v.norm_squared().max(1.0) {
        let ab = u.norm();
        return (ab + (c - b).norm(), ab);
    }
    let centre = a + (v.cross(&w) * u.norm_squared() + w.cross(&u) * v.norm_squared()) / (2.0 * w2);
    let n = w / w2.sqrt();
    let ra = a - centre;
    let radius = ra.norm();
    // Angle from `a` to `x` counter-clockwise about the normal (a→b→c runs
    // counter-clockwise about u×v).
    let angle = |x: &Vector3<f64>| {
        let rx = x - centre;
        let t = n.dot(&ra.cross(&rx)).atan2(ra.dot(&rx));
        if t < 0.0 {
            t + std::f64::consts::TAU
        } else {
            t
        }
    };
    (radius * angle(c), radius * angle(b))
}

/// A CSV field, quoted where it holds a comma or a quote (`pGrid{2,1}`).
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    #[test]
    fn predefined_speeds() {
        assert_eq!(predefined_speed("v100").unwrap().v_tcp, 100.0);
        assert_eq!(predefined_speed("V1000").unwrap().v_ori, 500.0);
        assert_eq!(predefined_speed("vmax").unwrap().v_tcp, 5000.0);
        assert!(predefined_speed("v123").is_none());
        assert!(predefined_speed("fine").is_none());
    }

    #[test]
    fn linear_move_takes_the_slower_of_path_and_reorientation() {
        let a = Isometry3::identity();
        let b = Isometry3::from_parts(
            Translation3::new(300.0, 400.0, 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 90f64.to_radians()),
        );
        let v100 = predefined_speed("v100").unwrap();
        assert_relative_eq!(linear_move_seconds(&a, &b, &v100), 5.0, epsilon = 1e-12);
        let slow_ori = SpeedData { v_ori: 9.0, ..v100 };
        assert_relative_eq!(linear_move_seconds(&a, &b, &slow_ori), 10.0, epsilon = 1e-9);
    }

    #[test]
    fn joint_move_is_limited_by_the_slowest_axis() {
        let from = [0.0; 6];
        let to = [90f64.to_radians(), 0.0, 0.0, 0.0, 0.0, 0.0];
        let max = [200.0, 200.0, 260.0, 360.0, 360.0, 450.0];
        let v = predefined_speed("v5000").unwrap();
        assert_relative_eq!(
            joint_move_seconds(&from, &to, &max, 0.0, &v),
            0.45,
            epsilon = 1e-12
        );
        let v5 = predefined_speed("v5").unwrap();
        assert_relative_eq!(
            joint_move_seconds(&from, &to, &max, 100.0, &v5),
            20.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn visits_pick_first_mean_last() {
        let t = [40.0, 70.0, 55.0];
        assert_eq!(Visit::First.pick(&t), 40.0);
        assert_eq!(Visit::Last.pick(&t), 70.0);
        assert_relative_eq!(Visit::Mean.pick(&t), 55.0);
    }

    #[test]
    fn schedule_round_trips_through_csv() {
        let mut s = Schedule::new();
        s.visit("p10", 40.0);
        s.visit("main#3", 41.5);
        s.visit("P10", 70.0);
        let csv = s.to_csv();
        assert_eq!(
            csv,
            "target,time_min\np10,40.0000\nmain#3,41.5000\np10,70.0000\n"
        );
        let back = Schedule::read("s.csv", csv.as_bytes()).unwrap();
        assert_eq!(back.times("p10").unwrap(), &[40.0, 70.0]);
        let mut grid = Schedule::new();
        grid.visit("pGrid{2,1}", 1.5);
        assert_eq!(grid.to_csv(), "target,time_min\n\"pGrid{2,1}\",1.5000\n");
        let grid_back = Schedule::read("s.csv", grid.to_csv().as_bytes()).unwrap();
        assert_eq!(grid_back.times("pgrid{2,1}").unwrap(), &[1.5]);
        assert_eq!(back.targets(), &["p10".to_string(), "main#3".to_string()]);
    }

    #[test]
    fn schedule_errors_are_located() {
        let e = Schedule::read("s.csv", b"target,time_min\np10,-1\n").unwrap_err();
        assert_eq!(e.location.unwrap().line, 2);
        let e = Schedule::read("s.csv", b"target\np10\n").unwrap_err();
        assert!(e.message.contains("time_min"));
    }
}
