//! The fast lane's reader: one token at a time over what the statements
//! of large programs are made of (plain names, decimal numbers, `[`, `]`,
//! `,`, `\`, `:=`, `;` and blanks). Anything else (a comment, a string,
//! an expression, a byte above 0x7F) is not its to read: it gives up, and
//! the grammar reads the statement.

use super::decline::StoppedAt;
use crate::rapid::{Number, PoseNumbers, RobTargetValue};

/// Reads tokens from `p` on. Blanks are spaces and tabs, and line ends
/// where `lines` (inside an array's value). Numbers are read with their
/// values where `values` (else their form alone, and their value 0).
pub(crate) struct Cursor<'a, 'm> {
    pub s: &'a [u8],
    pub p: usize,
    pub values: bool,
    pub lines: bool,
    pub seen: &'m mut Seen<'a>,
}

/// What a reader has looked up already: names that are no reserved word,
/// and the last instruction's number of literals. A large program repeats
/// them on a million lines, and looking each up again was a quarter of
/// reading them.
#[derive(Default)]
pub(crate) struct Seen<'a> {
    names: Vec<&'a [u8]>,
    pub instruction: Option<(&'a [u8], Option<usize>)>,
}

/// How many names [`Seen`] keeps: the speed, zone, tool and work object
/// of a few kinds of move.
const SEEN_NAMES: usize = 16;

/// Whether text ending in `before` (blanks skipped) ends with an
/// operand: a sign after it is an operator, not a number's.
fn after_operand(before: &[u8]) -> bool {
    before
        .iter()
        .rev()
        .find(|b| !matches!(b, b' ' | b'\t'))
        .is_some_and(|&b| is_ident_char(b) || matches!(b, b'.' | b']' | b')'))
}

pub(crate) fn is_ident_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80
}

impl<'a, 'm> Cursor<'a, 'm> {
    /// A reader of a statement's form from `p` on (numbers' values not
    /// read, line ends not blanks).
    pub fn form(s: &'a [u8], p: usize, seen: &'m mut Seen<'a>) -> Self {
        Cursor {
            s,
            p,
            values: false,
            lines: false,
            seen,
        }
    }

    /// What stands at the reader's place, blanks skipped: why it stopped
    /// there (see [`Found`]).
    pub fn found(&self) -> StoppedAt {
        let s = self.s;
        let mut p = self.p;
        while matches!(s.get(p), Some(b' ' | b'\t')) {
            p += 1;
        }
        let Some(&b) = s.get(p) else {
            return StoppedAt::EndOfText;
        };
        match b {
            b'!' => StoppedAt::Comment,
            b'"' => StoppedAt::Text,
            b'\r' | b'\n' => StoppedAt::LineBreak,
            0x80.. => StoppedAt::NonAscii,
            b'0'..=b'9' | b'.' => StoppedAt::Number,
            // A sign starting a number (not an operator after an operand).
            b'+' | b'-'
                if s.get(p + 1)
                    .is_some_and(|c| c.is_ascii_digit() || *c == b'.')
                    && !after_operand(&s[..p]) =>
            {
                StoppedAt::Number
            }
            b if b.is_ascii_alphabetic() => {
                let end = s[p..]
                    .iter()
                    .position(|&c| !is_ident_char(c))
                    .map_or(s.len(), |e| p + e);
                let word = &s[p..end];
                if !word.is_ascii() {
                    StoppedAt::NonAscii
                } else if std::str::from_utf8(word).is_ok_and(crate::rapid::reserved::is_reserved) {
                    StoppedAt::ReservedWord
                } else {
                    StoppedAt::Name
                }
            }
            b => StoppedAt::Char(b),
        }
    }

    pub fn blank(&mut self) {
        while let Some(&b) = self.s.get(self.p) {
            match b {
                b' ' | b'\t' => self.p += 1,
                b'\r' | b'\n' if self.lines => self.p += 1,
                _ => break,
            }
        }
    }

    pub fn byte(&mut self, b: u8) -> Option<()> {
        self.blank();
        (self.s.get(self.p) == Some(&b)).then(|| self.p += 1)
    }

    /// `:=`, one token: no blank inside.
    pub fn assign(&mut self) -> Option<()> {
        self.byte(b':')?;
        (self.s.get(self.p) == Some(&b'=')).then(|| self.p += 1)
    }

    /// An ASCII name that is no reserved word.
    pub fn name(&mut self) -> Option<std::ops::Range<usize>> {
        self.name_as(true)
    }

    /// An ASCII name, looked up among the reserved words where `check`
    /// (a name known otherwise, a motion instruction or `WObj`, need
    /// not be).
    pub fn name_as(&mut self, check: bool) -> Option<std::ops::Range<usize>> {
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
        // A name longer than RAPID allows is the grammar's, whose scanner
        // refuses it: the lane never holds what the controller refuses.
        if e - start > crate::rapid::scan::MAX_NAME_CHARS {
            return None;
        }
        let word = &self.s[start..e];
        if check && !self.seen.names.contains(&word) {
            if crate::rapid::reserved::is_reserved(std::str::from_utf8(word).ok()?) {
                return None;
            }
            if self.seen.names.len() < SEEN_NAMES {
                self.seen.names.push(word);
            }
        }
        self.p = e;
        Some(start..e)
    }

    /// A word among `words`, as a name (case ignored); its index.
    pub fn keyword(&mut self, words: &[&str]) -> Option<usize> {
        let save = self.p;
        let r = self.name_as(false)?;
        let w = &self.s[r];
        match words
            .iter()
            .position(|k| w.eq_ignore_ascii_case(k.as_bytes()))
        {
            Some(i) => Some(i),
            None => {
                self.p = save;
                None
            }
        }
    }

