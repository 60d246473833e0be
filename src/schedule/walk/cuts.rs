//! Moves a skeleton cut out of the file, walked where the program read by
//! [`parse_skeleton_runs`](crate::rapid::parse_skeleton_runs) has left
//! each run of them ([`StatementKind::CutMoves`]): taken from the numbers
//! the cut pass kept (else read again from the file a batch at a time on
//! every core), timed one by one as any move (the same
//! [`Walker::move_to_rob`]), each literal's visits kept by its number
//! ([`CutVisits`]). Whatever the walk would say of one of them (a note,
//! a target it cannot time) it says only of the whole program, read
//! statement by statement: the walk of the runs declines, and its caller
//! then walks that.

use super::moves::{Goal, Via};
use super::*;
use crate::rapid::fastmove::Skeleton;
use crate::resolve::robconf_of;
use crate::robot::frames::pose_from_rapid;
use crate::robot::{RobConf, ToolData, WobjData};
use crate::schedule::CutVisits;
use nalgebra::Isometry3;
use rayon::prelude::*;
use std::ops::Range;

/// Moves read from the file at once (on every core), then timed in order.
const BATCH: usize = 4096;
/// Names [`CutWalk`] keeps: the instruction, speed, tool and work object
/// of a few kinds of move.
const NAMES: usize = 16;

/// The cut moves of a walk, and what it found of them.
pub(crate) struct CutWalk<'p> {
    skeleton: &'p Skeleton,
    src: &'p [u8],
    /// The number of each cut's first literal (and of all, last).
    first_literal: Vec<usize>,
    pub(crate) visits: CutVisits,
    /// A cut move needed what only the whole program's walk says.
    pub(crate) declined: bool,
    /// Whether the arm's reach of the cut literals is asked (else the
    /// walk's caller asks it).
    pub(super) ask_reach: bool,
    /// The run being walked: its identifiers' prefix, the routine's
    /// inline literals before it, and the number of its first literal.
    run: (Arc<str>, usize, usize),
    /// Names met in the moves, as the walk's expressions.
    names: Vec<(&'p [u8], Arc<str>)>,
}

impl<'p> CutWalk<'p> {
    /// The moves `skeleton` cut out of `src`, their reach asked where
    /// `ask_reach`.
    pub(crate) fn new(skeleton: &'p Skeleton, src: &'p [u8], ask_reach: bool) -> CutWalk<'p> {
        let mut first_literal = Vec::with_capacity(skeleton.literals.len() + 1);
        let mut n = 0;
        first_literal.push(0);
        for &k in &skeleton.literals {
            n += usize::from(k);
            first_literal.push(n);
        }
        CutWalk {
            skeleton,
            src,
            first_literal,
            visits: CutVisits::new(n),
            declined: false,
            ask_reach,
            run: (Arc::from(""), 0, 0),
            names: Vec::new(),
        }
    }

    /// A visit of `literal` at `time_min`, after `before` other targets.
    pub(super) fn visit(&mut self, literal: usize, time_min: f64, before: usize) {
        let (routine, inline, first) = &self.run;
        let number = inline + (literal - first) + 1;
        self.visits
            .visit(literal, (routine, number), time_min, before);
    }

    /// The name at `r` of the file, as an expression.
    fn name(&mut self, r: &Range<usize>) -> Option<Expr> {
        let bytes = self.src.get(r.clone())?;
        if let Some((_, a)) = self.names.iter().find(|(b, _)| *b == bytes) {
            return Some(Expr::Name(a.clone()));
        }
        let a: Arc<str> = Arc::from(std::str::from_utf8(bytes).ok()?);
        // A few kept: a program of a thousand tools would search them all.
        if self.names.len() < NAMES {
            self.names.push((bytes, a.clone()));
        }
        Some(Expr::Name(a))
    }
}

/// Each run of cut moves of a program: its cuts, the inline literals of
/// its routine before it, its identifiers' prefix.
struct Runs<'a>(Vec<(Range<usize>, usize, &'a Arc<str>)>);

impl<'a> rapid::visit::Visit<'a> for Runs<'a> {
    fn visit_statement(&mut self, s: &'a Statement) {
        if let StatementKind::CutMoves {
            cuts,
            inline,
            prefix,
        } = &s.kind
        {
            self.0.push((cuts.clone(), *inline, prefix));
        }
        rapid::visit::walk_statement(self, s);
    }
}

