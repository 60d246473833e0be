//! The statements CAM programs are made of, read by hand: a move with
//! inline literal robtargets, a speed, a zone, a tool and at most a work
//! object, on one line (`MoveL [[x,y,z],[q1..q4],[cf1,cf4,cf6,cfx],
//! [e1..e6]],v100,z1,tSpindle\WObj:=wPlate;`). A million of them parse
//! here at the speed of the disk; anything this recogniser does not know
//! (another argument, an expression, a comment or a line break inside)
//! is left to the pest grammar, which gives the same numbers for what
//! both read (`tests/correct/streaming.rs` holds them to it).
//!
//! [`skeleton`] cuts the recognised moves out of a file: what is left is
//! parsed whole, the moves are read again one by one where they were.
//! [`skeleton_with_poses`] also keeps each cut literal's position,
//! orientation and robconf as it cuts, for a walk of the moves.

use super::scan::{PieceKind, Scanner};
use super::{motion_signature, ArgAt, MotionKind, Number, RobTargetValue};
use std::ops::Range;

/// One recognised move. Offsets are those of the file it was read from.
#[derive(Debug, Clone, PartialEq)]
pub struct FastMove {
    /// From the instruction's name to its `;` included.
    pub span: Range<usize>,
    pub instruction: Range<usize>,
    /// Each robtarget literal (CirPoint before ToPoint): where its `[`
    /// is, and its numbers (none kept on the cut pass, which reads their
    /// form alone).
    pub targets: Vec<(usize, RobTargetValue)>,
    /// How many robtarget literals the move holds.
    pub literals: usize,
    pub speed: Range<usize>,
    pub zone: Range<usize>,
    pub tool: Range<usize>,
    /// The work object's name, and the argument's name as written
    /// (`WObj`, `wobj`).
    pub wobj: Option<Range<usize>>,
    pub wobj_word: Option<Range<usize>>,
}

/// Reads one token at a time over one line: blanks are spaces and tabs.
/// The cut pass checks numbers for their form only (their values are
/// read, and checked finite, when corrected); reading a cut move again
/// does not look its names up among the reserved words (the cut pass
/// did).
struct Cursor<'a, 'm> {
    s: &'a [u8],
    p: usize,
    values: bool,
    names: bool,
    seen: &'m mut Seen<'a>,
    /// Where each literal's position, orientation and robconf go, on a
    /// pass that keeps no literal ([`Pass::Numbers`]).
    numbers: Option<&'m mut Vec<[f64; 11]>>,
}

/// What a pass has looked up already: names that are no reserved word,
/// and the last instruction's number of literals. A CAM program repeats
/// them on a million lines, and looking each up again was a quarter of
/// the cut pass.
#[derive(Default)]
struct Seen<'a> {
    names: Vec<&'a [u8]>,
    instruction: Option<(&'a [u8], usize)>,
}

/// How many names [`Seen`] keeps: the speed, zone, tool and work object
/// of a few kinds of move.
const SEEN_NAMES: usize = 16;

fn is_ident_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80
}

impl Cursor<'_, '_> {
    fn blank(&mut self) {
        while matches!(self.s.get(self.p), Some(b' ' | b'\t')) {
            self.p += 1;
        }
    }

    fn byte(&mut self, b: u8) -> Option<()> {
        self.blank();
        (self.s.get(self.p) == Some(&b)).then(|| self.p += 1)
    }

    /// An ASCII name that is no reserved word.
    fn name(&mut self) -> Option<Range<usize>> {
        self.name_as(self.names)
    }

    /// An ASCII name, looked up among the reserved words where `check`
    /// (a name known otherwise, a motion instruction or `WObj`, need not).
    fn name_as(&mut self, check: bool) -> Option<Range<usize>> {
        self.blank();
        let start = self.p;
        if !self.s.get(start)?.is_ascii_alphabetic() {
            return None;
        }
        let mut e = start + 1;
        while e < self.s.len() && is_ident_char(self.s[e]) {
            if self.s[e] >= 0x80 {
                return None;
            }
            e += 1;
        }
        let word = &self.s[start..e];
        if check && !self.seen.names.contains(&word) {
            if super::parse::is_reserved_word(std::str::from_utf8(word).ok()?) {
                return None;
            }
            if self.seen.names.len() < SEEN_NAMES {
                self.seen.names.push(word);
            }
        }
        self.p = e;
        Some(start..e)
    }

