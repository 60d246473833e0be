//! Where every move instruction of a program ends: its target corrected,
//! derived from corrected targets (Offs, RelTool, a variable assigned
//! from them), left alone for a reason, or the run refused. One rule for
//! every report (text, JSON, `--check`, the summary): a move the run
//! cannot account for is never dropped in silence.
//!
//! A move's fate is its targets' (the worst of them: left alone before
//! derived before corrected). A move whose argument reaches no target the
//! files read is left alone, and why is read from the program: a
//! parameter its calls do not settle, a variable of the routine or one
//! declared without a value (both filled at run time), a literal reading
//! variables, or a name declared nowhere in the files read.

use super::outcome::{Fate, Kind, LeftAlone, MoveCounts, MoveFate, Reason};
use crate::rapid::{Expr, Program, Routine, TargetKind, Targets};
use crate::resolve::{each_move_instruction_with, Frames, Move, MoveLookup, Point, Through};
use std::collections::HashMap;

/// What the run decided of its targets, which the moves' fates are read
/// from.
pub(super) struct Decided<'d> {
    /// Robtargets left alone, by index.
    pub robtargets: &'d HashMap<usize, Reason>,
    /// Jointtargets and other rows left alone, by (file, line, column).
    pub others: &'d [LeftAlone],
    /// The program's tools and work objects, to say which of an
    /// undeclared target's are missing too.
    pub frames: &'d Frames,
}

/// What every move's fate is read against, built once per run.
struct Reading<'p, 'd> {
    program: &'p Program,
    decided: &'d Decided<'d>,
    /// Jointtargets left alone, by (file, line, column).
    left_joints: HashMap<(&'d str, u32, u32), Reason>,
    /// Targets left alone, by lower-case name.
    left_by_id: HashMap<String, Reason>,
    declared: Declared,
    assigned: HashMap<String, Vec<String>>,
    targets: Targets<'p>,
}

/// The left-alone rows of target arguments that reach no target: one per
/// name and reason, at the first move's place, with the count of moves.
#[derive(Default)]
struct Unread {
    rows: Vec<LeftAlone>,
    /// Each (lower-case name, reason)'s row and count of moves.
    at: HashMap<(String, Reason), (usize, usize)>,
}

impl Unread {
    /// One row per name and reason: the first move's place, with the
    /// count of moves.
    fn record(
        &mut self,
        program: &Program,
        m: &Move,
        text: String,
        reason: Reason,
        detail: String,
    ) {
        let key = (text.to_ascii_lowercase(), reason);
        match self.at.get_mut(&key) {
            Some(seen) => seen.1 += 1,
            None => {
                self.at.insert(key, (self.rows.len(), 1));
                self.rows.push(LeftAlone {
                    id: text,
                    kind: Kind::Argument,
                    file: program.file_name(m.file).to_string(),
                    line: m.line,
                    col: m.col,
                    reason,
                    detail,
                    world_mm: None,
                });
            }
        }
    }

