//! The fast lane's reads done ahead of the parse, on every core. The
//! parse asks the lane at each statement in turn; a large program is a
//! million statements the lane reads, and reading them on one core made
//! the parse the longest part of a run. So where the lane reads a move
//! or a robtarget declaration, the next stretch of the file is read
//! ahead: cut at line starts into pieces, each piece read on a core
//! statement after statement (where a line holds nothing the lane reads,
//! from the next line's start), each read kept where it starts as a run
//! holds it (its names numbered within the piece). The parse takes the
//! read kept for the place it asks at, its names numbered in the run's
//! table, or reads there itself where none is kept.
//!
//! A read depends on the file's bytes and its start alone, so a read
//! kept for a place is what the parse would read there: what the parse
//! makes of the file does not depend on the cuts (a piece may begin
//! inside a statement; its reads there are for places the parse never
//! asks at). A statement the lane declines is not kept: the parse reads
//! it again and keeps the reason, as where nothing was read ahead.

use super::items::{decl_item, move_item};
use crate::rapid::lane::{read_decl, read_move, Decline, Seen, Value};
use crate::rapid::runs::{DeclItem, MoveItem, NONE};
use crate::rapid::scan::Scanner;
use crate::rapid::{Scope, Storage};
use rayon::prelude::*;
use std::ops::Range;

/// A statement read ahead, as a run holds it.
#[derive(Debug, Clone)]
pub(super) enum Kept {
    /// A move: its item (names numbered in its piece) and how many
    /// literals it has.
    Move(MoveItem, u8),
    /// A robtarget declared with a literal.
    Decl {
        item: DeclItem,
        scope: Option<Scope>,
        storage: Storage,
        type_name: Range<usize>,
    },
}

/// One piece's reads: where each starts, where it ends, what it is; and
/// the names its moves use, by their number in the piece.
#[derive(Debug, Default)]
struct Piece {
    kept: Vec<(usize, usize, Kept)>,
    names: Vec<Range<usize>>,
    /// Each name's number in the run's table, once the parse asked
    /// ([`NONE`] before).
    global: Vec<u16>,
}

/// The reads kept ahead of the parse.
#[derive(Debug, Default)]
pub(super) struct Ahead {
    pieces: Vec<Piece>,
    /// The piece and read the parse has reached.
    piece: usize,
    next: usize,
    /// The end of the stretch read ahead.
    covered: usize,
    /// The next stretch's length.
    window: usize,
}

/// The first stretch read ahead (bytes): a program of a few hundred
/// moves is read in one.
const FIRST_WINDOW: usize = 64 * 1024;
/// The longest stretch (its reads take about a fifth of its bytes).
const MAX_WINDOW: usize = 8 * 1024 * 1024;
/// A stretch shorter than this is read on the parse's own core (handing
/// it out would cost more than it saves).
const PARALLEL_FROM: usize = 256 * 1024;
/// The pieces a stretch is cut into per core (a piece ends where its
/// statements do, so some take longer than others).
const PIECES_PER_CORE: usize = 4;
/// Names one piece numbers (a piece using more leaves its moves to the
/// parse).
const PIECE_NAMES: usize = 256;

impl Ahead {
    /// The read kept for `at`, if any, and where it ends; a move's names
    /// numbered in the run's table by `global` (a name's place in the
    /// file to its number there: `None` where it has none, and then
    /// nothing is taken).
    pub fn take(
        &mut self,
        at: usize,
        mut global: impl FnMut(Range<usize>) -> Option<u16>,
    ) -> Option<(usize, Kept)> {
        loop {
            let piece = self.pieces.get(self.piece)?;
            while piece.kept.get(self.next).is_some_and(|k| k.0 < at) {
                self.next += 1;
            }
            if self.next < piece.kept.len() {
                break;
            }
            self.piece += 1;
            self.next = 0;
        }
        let piece = self.pieces.get_mut(self.piece)?;
        let (start, end, kept) = piece.kept.get(self.next)?.clone();
        if start != at {
            return None;
        }
        let kept = match kept {
            Kept::Move(mut item, literals) => {
                for n in item.names.iter_mut().filter(|n| **n != NONE) {
                    let k = usize::from(*n);
                    let known = piece.global.get_mut(k)?;
                    if *known == NONE {
                        *known = global(piece.names.get(k)?.clone())?;
                    }
                    *n = *known;
                }
                Kept::Move(item, literals)
            }
            decl => decl,
        };
        Some((end, kept))
    }