    /// A decimal literal, with a sign written against it (the parser folds
    /// such a sign into the literal): `-150.000`, `9E9`, `.5`, `1.`. Its
    /// value is read on the same pass as its form (17 numbers a target, a
    /// million targets): Clinger's fast path where it holds, as
    /// [`decimal_value`], else the standard parser.
    fn number(&mut self) -> Option<Number> {
        self.blank();
        let s = self.s;
        let start = self.p;
        let mut p = start;
        let negative = match s.get(p) {
            Some(b'-') => {
                p += 1;
                true
            }
            Some(b'+') => {
                p += 1;
                false
            }
            _ => false,
        };
        let digits_from = p;
        // The digits as one integer while it stays below 2^53, and how many
        // of them follow the point.
        let mut m = 0u64;
        let mut exact = true;
        let mut digits = |mut p: usize| {
            while let Some(&c) = s.get(p).filter(|c| c.is_ascii_digit()) {
                exact &= m < (1 << 53) / 10;
                m = m.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
                p += 1;
            }
            p
        };
        let int_end = digits(p);
        p = int_end;
        let mut frac = 0;
        if s.get(p) == Some(&b'.') {
            let frac_end = digits(p + 1);
            if int_end == digits_from && frac_end == p + 1 {
                return None;
            }
            frac = frac_end - (p + 1);
            p = frac_end;
        } else if int_end == digits_from {
            return None;
        }
        let mut exp = 0i32;
        if matches!(s.get(p), Some(b'e' | b'E')) {
            let mut q = p + 1;
            let minus = s.get(q) == Some(&b'-');
            if matches!(s.get(q), Some(b'+' | b'-')) {
                q += 1;
            }
            let from = q;
            while s.get(q).is_some_and(u8::is_ascii_digit) {
                q += 1;
            }
            if q == from {
                return None;
            }
            if q - from > 4 {
                exact = false;
            } else {
                for &d in &s[from..q] {
                    exp = exp * 10 + i32::from(d - b'0');
                }
            }
            if minus {
                exp = -exp;
            }
            p = q;
        }
        if s.get(p).is_some_and(|&b| is_ident_char(b) || b == b'.') {
            return None;
        }
        if !self.values {
            self.p = p;
            return Some(Number::new(0.0, start..p));
        }
        let v = match exact.then(|| clinger(m, exp - frac as i32)).flatten() {
            Some(v) => v,
            None => std::str::from_utf8(&s[digits_from..p])
                .ok()?
                .parse::<f64>()
                .ok()?,
        };
        if !v.is_finite() {
            return None;
        }
        self.p = p;
        Some(Number::new(if negative { -v } else { v }, start..p))
    }

    /// `[n, n, ...]` of exactly `N` numbers.
    fn numbers<const N: usize>(&mut self) -> Option<[Number; N]> {
        self.byte(b'[')?;
        // Filled in place: a million moves make four million groups, and
        // a vector each was an allocation each.
        let mut out = [(); N].map(|_| Number::new(0.0, 0..0));
        for (i, slot) in out.iter_mut().enumerate() {
            if i > 0 {
                self.byte(b',')?;
            }
            *slot = self.number()?;
        }
        self.byte(b']')?;
        Some(out)
    }

    fn robtarget(&mut self) -> Option<(usize, RobTargetValue)> {
        self.blank();
        let start = self.p;
        self.byte(b'[')?;
        let trans = self.numbers::<3>()?;
        self.byte(b',')?;
        let rot = self.numbers::<4>()?;
        self.byte(b',')?;
        let robconf = self.numbers::<4>()?;
        if let Some(out) = &mut self.numbers {
            let mut n = [0.0; 11];
            for (slot, x) in n.iter_mut().zip(trans.iter().chain(&rot).chain(&robconf)) {
                *slot = x.value;
            }
            out.push(n);
        }
        self.byte(b',')?;
        // Kept as numbers, the external axes' values are not needed: their
        // form is checked, as on the cut pass.
        let values = self.values;
        self.values = values && self.numbers.is_none();
        let extax = self.numbers::<6>();
        self.values = values;
        let extax = extax?;
        self.byte(b']')?;
        Some((
            start,
            RobTargetValue {
                trans,
                rot,
                robconf,
                extax,
            },
        ))
    }
}