    /// The rows, a name moved to more than once saying how often on its
    /// one row.
    fn finish(mut self) -> Vec<LeftAlone> {
        for (k, n) in self.at.values() {
            if *n > 1 {
                self.rows[*k].detail.push_str(&format!(" ({n} moves)"));
            }
        }
        self.rows
    }
}

/// Every move instruction's fate (its rows where `rows`), their counts,
/// and a left-alone row for each target argument that reaches no target
/// (one per name and reason: the first move's place, with the count).
pub(super) fn fates<'p>(
    program: &'p Program,
    lookup: &MoveLookup<'p>,
    decided: &Decided,
    rows: bool,
) -> (Vec<MoveFate>, MoveCounts, Vec<LeftAlone>) {
    let reading = Reading {
        program,
        decided,
        left_joints: decided
            .others
            .iter()
            .map(|l| ((l.file.as_str(), l.line, l.col), l.reason))
            .collect(),
        left_by_id: decided
            .others
            .iter()
            .map(|l| (l.id.to_ascii_lowercase(), l.reason))
            .collect(),
        declared: module_data(program),
        assigned: crate::resolve::frame_variables(program),
        targets: program.targets(),
    };
    let routines: HashMap<(&str, &str), &Routine> = program
        .modules
        .iter()
        .flat_map(|m| m.routines.iter().map(move |r| ((&*m.name, &*r.name), r)))
        .collect();
    let mut out = Vec::new();
    let mut counts = MoveCounts::default();
    let mut unread = Unread::default();
    // The routine of the last move: a million moves of a few routines
    // each look theirs up once.
    let mut last: Option<(*const str, *const str, Option<&Routine>)> = None;
    each_move_instruction_with(program, lookup, &mut |m: &Move| {
        let routine = match last {
            Some((module, routine, r))
                if std::ptr::eq(module, m.module) && std::ptr::eq(routine, m.routine) =>
            {
                r
            }
            _ => {
                let r = routines.get(&(m.module, m.routine)).copied();
                last = Some((m.module, m.routine, r));
                r
            }
        };
        let mut fate = Fate::Corrected;
        let mut names = Vec::new();
        if !m.known {
            let text = (m.points.iter())
                .map(|p| argument_text(program, m.file, p))
                .collect::<Vec<_>>()
                .join(", ");
            unread.record(
                program,
                m,
                text.clone(),
                Reason::Instruction,
                format!(
                    "{} is neither a procedure of the files read nor an instruction rapidtherm knows (an option's, or a procedure of another module of the task): what it does with {text} is unknown",
                    m.instruction
                ),
            );
            fate = Fate::LeftAlone(Reason::Instruction);
            if rows {
                names.push(text);
            }
        }
        // An unknown instruction's arguments are not judged one by one:
        // what it does with them is unknown.
        let points: &[Point] = if m.known { &m.points } else { &[] };
        for p in points {
            fate = fate.worst(reading.point(m, p, routine, &mut unread));
            if rows {
                names.push(argument_text(program, m.file, p));
            }
        }
        counts.add(fate);
        if rows {
            out.push(MoveFate {
                instruction: m.instruction.to_string(),
                file: program.file_name(m.file).to_string(),
                line: m.line,
                col: m.col,
                routine: m.routine.to_string(),
                target: names.join(", "),
                fate,
            });
        }
    });
    (out, counts, unread.finish())
}

impl Reading<'_, '_> {
    /// The fate of one target argument of a known move.
    fn point(&self, m: &Move, p: &Point, routine: Option<&Routine>, unread: &mut Unread) -> Fate {
        let program = self.program;
        // The argument's text names a row or an unread name only: a
        // streamed run keeps no rows, and a million moves need not
        // copy it.
        let text = || argument_text(program, m.file, p);
        let reaches = if m.joints {
            !p.jointtargets.is_empty()
        } else {
            !p.robtargets.is_empty()
        };
        let known = p
            .expr
            .and_then(Expr::as_name)
            .or(p.name)
            .and_then(|n| self.left_by_id.get(&n.to_ascii_lowercase()));
        let f = if let (false, true, Some(&r)) = (reaches, m.joints, known) {
            // Reported as a target already (a jointtarget written with
            // expressions).
            Fate::LeftAlone(r)
        } else if !reaches {
            let (reason, detail) = unread_reason(
                m,
                p,
                routine,
                &self.declared,
                self.decided.frames,
                &self.assigned,
            );
            unread.record(program, m, text(), reason, detail);
            Fate::LeftAlone(reason)
        } else if m.joints {
            self.jointtargets(p)
        } else {
            self.robtargets(p, routine)
        };
        // A parameter some call passes a name that reaches nothing:
        // the move goes there at run time too.
        let mut f = f;
        for name in &p.unread_passed {
            let (reason, detail) = passed_reason(name, &text(), m, program, &self.declared);
            unread.record(program, m, name.to_string(), reason, detail);
            f = f.worst(Fate::LeftAlone(reason));
        }
        f
    }

    /// The worst fate of the jointtargets an argument reaches.
    fn jointtargets(&self, p: &Point) -> Fate {
        let program = self.program;
        let mut f = Fate::Corrected;
        for &j in &p.jointtargets {
            let jt = &program.jointtargets()[j];
            let key = (
                program.file_name(jt.origin.file),
                jt.origin.pos.line,
                jt.origin.pos.col,
            );
            f = f.worst(match self.left_joints.get(&key) {
                Some(&r) => Fate::LeftAlone(r),
                None if jt.kind == TargetKind::Derived => Fate::Derived,
                None => Fate::Corrected,
            });
        }
        f
    }

