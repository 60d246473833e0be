//! The statements the fast lane reads, each on its own (a statement the
//! scanner delimits): a move to robtarget literals or to a target by
//! name (`MoveL [[...]],v200,z1,tSpindle\WObj:=wPlate;`, `MoveL
//! Target_10,v1000,z1,tGlue\WObj:=wTable;`), and a declaration of a
//! robtarget or jointtarget with a literal value, or of an array of
//! robtarget literals (`CONST robtarget pScan{N}:=[[...],...];`).
//! What it reads is what the grammar would make of the same bytes (the
//! parse holds it to that, `tests/rapid/lane.rs`); anything else is the
//! grammar's.

use super::cursor::{Cursor, Seen};
use super::decline::{Decline, Part};
use crate::rapid::build::{leading_targets, scope, storage, SCOPE_WORDS, STORAGE_WORDS};
use crate::rapid::{Scope, Storage};
use std::ops::Range;

/// A move the lane reads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct LaneMove {
    /// After its `;`.
    pub end: usize,
    pub instruction: Range<usize>,
    /// Its robtarget literals (CirPoint before ToPoint; 0 for a move to a
    /// target by name), where each `[` is.
    pub literals: Vec<usize>,
    /// The target's name, for a move to one by name.
    pub named: Option<Range<usize>>,
    pub speed: Range<usize>,
    pub zone: Range<usize>,
    pub tool: Range<usize>,
    /// `\WObj:=name`: the argument's name as written, and the work
    /// object's.
    pub wobj: Option<(Range<usize>, Range<usize>)>,
}

/// The move starting at `at` of `src`, where the lane reads it (numbers'
/// form checked, their values not read): `Ok(None)` where the statement
/// is no move the lane covers (another instruction, not a statement it
/// knows), `Err` where it began to read a move and declined it.
pub(crate) fn read_move<'a>(
    src: &'a [u8],
    at: usize,
    seen: &mut Seen<'a>,
) -> Result<Option<LaneMove>, Decline> {
    let mut c = Cursor::form(src, at, seen);
    // Motion instructions are no reserved words: their signature says.
    let Some(instruction) = c.name_as(false) else {
        return Ok(None);
    };
    let word = &src[instruction.clone()];
    let k = match c.seen.instruction {
        Some((w, k)) if w == word => k,
        _ => {
            let k = std::str::from_utf8(word).ok().and_then(leading_targets);
            c.seen.instruction = Some((word, k));
            k
        }
    };
    let Some(k) = k else {
        return Ok(None);
    };
    if !matches!(src.get(c.p), Some(b' ' | b'\t')) {
        return Err(Decline::At(Part::Instruction, c.found()));
    }
    let mut part = Part::Target;
    match move_arguments(&mut c, instruction, k, &mut part) {
        Ok(Some(mv)) => Ok(Some(mv)),
        Ok(None) => Err(Decline::At(part, c.found())),
        Err(why) => Err(why),
    }
}

/// A move's arguments after its instruction (`k` targets first), `part`
/// kept at the one being read: `None` where the cursor stopped.
fn move_arguments(
    c: &mut Cursor<'_, '_>,
    instruction: Range<usize>,
    k: usize,
    part: &mut Part,
) -> Result<Option<LaneMove>, Decline> {
    let read = |c: &mut Cursor<'_, '_>, part: &mut Part| -> Option<Result<LaneMove, Decline>> {
        let mut literals = Vec::with_capacity(k);
        let mut named = None;
        c.blank();
        if k == 1 && c.s.get(c.p) != Some(&b'[') {
            // A plain name, then the speed's comma: anything more (an
            // index, a component, a call) is the grammar's.
            named = Some(c.name()?);
        } else {
            for i in 0..k {
                if i > 0 {
                    c.byte(b',')?;
                }
                literals.push(c.literal()?);
            }
        }
        c.byte(b',')?;
        *part = Part::Speed;
        let speed = c.name()?;
        c.byte(b',')?;
        *part = Part::Zone;
        let zone = c.name()?;
        c.byte(b',')?;
        *part = Part::Tool;
        let tool = c.name()?;
        *part = Part::End;
        let mut wobj = None;
        if c.byte(b'\\').is_some() {
            *part = Part::OptionalArgument;
            let word = c.name_as(false)?;
            if !c.s[word.clone()].eq_ignore_ascii_case(b"WObj") {
                return Some(Err(Decline::OtherOptional));
            }
            c.assign()?;
            *part = Part::WorkObject;
            wobj = Some((word, c.name()?));
            *part = Part::End;
        }
        c.byte(b';')?;
        Some(Ok(LaneMove {
            end: c.p,
            instruction: instruction.clone(),
            literals,
            named,
            speed,
            zone,
            tool,
            wobj,
        }))
    };
    read(c, part).transpose()
}