    /// A whole decimal number, no sign (an array's size).
    pub fn count(&mut self) -> Option<(usize, std::ops::Range<usize>)> {
        self.blank();
        let start = self.p;
        let mut n: usize = 0;
        while let Some(&c) = self.s.get(self.p).filter(|c| c.is_ascii_digit()) {
            n = n.checked_mul(10)?.checked_add(usize::from(c - b'0'))?;
            self.p += 1;
        }
        if self.p == start
            || self
                .s
                .get(self.p)
                .is_some_and(|&b| is_ident_char(b) || b == b'.')
        {
            return None;
        }
        Some((n, start..self.p))
    }

    /// A decimal literal, with a sign written against it (the parser folds
    /// such a sign into the literal): `-150.000`, `9E9`, `.5`, `1.`. Its
    /// value is read on the same pass as its form: Clinger's fast path
    /// where it holds, as [`decimal_value`], else the standard parser.
    pub fn number(&mut self) -> Option<Number> {
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
            // A value read later must be finite: at most 60 digits and a
            // two-digit exponent always are (no coordinate needs more).
            let digit_count = int_end - digits_from + frac;
            if digit_count > 60 || exp.abs() > 99 || !exact && q_exponent_long(s, int_end, p) {
                return None;
            }
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

    /// `[n, n, ...]` of exactly `N` numbers, each given to `put` with
    /// its index: the one reading of a group, whatever is kept of it
    /// (nothing, the numbers, their values).
    fn each_number<const N: usize>(&mut self, mut put: impl FnMut(usize, Number)) -> Option<()> {
        self.byte(b'[')?;
        for i in 0..N {
            if i > 0 {
                self.byte(b',')?;
            }
            put(i, self.number()?);
        }
        self.byte(b']')
    }

    /// A robtarget literal's groups read in order (position,
    /// orientation, robconf, external axes), each number given to `put`
    /// with its group's index and its own; `whole`: all four and the
    /// closing `]`, else the three a pose is made of.
    fn robtarget_groups(
        &mut self,
        whole: bool,
        mut put: impl FnMut(usize, usize, Number),
    ) -> Option<()> {
        self.byte(b'[')?;
        self.each_number::<3>(|i, n| put(0, i, n))?;
        self.byte(b',')?;
        self.each_number::<4>(|i, n| put(1, i, n))?;
        self.byte(b',')?;
        self.each_number::<4>(|i, n| put(2, i, n))?;
        if !whole {
            return Some(());
        }
        self.byte(b',')?;
        self.each_number::<6>(|i, n| put(3, i, n))?;
        self.byte(b']')
    }

    /// A robtarget literal read for its form alone (what the parse's lane
    /// reads: its numbers' values are read when a target is made of it):
    /// where its `[` is.
    pub fn literal(&mut self) -> Option<usize> {
        self.blank();
        let start = self.p;
        self.robtarget_groups(true, |_, _, _| ())?;
        Some(start)
    }

    /// A robtarget literal's numbers into `v`, in place (a million
    /// targets filled one after another copied each literal's 272 bytes
    /// three times on its way); `v` partly written where it fails.
    pub fn robtarget_into(&mut self, v: &mut RobTargetValue) -> Option<()> {
        self.robtarget_groups(true, |g, i, n| match g {
            0 => v.trans[i] = n,
            1 => v.rot[i] = n,
            2 => v.robconf[i] = n,
            _ => v.extax[i] = n,
        })
    }

    /// `[n, n, ...]` of exactly `N` numbers.
    pub fn numbers<const N: usize>(&mut self) -> Option<[Number; N]> {
        // Filled in place: a million targets make four million groups,
        // and a vector each was an allocation each.
        let mut out = [(); N].map(|_| Number::new(0.0, 0..0));
        self.each_number::<N>(|i, n| out[i] = n)?;
        Some(out)
    }

    /// The pose numbers of a robtarget literal the lane has read whole
    /// before (its external axes, read then, are not read again).
    pub fn pose_numbers(&mut self) -> Option<PoseNumbers> {
        let mut p = PoseNumbers {
            trans: [0.0; 3],
            rot: [0.0; 4],
            robconf: [0.0; 4],
        };
        self.robtarget_groups(false, |g, i, n| match g {
            0 => p.trans[i] = n.value,
            1 => p.rot[i] = n.value,
            _ => p.robconf[i] = n.value,
        })?;
        Some(p)
    }

    /// A jointtarget literal `[[r1..r6],[e1..e6]]`: where its `[` is, and
    /// its numbers.
    pub fn jointtarget(&mut self) -> Option<(usize, [Number; 6], [Number; 6])> {
        self.blank();
        let start = self.p;
        self.byte(b'[')?;
        let robax = self.numbers::<6>()?;
        self.byte(b',')?;
        let extax = self.numbers::<6>()?;
        self.byte(b']')?;
        Some((start, robax, extax))
    }
}

/// Whether the exponent of the number ending at `end` (its mantissa's
/// digits ending at `from`) has more than four digits.
fn q_exponent_long(s: &[u8], from: usize, end: usize) -> bool {
    s[from..end]
        .iter()
        .position(|&b| b == b'e' || b == b'E')
        .is_some_and(|e| {
            s[from + e + 1..end]
                .iter()
                .filter(|b| b.is_ascii_digit())
                .count()
                > 4
        })
}

/// The value of a decimal literal whose form is checked (digits, at most
/// one point, an exponent), as `str::parse` reads it. Clinger's fast
/// path where it holds (at most 2^53 in the digits, a power of ten up to
/// 10^22: one correctly rounded operation on exact operands gives the
/// correctly rounded value), the standard parser otherwise.
pub(crate) fn decimal_value(text: &[u8]) -> Option<f64> {
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