    /// The worst fate of the robtargets an argument reaches.
    fn robtargets(&self, p: &Point, routine: Option<&Routine>) -> Fate {
        let targets = &self.targets;
        let parameter = p
            .expr
            .and_then(Expr::as_name)
            .or(p.name)
            .is_some_and(|n| routine.is_some_and(|r| is_parameter(r, n)));
        let mut f = Fate::Corrected;
        for (range, through) in &p.robtargets {
            for i in range.clone() {
                let one = match self.decided.robtargets.get(&i) {
                    Some(&r) => Fate::LeftAlone(r),
                    // A derived target is held one by one: a run's
                    // (a million elements of an array a loop moves
                    // to) is never made just to be told it is not.
                    None if targets.kind(i) == Some(TargetKind::Derived)
                        && targets
                            .one_by_one(i)
                            .is_some_and(|t| !t.written_with_expressions()) =>
                    {
                        Fate::Derived
                    }
                    // What a variable is assigned from carries it at
                    // run time; what a settled parameter is passed
                    // is the target itself.
                    None if *through == Through::Variable && !parameter => Fate::Derived,
                    // Reached through Offs/RelTool of it.
                    None if matches!(through, Through::Derived(_)) => Fate::Derived,
                    None => Fate::Corrected,
                };
                f = f.worst(one);
            }
        }
        f
    }
}

/// Module data by lower-case name: (type, whether it has a value, line).
type Declared = HashMap<String, (String, bool, u32)>;

fn module_data(program: &Program) -> Declared {
    let mut out = Declared::new();
    for m in &program.modules {
        for d in &m.data {
            out.entry(d.name.to_ascii_lowercase()).or_insert((
                d.type_name.clone(),
                d.has_value(),
                d.pos.line,
            ));
        }
    }
    out
}

fn is_parameter(routine: &Routine, name: &str) -> bool {
    routine
        .params
        .iter()
        .any(|p| p.name.eq_ignore_ascii_case(name))
}

/// Why a move's target argument reaches no target, and the words.
fn unread_reason(
    m: &Move,
    p: &Point,
    routine: Option<&Routine>,
    declared: &Declared,
    frames: &Frames,
    assigned: &HashMap<String, Vec<String>>,
) -> (Reason, String) {
    let root = match (p.expr, p.name) {
        (_, Some(n)) => Some(n.to_string()),
        (Some(e), _) => root_name(e),
        _ => None,
    };
    match p.expr {
        Some(Expr::Aggregate(_)) => {
            return (
                Reason::Expression,
                "a literal that reads variables: only the run knows its value".to_string(),
            )
        }
        Some(Expr::Call(c)) if root.is_none() => {
            return (
                Reason::Runtime,
                format!("the result of {}, known only at run time", c.name),
            )
        }
        _ => {}
    }
    let Some(name) = root else {
        return (
            Reason::Expression,
            "an expression only the run can value".to_string(),
        );
    };
    if let Some(r) = routine {
        if is_parameter(r, &name) {
            return (
                Reason::Parameter,
                format!(
                    "{name} is a parameter of {}, and its calls do not settle it (each must pass a target declared in the files read)",
                    r.name
                ),
            );
        }
        if let Some(d) = r.data.iter().find(|d| d.name.eq_ignore_ascii_case(&name)) {
            return (
                Reason::Runtime,
                format!(
                    "{name} is a {} {} of routine {} (line {}): the run fills it",
                    storage_word(d.storage),
                    d.type_name,
                    r.name,
                    d.pos.line
                ),
            );
        }
    }
    if let Some((type_name, has_value, line)) = declared.get(&name.to_ascii_lowercase()) {
        let how = if *has_value {
            "whose value is decided at run time"
        } else {
            "declared without a value"
        };
        return (
            Reason::Runtime,
            format!("{name} is a {type_name} {how} (line {line}): the run fills it"),
        );
    }
    let mut detail = format!(
        "{name} is declared in none of the files read: read the whole task (its folder or backup)"
    );
    let missing: Vec<String> = [
        ("tool", m.tool.as_deref()),
        ("work object", m.wobj.as_deref()),
    ]
    .into_iter()
    .filter_map(|(what, n)| {
        let n = n?;
        let known = match what {
            "tool" => frames.tool(Some(n)).is_some(),
            _ => frames.wobj(Some(n)).is_some(),
        } || assigned.contains_key(&n.to_ascii_lowercase());
        (!known).then(|| format!("its {what} {n}"))
    })
    .collect();
    if !missing.is_empty() {
        detail.push_str(&format!("; nor is {}", missing.join(" or ")));
    }
    (Reason::Undeclared, detail)
}