/// The value of a decimal literal whose form is checked (digits, at most
/// one point, an exponent), as `str::parse` reads it. Clinger's fast
/// path where it holds (at most 2^53 in the digits, a power of ten up to
/// 10^22: one correctly rounded operation on exact operands gives the
/// correctly rounded value), the standard parser otherwise.
pub(super) fn decimal_value(text: &[u8]) -> Option<f64> {
    let slow = || std::str::from_utf8(text).ok()?.parse::<f64>().ok();
    let (mut m, mut frac, mut point) = (0u64, 0i32, false);
    let mut i = 0;
    while let Some(&c) = text.get(i) {
        match c {
            b'.' => point = true,
            b'0'..=b'9' => {
                if m >= (1 << 53) / 10 {
                    return slow();
                }
                m = m * 10 + u64::from(c - b'0');
                frac += i32::from(point);
            }
            _ => break,
        }
        i += 1;
    }
    let mut exp = 0i32;
    if i < text.len() {
        let (negative, digits) = match text.get(i + 1) {
            Some(b'-') => (true, &text[i + 2..]),
            Some(b'+') => (false, &text[i + 2..]),
            _ => (false, &text[i + 1..]),
        };
        if digits.len() > 4 {
            return slow();
        }
        for &d in digits {
            exp = exp * 10 + i32::from(d - b'0');
        }
        if negative {
            exp = -exp;
        }
    }
    clinger(m, exp - frac).or_else(slow)
}

/// `m · 10^e` correctly rounded, where one operation on exact operands
/// gives it (m below 2^53, |e| at most 22); `None` elsewhere.
#[inline]
fn clinger(m: u64, e: i32) -> Option<f64> {
    const POW10: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    let p = POW10.get(usize::try_from(e.unsigned_abs()).ok()?)?;
    Some(if e >= 0 { m as f64 * p } else { m as f64 / p })
}

/// How many robtarget literals lead the positional arguments of a move
/// instruction whose other arguments are exactly speed, zone and tool;
/// `None` for any other instruction.
fn leading_targets(name: &str) -> Option<usize> {
    let sig = motion_signature(name)?;
    let k = sig.robtargets.len();
    let plain = matches!(
        sig.kind,
        MotionKind::Linear | MotionKind::Joint | MotionKind::Circular
    ) && sig.robtargets.iter().enumerate().all(|(i, &at)| i == at)
        && sig.speed == Some(ArgAt::Index(k))
        && sig.zone == Some(ArgAt::Index(k + 1))
        && sig.tool == Some(ArgAt::Index(k + 2));
    plain.then_some(k)
}

/// The move that starts at `at` of `src`, when it is one this recogniser
/// reads; `None` otherwise (the pest grammar then reads it).
pub fn recognise(src: &[u8], at: usize) -> Option<FastMove> {
    read_move(src, at, Pass::Values, &mut Seen::default())
}

/// How [`read_move`] reads: on the cut pass, the form alone, each name
/// checked; again, a cut move's values, knowing what the cut pass found.
#[derive(Clone, Copy)]
enum Pass {
    Form,
    Values,
    /// Values kept as numbers only (the cursor's sink), no literal.
    Numbers,
    /// A move cut with this many literals: its names were checked then.
    Again(usize),
}

fn read_move<'a>(src: &'a [u8], at: usize, pass: Pass, seen: &mut Seen<'a>) -> Option<FastMove> {
    read_move_into(src, at, pass, seen, None)
}