    /// After the parse read a statement ending at `end` itself: where
    /// that is past the stretch read ahead, the next stretch from there
    /// is read (each twice as long as the one before, to
    /// [`MAX_WINDOW`]). `lines` are the file's line starts.
    pub fn read_from(&mut self, src: &[u8], lines: &[usize], end: usize) {
        if end < self.covered || end >= src.len() {
            return;
        }
        self.window = (self.window * 2).clamp(FIRST_WINDOW, MAX_WINDOW);
        let to = end.saturating_add(self.window).min(src.len());
        let pieces = if to - end < PARALLEL_FROM {
            1
        } else {
            rayon::current_num_threads().max(1) * PIECES_PER_CORE
        };
        let step = (to - end).div_ceil(pieces).max(1);
        let bounds: Vec<(usize, usize)> = (0..pieces)
            .map(|k| (end + k * step, (end + (k + 1) * step).min(to)))
            .filter(|(a, b)| a < b)
            .collect();
        let read = |&(lo, hi): &(usize, usize)| {
            // The first piece starts where the parse stopped; the others
            // at their first line start.
            let from = if lo == end {
                Some(lo)
            } else {
                crate::error::next_line_start(src, lo).filter(|&n| n <= hi)
            };
            from.map_or_else(Piece::default, |from| read_piece(src, lines, from, hi))
        };
        // Each piece's reads start in it: the pieces in turn are in file
        // order.
        self.pieces = if bounds.len() > 1 {
            bounds.par_iter().map(read).collect()
        } else {
            bounds.iter().map(read).collect()
        };
        self.piece = 0;
        self.next = 0;
        self.covered = to;
    }
}

/// The statements the lane reads from `from` on, starting before `hi`:
/// after each, the next statement's start as the scanner finds it (blanks
/// and comments skipped); after a place the lane reads nothing at (or
/// declines), the next line's start.
fn read_piece(src: &[u8], lines: &[usize], from: usize, hi: usize) -> Piece {
    let mut seen = Seen::default();
    let mut scanner = Scanner::new(src);
    let mut piece = Piece::default();
    let mut p = from;
    loop {
        scanner.skip_to(p);
        let at = scanner.next_start();
        if at >= hi {
            break;
        }
        let line = lines.partition_point(|&s| s <= at).max(1) as u32;
        if let Some((end, kept)) = read_one(src, at, line, &mut seen, &mut piece.names) {
            piece.kept.push((at, end, kept));
            p = end;
            continue;
        }
        match crate::error::next_line_start(src, at) {
            Some(n) => p = n,
            None => break,
        }
    }
    piece.global = vec![NONE; piece.names.len()];
    piece
}

/// The move or robtarget declaration the lane reads at `at`, as a run
/// holds it (its names numbered in `names`), and where it ends.
fn read_one<'a>(
    src: &'a [u8],
    at: usize,
    line: u32,
    seen: &mut Seen<'a>,
    names: &mut Vec<Range<usize>>,
) -> Option<(usize, Kept)> {
    let mut number = |r: Range<usize>| -> Result<u16, Decline> {
        let word = &src[r.clone()];
        if let Some(k) = names.iter().position(|n| &src[n.clone()] == word) {
            return Ok(k as u16);
        }
        if names.len() >= PIECE_NAMES {
            return Err(Decline::TooManyNames);
        }
        names.push(r);
        Ok((names.len() - 1) as u16)
    };
    if let Ok(Some(mv)) = read_move(src, at, seen) {
        let (item, literals) = move_item(at, line, &mv, &mut number).ok()?;
        return Some((mv.end, Kept::Move(item, literals)));
    }
    let d = read_decl(src, at, seen).ok()??;
    let Value::Literal(lit) = d.value else {
        return None;
    };
    if d.joint {
        return None;
    }
    let item = decl_item(at, line, &d, lit).ok()?;
    Some((
        d.end,
        Kept::Decl {
            item,
            scope: d.scope,
            storage: d.storage,
            type_name: d.type_name,
        },
    ))
}
