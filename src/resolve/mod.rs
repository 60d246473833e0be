//! From a program's RAPID values to robot frames: its tooldata and
//! wobjdata as [`ToolData`]/[`WobjData`], each robtarget as a pose with its
//! robconf, and for each target the tool and work object the program moves
//! to it with.
//!
//! Owns what a program means by its targets, shared by `schedule`,
//! `correct` and `diagnose` (programs as pose sets). May import `rapid`,
//! `robot` and the shared `error`; never `model`, `schedule` or the jobs.

use crate::error::{Error, ErrorKind, Result, Subject};
use crate::rapid::targets::TargetIndex;
use crate::rapid::{self, Block, Expr, NoCase, Program, Target, TargetKind};
use crate::robot::conf::RobConf;
use crate::robot::frames::{pose_from_rapid, ToolFrame, WobjFrames};
use nalgebra::Isometry3;
use std::borrow::Cow;
use std::collections::HashMap;

pub mod arm;
mod calls;
pub mod dataflow;
mod each_move;
mod frame_vars;
pub mod listing;
pub mod monitoring;
mod moves;
mod params;
mod per_call;
mod statements;
mod uses;

pub use frame_vars::frame_variables;
pub use moves::{each_move_instruction, each_move_instruction_with, Move, Point};
pub use params::settled_parameters;
pub use per_call::unsettled_frame_parameters;
pub use statements::{walk_calls, walk_items, walk_statements};

use each_move::{each_move, reached_by_routine};
use uses::{offset32, Packed, Site, UsesBuilder};
pub use uses::{UseRef, Uses};

/// The tools and work objects a program declares, by lower-case name, with
/// RAPID's predefined `tool0` and `wobj0`.
#[derive(Debug, Clone)]
pub struct Frames {
    /// By lower-case name, hashed fast: each of a million targets looks
    /// its tool and work object up (SipHash was 2 % of a correction).
    tools: foldhash::HashMap<String, ToolFrame>,
    wobjs: foldhash::HashMap<String, WobjFrames>,
}

impl Frames {
    /// Convert every tooldata and wobjdata declaration of the program.
    pub fn of_program(program: &Program) -> Result<Frames> {
        let mut tools = foldhash::HashMap::default();
        tools.insert("tool0".to_string(), ToolFrame::tool0());
        for t in program.tools() {
            let tool = ToolFrame::new(
                t.robhold.value,
                t.tframe_trans.each_ref().map(|n| n.value),
                t.tframe_rot.each_ref().map(|n| n.value),
            )
            .map_err(|e| {
                located(
                    program,
                    &t.origin,
                    format!("tooldata `{}`: {}", t.name, e.message),
                )
            })?;
            tools.insert(t.name.to_ascii_lowercase(), tool);
        }
        let mut wobjs = foldhash::HashMap::default();
        wobjs.insert("wobj0".to_string(), WobjFrames::wobj0());
        for w in program.wobjs() {
            let frame = |trans: &[rapid::Number; 3], rot: &[rapid::Number; 4]| {
                (
                    trans.each_ref().map(|n| n.value),
                    rot.each_ref().map(|n| n.value),
                )
            };
            let wobj = WobjFrames::new(
                w.robhold.value,
                w.ufprog.value,
                &w.ufmec,
                frame(&w.uframe_trans, &w.uframe_rot),
                frame(&w.oframe_trans, &w.oframe_rot),
            )
            .map_err(|e| {
                located(
                    program,
                    &w.origin,
                    format!("wobjdata `{}`: {}", w.name, e.message),
                )
            })?;
            wobjs.insert(w.name.to_ascii_lowercase(), wobj);
        }
        Ok(Frames { tools, wobjs })
    }

    /// The same frames for a robot whose base stands at `base` in the
    /// world: work objects the robot does not hold, and tools it does not
    /// hold, are written in world coordinates; the arm reaches them in its
    /// base frame. (Work objects a mechanical unit moves are left alone
    /// elsewhere.)
    pub fn placed(mut self, base: &Isometry3<f64>) -> Frames {
        let inv = base.inverse();
        for w in self.wobjs.values_mut() {
            if !w.robhold {
                w.uframe = inv * w.uframe;
            }
        }
        for t in self.tools.values_mut() {
            if !t.robhold {
                t.tframe = inv * t.tframe;
            }
        }
        self
    }