/// [`read_move`], the numbers of a [`Pass::Numbers`] put in `numbers`
/// (left as they were where the move is not read).
fn read_move_into<'a>(
    src: &'a [u8],
    at: usize,
    pass: Pass,
    seen: &mut Seen<'a>,
    numbers: Option<&mut Vec<[f64; 11]>>,
) -> Option<FastMove> {
    let before = numbers.as_ref().map(|n| n.len());
    let mut c = Cursor {
        s: src,
        p: at,
        values: !matches!(pass, Pass::Form),
        names: !matches!(pass, Pass::Again(_)),
        seen,
        numbers,
    };
    let m = read_with(&mut c, src, at, pass);
    if let (None, Some(out), Some(n)) = (&m, c.numbers, before) {
        out.truncate(n);
    }
    m
}

fn read_with<'a>(c: &mut Cursor<'a, '_>, src: &'a [u8], at: usize, pass: Pass) -> Option<FastMove> {
    // Motion instructions are no reserved words: their signature says.
    let instruction = c.name_as(false)?;
    let word = &src[instruction.clone()];
    let k = match (pass, c.seen.instruction) {
        (Pass::Again(k), _) => k,
        (_, Some((w, k))) if w == word => k,
        _ => {
            let k = leading_targets(std::str::from_utf8(word).ok()?)?;
            c.seen.instruction = Some((word, k));
            k
        }
    };
    if !matches!(src.get(c.p), Some(b' ' | b'\t')) {
        return None;
    }
    let keep = !matches!(pass, Pass::Form | Pass::Numbers);
    let mut targets = Vec::with_capacity(if keep { k } else { 0 });
    for i in 0..k {
        if i > 0 {
            c.byte(b',')?;
        }
        let target = c.robtarget()?;
        if keep {
            targets.push(target);
        }
    }
    c.byte(b',')?;
    let speed = c.name()?;
    c.byte(b',')?;
    let zone = c.name()?;
    c.byte(b',')?;
    let tool = c.name()?;
    let mut wobj = None;
    let mut wobj_word = None;
    if c.byte(b'\\').is_some() {
        let word = c.name_as(false)?;
        if !src[word.clone()].eq_ignore_ascii_case(b"WObj") {
            return None;
        }
        c.byte(b':')?;
        // `:=` is one token: no blank inside.
        if src.get(c.p) != Some(&b'=') {
            return None;
        }
        c.p += 1;
        wobj = Some(c.name()?);
        wobj_word = Some(word);
    }
    c.byte(b';')?;
    Some(FastMove {
        span: at..c.p,
        instruction,
        targets,
        literals: k,
        speed,
        zone,
        tool,
        wobj,
        wobj_word,
    })
}

/// A file with its recognised moves cut out: `bytes` is what is left
/// (every line still there, so lines and the columns before a cut are
/// those of the file), `cuts` the ranges cut out of the file, in order.
#[derive(Debug, Default)]
pub struct Skeleton {
    pub bytes: Vec<u8>,
    pub cuts: Vec<Range<usize>>,
    /// How many robtarget literals each cut move holds (two for MoveC).
    pub literals: Vec<u8>,
    /// The cut moves' numbers, where asked for ([`skeleton_with_poses`]).
    pub poses: Option<CutPoses>,
    /// Where each cut is in the skeleton, and the bytes cut out before
    /// cut k (k = 0..=cuts.len()).
    starts: Vec<usize>,
    cut_before: Vec<usize>,
}

impl Skeleton {
    /// The file's offset of the skeleton's offset `at`: a kept byte right
    /// after a cut maps to after the cut.
    pub fn file_offset(&self, at: usize) -> usize {
        let k = self.starts.partition_point(|&s| s <= at);
        at + self.cut_before.get(k).copied().unwrap_or(0)
    }

    /// Cut move `k` read again from `src`, the file it was cut from, with
    /// its values ([`recognise`]'s answer, without the checks the cut
    /// made).
    pub fn reread(&self, src: &[u8], k: usize) -> Option<FastMove> {
        let at = self.cuts.get(k)?.start;
        let k = usize::from(*self.literals.get(k)?);
        read_move(src, at, Pass::Again(k), &mut Seen::default())
    }