/// What a declaration the lane reads declares.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct LaneDecl {
    /// After its `;`.
    pub end: usize,
    pub scope: Option<Scope>,
    pub storage: Storage,
    pub type_name: Range<usize>,
    /// A jointtarget (else a robtarget).
    pub joint: bool,
    pub name: Range<usize>,
    pub value: Value,
}

/// The value of a declaration the lane reads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Value {
    /// One literal: where its `[` is.
    Literal(usize),
    /// An array of robtarget literals `{size}`: the size's text, where
    /// the value's `[` and `]` are, and each literal's `[`.
    Array {
        size: (usize, Range<usize>),
        open: usize,
        close: usize,
        elements: Vec<usize>,
    },
}

/// The declaration starting at `at` of `src`, where the lane reads it:
/// `[LOCAL|TASK] CONST|PERS|VAR robtarget|jointtarget NAME := literal;`
/// or a robtarget array `NAME{size} := [literal, ...];` (its literals on
/// as many lines as they like). `Ok(None)` where it is no declaration
/// of a robtarget or jointtarget, `Err` where the lane began to read one
/// and declined it.
pub(crate) fn read_decl<'a>(
    src: &'a [u8],
    at: usize,
    seen: &mut Seen<'a>,
) -> Result<Option<LaneDecl>, Decline> {
    let mut c = Cursor::form(src, at, seen);
    let scope = c.keyword(&SCOPE_WORDS).map(scope);
    let Some(storage) = c.keyword(&STORAGE_WORDS).map(storage) else {
        return Ok(None);
    };
    let Some(type_name) = c.name_as(false) else {
        return Ok(None);
    };
    let joint = match &src[type_name.clone()] {
        t if t.eq_ignore_ascii_case(b"robtarget") => false,
        t if t.eq_ignore_ascii_case(b"jointtarget") => true,
        _ => return Ok(None),
    };
    let mut part = Part::Name;
    match decl_rest(&mut c, scope, storage, type_name, joint, &mut part) {
        Ok(Some(d)) => Ok(Some(d)),
        Ok(None) => Err(Decline::At(part, c.found())),
        Err(why) => Err(why),
    }
}

/// A declaration after its type, `part` kept at the one being read:
/// `None` where the cursor stopped.
fn decl_rest(
    c: &mut Cursor<'_, '_>,
    scope: Option<Scope>,
    storage: Storage,
    type_name: Range<usize>,
    joint: bool,
    part: &mut Part,
) -> Result<Option<LaneDecl>, Decline> {
    let read = |c: &mut Cursor<'_, '_>, part: &mut Part| -> Option<Result<LaneDecl, Decline>> {
        let name = c.name()?;
        let value = if c.byte(b'{').is_some() {
            if joint {
                return Some(Err(Decline::JointtargetArray));
            }
            *part = Part::ArraySize;
            let size = c.count()?;
            c.byte(b'}')?;
            *part = Part::Value;
            c.assign()?;
            c.lines = true;
            c.blank();
            let open = c.p;
            c.byte(b'[')?;
            // A large value is read on every core; where that does not
            // read it whole, in order (which finds where it fails).
            let (elements, close) = match super::array::elements(c.s, c.p) {
                Some(read) => read,
                None => {
                    let mut elements = Vec::new();
                    loop {
                        elements.push(c.literal()?);
                        c.blank();
                        match c.s.get(c.p) {
                            Some(b',') => c.p += 1,
                            Some(b']') => break,
                            _ => return None,
                        }
                    }
                    (elements, c.p)
                }
            };
            c.p = close + 1;
            Value::Array {
                size,
                open,
                close,
                elements,
            }
        } else {
            *part = Part::Value;
            c.assign()?;
            c.blank();
            let at = c.p;
            if joint {
                c.jointtarget()?;
            } else {
                c.literal()?;
            }
            Value::Literal(at)
        };
        *part = Part::End;
        c.byte(b';')?;
        Some(Ok(LaneDecl {
            end: c.p,
            scope,
            storage,
            type_name: type_name.clone(),
            joint,
            name,
            value,
        }))
    };
    read(c, part).transpose()
}