    /// The tooldata of this name (`tool0` when `None`).
    pub fn tool(&self, name: Option<&str>) -> Option<&ToolFrame> {
        by_name(&self.tools, name.unwrap_or("tool0"))
    }

    /// The wobjdata of this name (`wobj0` when `None`).
    pub fn wobj(&self, name: Option<&str>) -> Option<&WobjFrames> {
        by_name(&self.wobjs, name.unwrap_or("wobj0"))
    }
}

/// `name` in a map by lower-case name: copied to lower case only where it
/// is not (each of a million targets asks for its tool and work object).
fn by_name<'m, T>(map: &'m foldhash::HashMap<String, T>, name: &str) -> Option<&'m T> {
    if !name.bytes().any(|b| b.is_ascii_uppercase()) {
        return map.get(name);
    }
    // A RAPID name has at most 32 characters: lowered on the stack, not
    // in a string made for each target (`tProbe`, a million times).
    let mut lower = [0u8; 32];
    match lower.get_mut(..name.len()) {
        Some(buf) => {
            buf.copy_from_slice(name.as_bytes());
            buf.make_ascii_lowercase();
            map.get(std::str::from_utf8(buf).ok()?)
        }
        None => map.get(&name.to_ascii_lowercase()),
    }
}

fn located(program: &Program, origin: &rapid::Origin, message: String) -> Error {
    Error::input(message).at(program.location(origin))
}

/// A robtarget's pose (TCP in its work object) and robconf, from its
/// numbers.
pub fn target_pose(
    program: &Program,
    target: &Target,
) -> Result<Option<(Isometry3<f64>, RobConf)>> {
    let Some(v) = &target.value else {
        return Ok(None);
    };
    let about = || Subject::Target(target.id.clone());
    let pose = pose_from_rapid(v.trans_values(), v.rot_values())
        .map_err(|e| located(program, &target.origin, e.message).about(about()))?;
    let conf = robconf_of(v.robconf_values()).map_err(|x| {
        located(
            program,
            &target.origin,
            format!("robconf value {x} is not a whole number"),
        )
        .about(about())
    })?;
    Ok(Some((pose, conf)))
}

/// A robconf from its four written numbers; `Err` with the first that is
/// not a whole number.
pub fn robconf_of(cf: [f64; 4]) -> std::result::Result<RobConf, f64> {
    let whole = |x: f64| {
        (x.fract() == 0.0 && x.abs() < 1e6)
            .then_some(x as i32)
            .ok_or(x)
    };
    Ok(RobConf::new(
        whole(cf[0])?,
        whole(cf[1])?,
        whole(cf[2])?,
        whole(cf[3])?,
    ))
}

/// The tool and work object one motion instruction uses for a target.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Usage {
    /// How the move reaches the target.
    pub through: Through,
    pub tool: Option<String>,
    pub wobj: Option<String>,
    /// The instruction (`MoveL`) and where it is, for messages.
    pub instruction: String,
    pub routine: String,
    pub line: u32,
    /// The file (index into [`Program::files`]) and byte offset where the
    /// instruction starts, for edits of its arguments.
    pub file: usize,
    pub offset: usize,
}

impl Usage {
    /// The tool's name as written (`tool0` when the move names none).
    pub fn tool_name(&self) -> &str {
        self.tool.as_deref().unwrap_or("tool0")
    }

    /// The work object's name as written (`wobj0` when the move names
    /// none).
    pub fn wobj_name(&self) -> &str {
        self.wobj.as_deref().unwrap_or("wobj0")
    }

    /// Whether two uses move with the same tool and work object (by name,
    /// as RAPID compares names: case-insensitively).
    pub fn same_frames(&self, other: &Usage) -> bool {
        self.tool_name().eq_ignore_ascii_case(other.tool_name())
            && self.wobj_name().eq_ignore_ascii_case(other.wobj_name())
    }
}

/// A target's uses grouped by tool and work object, in program order of
/// each pair's first use: the first group is the pair the target is
/// corrected for (see [`frames_of`]).
pub fn uses_by_frames(uses: &[Usage]) -> Vec<Vec<&Usage>> {
    let mut groups: Vec<Vec<&Usage>> = Vec::new();
    for u in uses {
        match groups.iter_mut().find(|g| g[0].same_frames(u)) {
            Some(g) => g.push(u),
            None => groups.push(vec![u]),
        }
    }
    groups
}