impl CutWalk<'_> {
    /// The cut literals never visited, in file order: each one's place
    /// in the skeleton (that of its move) and identifier, made for the
    /// first `shown` only; and how many there are.
    pub(super) fn missed(&self, program: &Program, shown: usize) -> (Vec<(usize, String)>, usize) {
        let mut runs = Runs(Vec::new());
        rapid::visit::walk_program(&mut runs, program);
        runs.0.sort_by_key(|r| r.0.start);
        let (mut listed, mut count) = (Vec::new(), 0);
        for (cuts, inline, prefix) in runs.0 {
            let first = self.first_literal[cuts.start];
            for k in cuts {
                for l in self.first_literal[k]..self.first_literal[k + 1] {
                    if self.visits.times(l).is_some() {
                        continue;
                    }
                    count += 1;
                    if listed.len() < shown {
                        let id = format!("{prefix}#{}", inline + (l - first) + 1);
                        listed.push((self.skeleton.place_of_cut(k), id));
                    }
                }
            }
        }
        (listed, count)
    }
}

/// The error a declined walk stops with (never shown: its caller walks
/// the whole program instead).
fn declined() -> Error {
    Error::input("internal: a cut move is left to the whole program's walk")
}

/// A cut move as the walk needs it, read on any core: what says how it
/// goes (its instruction, and its speed to its end), and each literal's
/// pose and robconf (CirPoint before ToPoint); `None` where a literal has
/// none (the whole walk says why).
struct Read {
    instruction: Range<usize>,
    tail: Range<usize>,
    literals: [Option<(Isometry3<f64>, RobConf)>; 2],
}

impl Read {
    /// Move `k`, from the numbers the cut pass kept, or else read again.
    fn of(skeleton: &Skeleton, src: &[u8], k: usize) -> Option<Read> {
        let Some(poses) = &skeleton.poses else {
            let m = skeleton.reread(src, k)?;
            let numbers: Vec<[f64; 11]> = m.targets.iter().map(|(_, v)| numbers_of(v)).collect();
            return Read::new(m.instruction, m.speed.start..m.span.end, &numbers);
        };
        let cut = skeleton.cuts.get(k)?;
        let &(_, a, b) = poses.moves.get(k)?;
        let numbers = poses.numbers_of(k, usize::from(*skeleton.literals.get(k)?))?;
        let at = |d: u32| cut.start + d as usize;
        Read::new(cut.start..at(a), at(b)..cut.end, numbers)
    }

    fn new(instruction: Range<usize>, tail: Range<usize>, numbers: &[[f64; 11]]) -> Option<Read> {
        let mut literals = [None, None];
        if numbers.len() > literals.len() {
            return None;
        }
        for (slot, n) in literals.iter_mut().zip(numbers) {
            let pose = pose_from_rapid([n[0], n[1], n[2]], [n[3], n[4], n[5], n[6]]).ok()?;
            let conf = robconf_of([n[7], n[8], n[9], n[10]]).ok()?;
            *slot = Some((pose, conf));
        }
        Some(Read {
            instruction,
            tail,
            literals,
        })
    }

    /// The bytes that say how the move goes.
    fn key<'s>(&self, src: &'s [u8]) -> [Option<&'s [u8]>; 2] {
        [
            src.get(self.instruction.clone()),
            src.get(self.tail.clone()),
        ]
    }
}

/// A literal's position, orientation and robconf numbers.
fn numbers_of(v: &crate::rapid::RobTargetValue) -> [f64; 11] {
    let mut n = [0.0; 11];
    let all = v
        .trans_values()
        .into_iter()
        .chain(v.rot_values())
        .chain(v.robconf_values());
    for (slot, x) in n.iter_mut().zip(all) {
        *slot = x;
    }
    n
}

/// How the moves of a run written alike (instruction, speed, zone, tool,
/// work object) go: worked out once per run (nothing between two cut
/// moves changes what the names stand for).
struct Setup<'s> {
    key: [Option<&'s [u8]>; 2],
    call: Call,
    kind: MotionKind,
    speed: SpeedData,
    t_override: Option<f64>,
    frames: std::rc::Rc<(ToolData, WobjData)>,
    max_speed: [f64; 6],
}