    /// Where cut `k` was in the skeleton: the offset of the byte after it
    /// (on the same line as the cut move).
    pub fn place_of_cut(&self, k: usize) -> usize {
        self.starts.get(k).copied().unwrap_or(self.bytes.len())
    }

    /// Whether a cut move came before one of its routine's declarations
    /// (the skeleton's kept bytes parsed as `program`): the grammar
    /// refuses the file (a routine's data come before its first
    /// statement), the skeleton alone would not.
    pub fn cuts_before_declarations(&self, program: &super::Program) -> bool {
        program.modules.iter().flat_map(|m| &m.routines).any(|r| {
            let Some(last) = r.data.iter().map(|d| d.pos.offset).max() else {
                return false;
            };
            let first = self.first_cut_from(r.pos.offset);
            first < self.cuts.len() && self.place_of_cut(first) < last
        })
    }

    /// The first cut whose place is at or after `at` of the skeleton.
    pub fn first_cut_from(&self, at: usize) -> usize {
        self.starts.partition_point(|&s| s < at)
    }
}

/// What a walk of the cut moves needs of them, read as they are cut (a
/// second reading of a million moves was most of a walk).
#[derive(Debug, Default)]
pub struct CutPoses {
    /// Literals' position, orientation and robconf numbers, in pieces
    /// as they were read (on every core: gathered into one, they were
    /// copied to fresh memory, a third of the cut).
    pub numbers: Vec<Vec<[f64; 11]>>,
    /// Each cut move's first literal's numbers in `numbers` (piece,
    /// index), and its instruction's end and speed's start from its
    /// start: the bytes before the one and from the other on say what
    /// the move is, apart from its literals.
    pub moves: Vec<((u32, u32), u32, u32)>,
}

impl CutPoses {
    /// The numbers of cut move `k`'s `n` literals.
    pub fn numbers_of(&self, k: usize, n: usize) -> Option<&[[f64; 11]]> {
        let &((piece, first), _, _) = self.moves.get(k)?;
        let first = first as usize;
        self.numbers.get(piece as usize)?.get(first..first + n)
    }
}

/// [`skeleton`], with the numbers a walk of the cut moves needs.
pub fn skeleton_with_poses(src: &[u8]) -> Skeleton {
    cut(src, true)
}

/// Cut the moves [`recognise`] reads out of `src`, where it is safe to:
/// inside a routine, and with nothing but blanks or a comment after the
/// move on its line (so that no statement the skeleton keeps moves to
/// another column). A file the scanner refuses is returned whole: the
/// parser then reports why.
pub fn skeleton(src: &[u8]) -> Skeleton {
    cut(src, false)
}