/// How a move reaches a target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Through {
    /// The move names it (or is written with it).
    Direct,
    /// Through a derived expression (`Offs(p10, 0, 0, 50)`): the index of
    /// that expression among the program's targets.
    Derived(usize),
    /// Through a variable the run assigns from it (`pAbove := Offs(p10,
    /// ...); MoveL pAbove`): the pose is decided at run time.
    Variable,
}

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
    index: TargetIndex<'p>,
    aliases: HashMap<String, Vec<String>>,
    /// What the moves by name of each run reach, kept by the first walk
    /// ([`uses_with`]) for the next ([`each_move_instruction_with`]): a
    /// million names looked up among a million targets, a cache miss
    /// each, once instead of twice.
    named: Vec<each_move::Named>,
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

/// A routine's statement lists: its body, and its backward, undo and
/// error handlers.
pub(crate) fn routine_bodies(routine: &rapid::Routine) -> impl Iterator<Item = &Block> {
    [
        Some(&routine.body),
        routine.backward.as_ref(),
        routine.undo.as_ref(),
        routine.error.as_ref().map(|(_, s)| s),
    ]
    .into_iter()
    .flatten()
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

/// What a move's target argument is.
#[derive(Clone, Copy)]
enum Reach<'a> {
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
fn describe(expr: &Expr) -> String {
    match expr {
        Expr::Name(n) => n.to_string(),
        Expr::Index(b) => format!("{}{{…}}", describe(&b.0)),
        Expr::Component(b) => format!("{}.{}", describe(&b.0), b.1),
        Expr::Call(c) => format!("{}(…)", c.name),
        _ => "an expression".to_string(),
    }
}

/// Whether a tool or work-object name is one a declaration can have.
fn is_plain_name(name: &str) -> bool {
    name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// What resolving the targets an expression reads needs.
struct Refs<'a> {
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
type Scope<'s> = (&'s str, &'s str);

/// What a move reaches: one target, or every target of a stretch (an
/// array's elements through an index known only at run time).
enum Reached {
    One(usize),
    All(std::ops::Range<usize>),
}

impl<'a> Refs<'a> {
    fn new(
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
    fn passed(&self, id: &str, (module, routine): Scope) -> Option<usize> {
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
    fn targets(&self, reach: Reach, module: Scope) -> Vec<(Reached, Through)> {
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
fn access_pattern(expr: &Expr) -> Option<String> {
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

/// Case-insensitive match of an identifier against a pattern whose `*`
/// stands for one index (an optionally signed whole number).
fn glob_match(pattern: &str, id: &str) -> bool {
    let (p, s) = (pattern.as_bytes(), id.as_bytes());
    let (mut i, mut j) = (0, 0);
    while i < p.len() {
        if p[i] == b'*' {
            let start = j;
            if j < s.len() && s[j] == b'-' {
                j += 1;
            }
            while j < s.len() && s[j].is_ascii_digit() {
                j += 1;
            }
            if j == start || (j == start + 1 && s[start] == b'-') {
                return false;
            }
            i += 1;
        } else {
            if j >= s.len() || !p[i].eq_ignore_ascii_case(&s[j]) {
                return false;
            }
            i += 1;
            j += 1;
        }
    }
    j == s.len()
}

/// The one tool/work-object pair a target is corrected for: its first
/// use's, in program order (as [`usages`] lists them). A target moved to
/// with other pairs too is still corrected for the first; what that
/// leaves at the other uses is the job's to report. An unknown name is an
/// error.
pub fn frames_of(
    program: &Program,
    frames: &Frames,
    index: usize,
    uses: Option<&Vec<Usage>>,
) -> Result<(ToolFrame, WobjFrames, Option<String>, Option<String>)> {
    let target = program.targets().at(index);
    let first = uses
        .and_then(|u| u.first())
        .map(|f| (f.tool.as_deref(), f.wobj.as_deref()));
    frames_for(program, frames, &target, first)
}

/// [`frames_of`] for `target`, whose first use names `first` (its tool
/// and work object as written; `None`: no move reaches it, and the target
/// names its own instruction's).
pub fn frames_for(
    program: &Program,
    frames: &Frames,
    target: &Target,
    first: Option<(Option<&str>, Option<&str>)>,
) -> Result<(ToolFrame, WobjFrames, Option<String>, Option<String>)> {
    let (tool, wobj, tool_name, wobj_name) = frames_for_in(program, frames, target, first)?;
    Ok((
        tool.clone(),
        wobj.clone(),
        tool_name.map(Cow::into_owned),
        wobj_name.map(Cow::into_owned),
    ))
}

/// [`frames_for`] without a copy (a million targets ask): the table's
/// frames, the first move's names (the target's own copied).
pub fn frames_for_in<'f>(
    program: &Program,
    frames: &'f Frames,
    target: &Target,
    first: Option<(Option<&'f str>, Option<&'f str>)>,
) -> Result<FramesFound<'f>> {
    let (tool_name, wobj_name): (Option<Cow<'f, str>>, Option<Cow<'f, str>>) = match first {
        Some((tool, wobj)) => (tool.map(Cow::Borrowed), wobj.map(Cow::Borrowed)),
        None => (
            target.tool.as_deref().map(|n| Cow::Owned(n.to_string())),
            target.wobj.as_deref().map(|n| Cow::Owned(n.to_string())),
        ),
    };
    let (tool, wobj) = frames_named_in(
        program,
        frames,
        target,
        tool_name.as_deref(),
        wobj_name.as_deref(),
    )?;
    Ok((tool, wobj, tool_name, wobj_name))
}

/// A target's tool and work object, and their names where written.
pub type FramesFound<'f> = (
    &'f ToolFrame,
    &'f WobjFrames,
    Option<Cow<'f, str>>,
    Option<Cow<'f, str>>,
);

/// The tooldata and wobjdata of these names (`tool0`/`wobj0` for `None`)
/// for `target`; an unknown name is an error located at the target.
pub fn frames_named(
    program: &Program,
    frames: &Frames,
    target: &Target,
    tool_name: Option<&str>,
    wobj_name: Option<&str>,
) -> Result<(ToolFrame, WobjFrames)> {
    let (tool, wobj) = frames_named_in(program, frames, target, tool_name, wobj_name)?;
    Ok((tool.clone(), wobj.clone()))
}

/// [`frames_named`], the frames as the table holds them: what a million
/// targets' corrections read, each without a copy.
pub fn frames_named_in<'f>(
    program: &Program,
    frames: &'f Frames,
    target: &Target,
    tool_name: Option<&str>,
    wobj_name: Option<&str>,
) -> Result<(&'f ToolFrame, &'f WobjFrames)> {
    let unknown = |what: &str, data: &str, name: &str| {
        if is_plain_name(name) {
            located(
                program,
                &target.origin,
                format!("unknown {what} `{name}` (no {data} of that name in the program)"),
            )
            .about(Subject::Target(target.id.clone()))
            .with_note(ELSEWHERE)
        } else {
            located(
                program,
                &target.origin,
                format!(
                    "the {what} is `{name}`, which only the run decides (not a {data} declared by name); correcting it for another {what} would be silently wrong"
                ),
            )
            .about(Subject::Target(target.id.clone()))
            .with_note("name the tooldata/wobjdata in the move instruction, or correct such targets by hand")
        }
    };
    let tool = frames
        .tool(tool_name)
        .ok_or_else(|| unknown("tool", "tooldata", tool_name.unwrap_or("tool0")))?;
    let wobj = frames
        .wobj(wobj_name)
        .ok_or_else(|| unknown("work object", "wobjdata", wobj_name.unwrap_or("wobj0")))?;
    Ok((tool, wobj))
}

/// Why a tool or work object is often missing: cells declare them in a
/// system module of the task, which a program read alone does not have.
const ELSEWHERE: &str = "tools and work objects are often declared in a system module of the task (user.sys): read the whole task (its folder, a backup, or that module beside this one)";

/// An error for a target whose frames cannot be modelled.
pub fn unsupported(program: &Program, target: &Target, why: &str) -> Error {
    Error::new(ErrorKind::Unsupported, why)
        .about(Subject::Target(target.id.clone()))
        .at(program.location(&target.origin))
}

#[cfg(test)]
mod tests {
    use super::glob_match;

    #[test]
    fn patterns_match_indices_only() {
        assert!(glob_match("sCell{*}.path.start", "scell{12}.PATH.start"));
        assert!(glob_match("p{*,1}", "p{3,1}"));
        assert!(!glob_match("p{*,1}", "p{3,2}"));
        assert!(!glob_match("p{*}", "p{}"));
        assert!(!glob_match("a.b", "a.bc"));
    }
}