impl<'p> Walker<'p> {
    /// The run `cuts` of a routine's cut moves, after its first `inline`
    /// literals, their identifiers' `prefix`; `s` is the run's statement.
    pub(super) fn exec_cut_moves(
        &mut self,
        cuts: Range<usize>,
        (inline, prefix): (usize, &Arc<str>),
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<Flow> {
        // Only a first walk, which asks of reach after it, walks the moves
        // itself: a second one is to find each failing target in its place.
        let (Some(cw), Some(_)) = (self.cuts.as_mut(), &self.deferred) else {
            return self.decline();
        };
        cw.run = (prefix.clone(), inline, cw.first_literal[cuts.start]);
        let (skeleton, src) = (cw.skeleton, cw.src);
        let mut setup: Option<Setup> = None;
        let end = cuts.end;
        // Moves whose numbers the cut pass kept take a few nanoseconds
        // each: read in turn (on every core, a run of a few moves between
        // two statements cost more to share out than to read).
        let kept = skeleton.poses.is_some();
        let read = move |lo: usize| -> Vec<Option<Read>> {
            let batch = lo..(lo + BATCH).min(end);
            match kept {
                true => batch.map(|k| Read::of(skeleton, src, k)).collect(),
                false => batch
                    .into_par_iter()
                    .map(|k| Read::of(skeleton, src, k))
                    .collect(),
            }
        };
        // Each batch is timed here while the next is read again on another
        // thread: timing is one move after another, reading is not.
        std::thread::scope(|scope| {
            let mut lo = cuts.start;
            let mut moves = read(lo);
            while lo < end {
                let hi = (lo + BATCH).min(end);
                let read = &read;
                let ahead = (hi < end && !kept).then(|| scope.spawn(move || read(hi)));
                for (k, m) in (lo..hi).zip(moves) {
                    self.count_step(frame, s)?;
                    let notes = self.notes.len();
                    let timed = match m {
                        Some(m) => self.cut_move(k, &m, &mut setup, s, frame)?,
                        None => false,
                    };
                    if !timed || self.notes.len() != notes || !self.errors.is_empty() {
                        return self.decline();
                    }
                }
                moves = match ahead.map(|h| h.join()) {
                    Some(Ok(next)) => next,
                    Some(Err(_)) => return self.decline(),
                    None if hi < end => read(hi),
                    None => Vec::new(),
                };
                lo = hi;
            }
            Ok(Flow::Normal)
        })
    }

    fn decline(&mut self) -> Result<Flow> {
        if let Some(cw) = self.cuts.as_mut() {
            cw.declined = true;
        }
        Err(declined())
    }

    /// How cut move `k`, written `key`, goes, as the walk works it out for
    /// the statement the whole program makes of the move (its line is the
    /// run's: any note declines); `None`: not a move the walk of the runs
    /// times.
    fn setup<'s>(
        &mut self,
        key: [Option<&'s [u8]>; 2],
        k: usize,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<Option<Setup<'s>>> {
        let Some(cw) = self.cuts.as_mut() else {
            return Ok(None);
        };
        let Some(m) = cw.skeleton.reread(cw.src, k) else {
            return Ok(None);
        };
        let (Some(Expr::Name(name)), Some(speed), Some(tool)) =
            (cw.name(&m.instruction), cw.name(&m.speed), cw.name(&m.tool))
        else {
            return Ok(None);
        };
        let wobj = match &m.wobj {
            Some(w) => match cw.name(w) {
                Some(w) => Some(w),
                None => return Ok(None),
            },
            None => None,
        };
        let kind = match rapid::motion_signature(&name).map(|sig| sig.kind) {
            Some(k @ (MotionKind::Linear | MotionKind::Joint | MotionKind::Circular)) => k,
            _ => return Ok(None),
        };
        let line = s.pos.line;
        let (speed, t_override) = self.move_speed([Some(&speed), None, None], frame, line)?;
        let frames = self.frame_names(Some(&tool), wobj.as_ref(), frame, line)?;
        let ov = self.velset.0;
        Ok(Some(Setup {
            key,
            call: Call {
                name,
                late_bound: false,
                args: Vec::new(),
                targets: Vec::new(),
                jointtargets: Vec::new(),
            },
            kind,
            speed,
            t_override,
            frames,
            max_speed: self.robot.max_speed_deg_s.map(|v| v * ov),
        }))
    }

    /// Cut move `k`, read as `m`, timed as the walk times the statement
    /// it is (`setup`: how the run's last move went); `false`: it is left
    /// to the whole program's walk.
    fn cut_move<'s>(
        &mut self,
        k: usize,
        m: &Read,
        setup: &mut Option<Setup<'s>>,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<bool>
    where
        'p: 's,
    {
        let Some(cw) = self.cuts.as_ref() else {
            return Ok(false);
        };
        let (first, src) = (cw.first_literal[k], cw.src);
        let key = m.key(src);
        if setup.as_ref().is_none_or(|u| u.key != key) {
            let notes = self.notes.len();
            *setup = self.setup(key, k, s, frame)?;
            if self.notes.len() != notes {
                return Ok(false);
            }
        }
        let Some(u) = setup.as_ref() else {
            return Ok(false);
        };
        let rob = |j: usize| {
            m.literals[j].map(|(pose, conf)| Rob {
                pose,
                conf,
                id: None,
                derived: None,
                bases: Vec::new(),
                cut: Some(first + j),
            })
        };
        let (to, via) = match (u.kind, rob(0), rob(1)) {
            (MotionKind::Circular, Some(via), Some(to)) => (to, Some(Via::Known(via))),
            (MotionKind::Linear | MotionKind::Joint, Some(to), None) => (to, None),
            _ => return Ok(false),
        };
        let goal = Goal {
            kind: u.kind,
            speed: u.speed,
            t_override: u.t_override,
            conc: false,
            frames: &u.frames,
            max_speed: u.max_speed,
        };
        self.move_to_rob(&goal, to, via, &u.call, frame, s)?;
        Ok(true)
    }
}