fn cut(src: &[u8], poses: bool) -> Skeleton {
    let mut scanner = Scanner::new(src);
    if src.starts_with(&[0xEF, 0xBB, 0xBF]) {
        scanner.skip_to(3);
    }
    let mut cuts = Vec::new();
    let mut literals = Vec::new();
    let mut kept = poses.then(CutPoses::default);
    let mut in_routine = false;
    let Found {
        moves: found,
        shapes,
        numbers: mut pieces,
    } = moves_at_line_starts(src, poses);
    // Moves read here, after another statement on their line.
    let mut numbers = Vec::new();
    let here = pieces.len() as u32;
    let mut next = found.iter().enumerate().peekable();
    loop {
        if in_routine {
            let at = scanner.next_start();
            while next.next_if(|f| f.1 .0.start < at).is_some() {}
            let m = match next.peek() {
                Some(&(i, f)) if f.0.start == at => {
                    if let (Some(kept), Some(&shape)) = (&mut kept, shapes.get(i)) {
                        kept.moves.push(shape);
                    }
                    Some(f.clone())
                }
                // A statement after another on its line.
                _ => {
                    let first = numbers.len();
                    let (pass, sink) = match poses {
                        true => (Pass::Numbers, Some(&mut numbers)),
                        false => (Pass::Form, None),
                    };
                    let m = read_move_into(src, at, pass, &mut Seen::default(), sink)
                        .filter(|m| rest_is_blank(src, m.span.end));
                    numbers.truncate(match &m {
                        Some(_) => numbers.len(),
                        None => first,
                    });
                    m.map(|m| {
                        if let Some(kept) = &mut kept {
                            kept.moves.push(shape_of(&m, (here, first as u32)));
                        }
                        (m.span, m.literals as u8)
                    })
                }
            };
            if let Some((span, n)) = m {
                cuts.push(span.clone());
                literals.push(n);
                scanner.skip_to(span.end);
                continue;
            }
        }
        match scanner.next_piece() {
            Ok(Some(piece)) => match piece.kind {
                PieceKind::Routine => in_routine = true,
                PieceKind::EndRoutine | PieceKind::Module | PieceKind::EndModule => {
                    in_routine = false
                }
                _ => {}
            },
            Ok(None) => break,
            Err(_) => {
                cuts.clear();
                literals.clear();
                kept = kept.map(|_| CutPoses::default());
                break;
            }
        }
    }
    let mut bytes = Vec::with_capacity(src.len() - cuts.iter().map(Range::len).sum::<usize>());
    let mut at = 0;
    for c in &cuts {
        bytes.extend_from_slice(&src[at..c.start]);
        at = c.end;
    }
    bytes.extend_from_slice(&src[at..]);
    let mut cut_before = Vec::with_capacity(cuts.len() + 1);
    let mut starts = Vec::with_capacity(cuts.len());
    cut_before.push(0);
    for c in &cuts {
        let before = cut_before.last().copied().unwrap_or(0);
        starts.push(c.start - before);
        cut_before.push(before + c.len());
    }
    Skeleton {
        bytes,
        cuts,
        literals,
        poses: kept.map(|k| {
            pieces.push(numbers);
            CutPoses {
                numbers: pieces,
                ..k
            }
        }),
        starts,
        cut_before,
    }
}

/// A move's first literal's numbers' index and its shape (see
/// [`CutPoses::moves`]).
fn shape_of(m: &FastMove, first: (u32, u32)) -> ((u32, u32), u32, u32) {
    let at = |p: usize| (p - m.span.start) as u32;
    (first, at(m.instruction.end), at(m.speed.start))
}

/// One part's moves, shapes and numbers, as [`Found`] holds them.
type Part = (
    Vec<(Range<usize>, u8)>,
    Vec<((u32, u32), u32, u32)>,
    Vec<[f64; 11]>,
);

/// The moves found at line starts, and where asked, each one's shape
/// (see [`CutPoses::moves`]) and its literals' numbers, a piece a part.
#[derive(Default)]
struct Found {
    moves: Vec<(Range<usize>, u8)>,
    shapes: Vec<((u32, u32), u32, u32)>,
    numbers: Vec<Vec<[f64; 11]>>,
}