/// Why a name a call passes for a parameter reaches no target, and the
/// words: data of the program filled at run time, or declared in none of
/// the files read.
fn passed_reason(
    name: &str,
    parameter: &str,
    m: &Move,
    program: &Program,
    declared: &Declared,
) -> (Reason, String) {
    let passed = format!("{name}, passed for {parameter} of {}", m.routine);
    if let Some((type_name, has_value, line)) = declared.get(&name.to_ascii_lowercase()) {
        let how = match has_value {
            true => "whose value is decided at run time",
            false => "declared without a value",
        };
        return (
            Reason::Runtime,
            format!("{passed}, is a {type_name} {how} (line {line}): the run fills it"),
        );
    }
    let local = (program.modules.iter())
        .flat_map(|m| &m.routines)
        .find_map(|r| {
            let d = r.data.iter().find(|d| d.name.eq_ignore_ascii_case(name))?;
            Some((r, d))
        });
    if let Some((r, d)) = local {
        return (
            Reason::Runtime,
            format!(
                "{passed}, is a {} {} of routine {} (line {}): the run fills it",
                storage_word(d.storage),
                d.type_name,
                r.name,
                d.pos.line
            ),
        );
    }
    (
        Reason::Undeclared,
        format!("{passed}, is declared in none of the files read: read the whole task (its folder or backup)"),
    )
}

fn storage_word(s: crate::rapid::Storage) -> &'static str {
    match s {
        crate::rapid::Storage::Var => "VAR",
        crate::rapid::Storage::Pers => "PERS",
        crate::rapid::Storage::Const => "CONST",
    }
}

/// The variable an argument reads: its name, an array's or record's
/// root, the first name a function is given (`Offs(pHome, ...)`).
fn root_name(e: &Expr) -> Option<String> {
    match e {
        Expr::Name(n) => Some(n.to_string()),
        Expr::Index(b) => root_name(&b.0),
        Expr::Component(b) => root_name(&b.0),
        Expr::Call(c) => c
            .args
            .iter()
            .filter(|a| !a.optional)
            .find_map(|a| a.value.as_ref().and_then(Expr::as_name))
            .map(str::to_string),
        _ => None,
    }
}

/// A target argument as written, for the report.
fn argument_text(program: &Program, file: usize, p: &Point) -> String {
    if let Some(n) = p.name {
        return n.to_string();
    }
    let Some(e) = p.expr else {
        return p
            .robtargets
            .first()
            .and_then(|(r, _)| program.targets().get(r.start).map(|t| t.id.clone()))
            .unwrap_or_default();
    };
    let src = program.source(file);
    let span = |r: &std::ops::Range<usize>| {
        src.get(r.clone())
            .map(|b| b.iter().map(|&c| c as char).collect::<String>())
    };
    match e {
        Expr::Name(n) => n.to_string(),
        Expr::Target(i) => program
            .targets()
            .get(*i)
            .map(|t| t.id.clone())
            .unwrap_or_default(),
        Expr::JointTarget(i) => program
            .jointtargets()
            .get(*i)
            .map(|t| t.id.clone())
            .unwrap_or_default(),
        Expr::Call(c) => span(&c.span).unwrap_or_else(|| c.name.to_string()),
        Expr::Aggregate(a) => span(&a.span).unwrap_or_default(),
        Expr::Index(_) | Expr::Component(_) => access_text(e),
        _ => "an expression".to_string(),
    }
}

fn access_text(e: &Expr) -> String {
    match e {
        Expr::Name(n) => n.to_string(),
        Expr::Index(b) => {
            let idx: Vec<String> =
                b.1.iter()
                    .map(|x| match (x.as_num(), x.as_name()) {
                        (Some(v), _) => format!("{v}"),
                        (_, Some(n)) => n.to_string(),
                        _ => "…".to_string(),
                    })
                    .collect();
            format!("{}{{{}}}", access_text(&b.0), idx.join(","))
        }
        Expr::Component(b) => format!("{}.{}", access_text(&b.0), b.1),
        _ => "…".to_string(),
    }
}

/// The robtargets left alone, by index, of the pass's rows.
pub(super) fn left_by_index(left: &[(usize, LeftAlone)]) -> HashMap<usize, Reason> {
    left.iter().map(|(i, l)| (*i, l.reason)).collect()
}
