//! The tools and work objects a program declares as robot frames
//! ([`Frames`]), each robtarget's pose and robconf, and the frames a target
//! is corrected for, by the names its first move gives.

use super::usage::Usage;
use crate::error::{Error, ErrorKind, Result, Subject};
use crate::rapid::{self, Program, Target};
use crate::robot::conf::RobConf;
use crate::robot::frames::{pose_from_rapid, ToolFrame, WobjFrames};
use nalgebra::Isometry3;
use std::borrow::Cow;

/// The tools and work objects a program declares, by lower-case name, with
/// RAPID's predefined `tool0` and `wobj0`.
#[derive(Debug, Clone)]
pub struct Frames {
    /// By lower-case name, hashed fast: each of a million targets looks
    /// its tool and work object up (SipHash was 2 % of a correction).
    tools: foldhash::HashMap<String, ToolFrame>,
    wobjs: foldhash::HashMap<String, WobjFrames>,
    /// Tooldata and wobjdata declared PERS without a value (`PERS
    /// wobjdata wConv;`), by lower-case name: another task or module sets
    /// them at run time.
    elsewhere: foldhash::HashSet<String>,
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
        let mut elsewhere = foldhash::HashSet::default();
        for m in &program.modules {
            for d in program.module_data(m) {
                let frame_type = d.type_name.eq_ignore_ascii_case("tooldata")
                    || d.type_name.eq_ignore_ascii_case("wobjdata");
                if frame_type && d.storage == rapid::Storage::Pers && !d.has_value() {
                    elsewhere.insert(d.name.to_ascii_lowercase());
                }
            }
        }
        Ok(Frames {
            tools,
            wobjs,
            elsewhere,
        })
    }

    /// Whether the tooldata or wobjdata `name` is declared PERS without a
    /// value, and none of the files read gives it one: set elsewhere at
    /// run time.
    pub fn set_elsewhere(&self, name: &str) -> bool {
        let n = name.to_ascii_lowercase();
        self.elsewhere.contains(&n) && !self.tools.contains_key(&n) && !self.wobjs.contains_key(&n)
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

/// Whether a tool or work-object name is one a declaration can have.
fn is_plain_name(name: &str) -> bool {
    name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}