/// The moves [`skeleton`] would cut that start a line (after blanks),
/// found on every core ahead of the scan, which is sequential (strings
/// and comments decide what a byte is) and then only looks them up: the
/// span and the number of literals of each, in file order. Whether one
/// is cut is still the scan's to say (it must be a statement of a
/// routine).
fn moves_at_line_starts(src: &[u8], poses: bool) -> Found {
    use rayon::prelude::*;
    const PART: usize = 1 << 20;
    let mut bounds = vec![0];
    while let Some(&last) = bounds.last() {
        if last >= src.len() {
            break;
        }
        let end = (last + PART).min(src.len());
        let end = memchr::memchr(b'\n', &src[end..]).map_or(src.len(), |i| end + i + 1);
        bounds.push(end);
    }
    let parts: Vec<Part> = bounds
        .par_windows(2)
        .map(|w| {
            let (mut moves, mut shapes) = (Vec::new(), Vec::new());
            // Room for a literal every hundred bytes (a CAM line is
            // longer): grown by doubling, the numbers were copied over
            // and over.
            let mut numbers = Vec::with_capacity(if poses { (w[1] - w[0]) / 100 } else { 0 });
            let mut seen = Seen::default();
            let mut line = w[0];
            while line < w[1] {
                let mut at = line;
                while matches!(src.get(at), Some(b' ' | b'\t')) {
                    at += 1;
                }
                let first = numbers.len();
                let (pass, sink) = match poses {
                    true => (Pass::Numbers, Some(&mut numbers)),
                    false => (Pass::Form, None),
                };
                let m = read_move_into(src, at, pass, &mut seen, sink)
                    .filter(|m| rest_is_blank(src, m.span.end));
                // The line's end is looked for after the move read on
                // it (a move stays on its line), not over its bytes
                // again.
                let from = m.as_ref().map_or(line, |m| m.span.end);
                line = memchr::memchr(b'\n', &src[from..w[1]]).map_or(w[1], |i| from + i + 1);
                match m {
                    Some(m) => {
                        if poses {
                            shapes.push(shape_of(&m, (0, first as u32)));
                        }
                        moves.push((m.span, m.literals as u8));
                    }
                    None => numbers.truncate(first),
                }
            }
            (moves, shapes, numbers)
        })
        .collect();
    let mut all = Found {
        moves: Vec::with_capacity(parts.iter().map(|p| p.0.len()).sum()),
        ..Found::default()
    };
    for (piece, (moves, shapes, numbers)) in parts.into_iter().enumerate() {
        all.moves.extend(moves);
        all.shapes.extend(
            shapes
                .into_iter()
                .map(|((_, first), a, b)| ((piece as u32, first), a, b)),
        );
        if poses {
            all.numbers.push(numbers);
        }
    }
    all
}

/// Nothing but blanks, then a line end, a comment or the end of the file.
fn rest_is_blank(src: &[u8], mut p: usize) -> bool {
    while matches!(src.get(p), Some(b' ' | b'\t')) {
        p += 1;
    }
    matches!(src.get(p), None | Some(b'\r' | b'\n' | b'!'))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Option<f64> {
        let mut seen = Seen::default();
        let mut c = Cursor {
            s: text.as_bytes(),
            p: 0,
            values: true,
            names: true,
            seen: &mut seen,
            numbers: None,
        };
        let n = c.number()?;
        (c.p == text.len()).then_some(n.value)
    }

    /// The value read with the form is `str::parse`'s, to the bit: every
    /// form RAPID writes, mantissas past 2^53, exponents past 10^22 and
    /// past four digits, and what is no number.
    #[test]
    fn numbers_read_as_the_standard_parser_reads_them() {
        let mut state = 11u64;
        let mut next = |k: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % k
        };
        let mut checked = 0;
        for _ in 0..300_000 {
            let digits = |n: u64, next: &mut dyn FnMut(u64) -> u64| {
                (0..n)
                    .map(|_| char::from(b'0' + next(10) as u8))
                    .collect::<String>()
            };
            let sign = ["", "-", "+"][next(3) as usize];
            let int = digits(next(19), &mut next);
            let frac = match next(3) {
                0 => String::new(),
                1 => ".".to_string(),
                _ => format!(".{}", digits(next(19), &mut next)),
            };
            let exp_digits = digits(next(6), &mut next);
            let exp = match next(4) {
                0 => format!(
                    "{}{}{exp_digits}",
                    ["E", "e"][next(2) as usize],
                    ["", "+", "-"][next(3) as usize]
                ),
                _ => String::new(),
            };
            let text = format!("{sign}{int}{frac}{exp}");
            let mantissa = !int.is_empty() || frac.len() > 1;
            let exponent = exp.is_empty() || !exp_digits.is_empty();
            let got = read(&text);
            if mantissa && exponent {
                let want = text.parse::<f64>().ok().filter(|v| v.is_finite());
                assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{text}");
                checked += usize::from(got.is_some());
            } else {
                assert_eq!(got, None, "{text}");
            }
        }
        assert!(checked > 100_000);
        for (text, want) in [
            ("9E9", 9e9),
            ("9E+09", 9e9),
            (".5", 0.5),
            ("1.", 1.0),
            ("-0", -0.0),
        ] {
            assert_eq!(
                read(text).map(f64::to_bits),
                Some(f64::to_bits(want)),
                "{text}"
            );
        }
    }
}
