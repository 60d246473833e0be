//! A statement the fast lane read, as a run holds it: a few numbers
//! (where it starts, its line, its parts' places within it, its names'
//! numbers), or why it cannot be held so. Made where the parse reads a
//! statement itself and where the lane reads ahead of it (`ahead`).

use crate::rapid::lane::{Decline, LaneDecl, LaneMove};
use crate::rapid::runs::{DeclItem, MoveItem, NONE};

/// A move the lane read at `at` (on `line`), as a run holds it, its names
/// numbered by `number`; why not where it cannot be (a statement too
/// long, too many names, a file too large).
pub(super) fn move_item(
    at: usize,
    line: u32,
    mv: &LaneMove,
    number: &mut dyn FnMut(std::ops::Range<usize>) -> std::result::Result<u16, Decline>,
) -> std::result::Result<(MoveItem, u8), Decline> {
    let (literals, parts) = match &mv.named {
        Some(n) => (0, [offset(at, n.start)?, short(n.len())?]),
        None => {
            let mut parts = [0u16; 2];
            for (p, &l) in parts.iter_mut().zip(&mv.literals) {
                *p = offset(at, l)?;
            }
            // A move has one or two targets.
            (mv.literals.len() as u8, parts)
        }
    };
    let mut names = [NONE; 6];
    let wobj = mv.wobj.clone();
    let ranges = [
        Some(mv.instruction.clone()),
        Some(mv.speed.clone()),
        Some(mv.zone.clone()),
        Some(mv.tool.clone()),
        wobj.as_ref().map(|w| w.0.clone()),
        wobj.map(|w| w.1),
    ];
    for (slot, r) in names.iter_mut().zip(ranges) {
        if let Some(r) = r {
            *slot = number(r)?;
        }
    }
    let item = MoveItem {
        at: in_file(at)?,
        line,
        names,
        parts,
    };
    Ok((item, literals))
}

/// A robtarget declaration the lane read at `at` (on `line`), its literal
/// at `lit`, as a run holds it.
pub(super) fn decl_item(
    at: usize,
    line: u32,
    d: &LaneDecl,
    lit: usize,
) -> std::result::Result<DeclItem, Decline> {
    Ok(DeclItem {
        at: in_file(at)?,
        line,
        name: (
            offset(at, d.name.start)?,
            u8::try_from(d.name.len()).map_err(|_| Decline::TooLong)?,
        ),
        literal: offset(at, lit)?,
        qualified: false,
    })
}

/// Where `x` is in a statement at `at`, as a run holds it (16 bits).
fn offset(at: usize, x: usize) -> std::result::Result<u16, Decline> {
    short(x.saturating_sub(at))
}

/// A length within a statement, as a run holds it (16 bits).
fn short(n: usize) -> std::result::Result<u16, Decline> {
    u16::try_from(n).map_err(|_| Decline::TooLong)
}

/// Where `x` is in its file, as a run holds it (32 bits).
pub(super) fn in_file(x: usize) -> std::result::Result<u32, Decline> {
    u32::try_from(x).map_err(|_| Decline::FileTooLarge)
}
