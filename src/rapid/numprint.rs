//! A fingerprint of the numbers a RAPID file holds, outside its comments
//! and strings: what a corrected file's marker records, so that a target
//! re-taught, added or pasted after the correction is found.
//!
//! The encoding, version 1 (pinned by a test; change it only with a new
//! version):
//! - the bytes are read as RAPID's lexer does: `!` starts a comment to the
//!   end of the line; `"` a string (`""` inside it is a quote); a letter
//!   or `_` an identifier (letters, digits, `_`); a digit, or `.` before a
//!   digit, a number (`12`, `0.5`, `.5`, `9E+09`, `1E5`; `1THEN` is the
//!   number 1 and the word THEN);
//! - each number is taken to six significant digits (rounded half up on
//!   the seventh), which is what a controller keeps of a `num` when it
//!   saves a module: `1234.567` and `1234.57` are one number;
//! - each number is hashed as the byte 1, its six digits as a u32 and its
//!   decimal exponent (the number is 0.dddddd × 10^exponent) as an i32,
//!   both little-endian; zero as six zero digits and exponent 0; each `-`
//!   and `+` outside numbers as the byte 2 or 3; nothing else is hashed;
//! - the fingerprint is `v1 sha256:` and the first 16 hex digits of the
//!   SHA-256 of those bytes.
//!
//! Layout, indentation, line ends, comments, strings and names do not
//! change it; any number does. Bytes are fed in pieces as they are
//! written: the result does not depend on where the pieces are cut.

use sha2::{Digest, Sha256};

/// The encoding's name and version, as the fingerprint starts.
pub const VERSION: &str = "v1";

/// Significant digits kept of each number.
const DIGITS: usize = 6;

/// Where the lexer is between two pieces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Normal,
    Comment,
    Str,
    /// After a `"` inside a string: another `"` continues it.
    StrQuote,
    Ident,
    /// A `.` that starts a number if a digit follows.
    Dot,
    Int,
    Frac,
    /// After `E`: a sign or a digit makes it an exponent.
    ExpMark,
    /// After `E` and a sign: a digit makes it an exponent.
    ExpSign,
    Exp,
}

/// A number being read: its significant digits (the first seven), how
/// many digits stood before the decimal point after the leading zeros,
/// and its written exponent.
#[derive(Debug, Clone, Copy, Default)]
struct Num {
    digits: [u8; DIGITS + 1],
    len: usize,
    /// Digits seen before the point, leading zeros excluded.
    int_sig: i64,
    /// Leading zeros after the point before the first significant digit.
    frac_zeros: i64,
    any_sig: bool,
    exp: i64,
    exp_neg: bool,
    /// The sign of an exponent that turned out not to be one (`1E+x`).
    pending_sign: Option<u8>,
}

impl Num {
    fn digit(&mut self, d: u8, fraction: bool) {
        if d == b'0' && !self.any_sig {
            if fraction {
                self.frac_zeros += 1;
            }
            return;
        }
        self.any_sig = true;
        if !fraction {
            self.int_sig += 1;
        }
        if self.len < self.digits.len() {
            self.digits[self.len] = d - b'0';
            self.len += 1;
        }
    }

    /// Six digits and the exponent: the number is 0.dddddd × 10^exponent.
    fn canonical(&self) -> (u32, i32) {
        if !self.any_sig {
            return (0, 0);
        }
        let mut m: u32 = 0;
        for k in 0..DIGITS {
            m = m * 10 + u32::from(*self.digits.get(k).filter(|_| k < self.len).unwrap_or(&0));
        }
        let written = if self.exp_neg { -self.exp } else { self.exp };
        let mut e = if self.int_sig > 0 {
            self.int_sig
        } else {
            -self.frac_zeros
        } + written;
        if self.len > DIGITS && self.digits[DIGITS] >= 5 {
            m += 1;
            if m == 1_000_000 {
                m = 100_000;
                e += 1;
            }
        }
        (m, e.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32)
    }
}

/// A number's significant digits as the fast reader gathers them: the
/// first six as one integer, how many were seen (counted to seven), the
/// seventh (which rounds).
#[derive(Default)]
struct Sig {
    m: u32,
    len: u32,
    seventh: u8,
}

impl Sig {
    fn take(&mut self, d: u8) {
        if self.len < DIGITS as u32 {
            self.m = self.m * 10 + u32::from(d);
        } else if self.len == DIGITS as u32 {
            self.seventh = d;
        }
        self.len = (self.len + 1).min(DIGITS as u32 + 1);
    }
}

/// The fingerprint of the numbers fed so far.
#[derive(Clone)]
pub struct NumberPrint {
    sha: Sha256,
    buf: Vec<u8>,
    state: State,
    num: Num,
}

impl Default for NumberPrint {
    fn default() -> Self {
        NumberPrint::new()
    }
}

impl NumberPrint {
    pub fn new() -> NumberPrint {
        NumberPrint {
            sha: Sha256::new(),
            buf: Vec::with_capacity(PAGE),
            state: State::Normal,
            num: Num::default(),
        }
    }

    /// The fingerprint of `bytes`, whole.
    pub fn of(bytes: &[u8]) -> String {
        let mut p = NumberPrint::new();
        p.feed(bytes);
        p.finish()
    }

    /// Read the next piece of the file.
    pub fn feed(&mut self, bytes: &[u8]) {
        // A page at a time: the tokens of a megabyte are not held.
        for piece in bytes.chunks(PAGE) {
            self.lex(piece);
            self.flush_page();
        }
    }

    /// Read `bytes`, their tokens into the buffer.
    fn lex(&mut self, bytes: &[u8]) {
        let mut i = 0;
        while i < bytes.len() {
            if self.state != State::Normal {
                // A token cut by the piece's start: byte by byte.
                self.byte(bytes[i]);
                i += 1;
                continue;
            }
            match self.token(bytes, i) {
                Some(next) => i = next,
                // A token running past the piece's end: byte by byte,
                // its state carried to the next piece.
                None => {
                    for &b in &bytes[i..] {
                        self.byte(b);
                    }
                    i = bytes.len();
                }
            }
        }
    }

    /// The token at `i` (outside any token), read whole where it ends
    /// within `s`: where the next one starts. `None` where it runs to the
    /// end of `s` (the byte-by-byte reader takes it). The same tokens as
    /// [`Self::byte`] reads, a slice at a time.
    fn token(&mut self, s: &[u8], mut i: usize) -> Option<usize> {
        let b = s[i];
        match CLASS[usize::from(b)] {
            Class::Other => {
                i += 1;
                while i < s.len() && CLASS[usize::from(s[i])] == Class::Other {
                    i += 1;
                }
                Some(i)
            }
            Class::Word => {
                i += 1;
                while i < s.len() && is_word(s[i]) {
                    i += 1;
                }
                (i < s.len()).then_some(i)
            }
            Class::Comment => {
                let end = memchr::memchr2(b'\n', b'\r', &s[i..])?;
                Some(i + end)
            }
            Class::Quote => {
                let mut j = i + 1;
                loop {
                    j += memchr::memchr(b'"', &s[j..])?;
                    // `""` inside a string is a quote; the byte after the
                    // closing one must be seen to know which.
                    match s.get(j + 1) {
                        Some(b'"') => j += 2,
                        Some(_) => return Some(j + 1),
                        None => return None,
                    }
                }
            }
            Class::Sign => {
                self.op(b);
                Some(i + 1)
            }
            Class::Dot if !s.get(i + 1)?.is_ascii_digit() => Some(i + 1),
            Class::Dot | Class::Digit => self.number(s, i),
        }
    }

    /// A number starting at `i` (a digit, or `.` and a digit), read whole
    /// where it ends within `s`. The same number [`Num`] makes digit by
    /// digit, its six digits gathered straight into one integer: most of
    /// a corrected file's bytes are numbers, and this is where the
    /// fingerprint spends its time.
    fn number(&mut self, s: &[u8], mut i: usize) -> Option<usize> {
        let mut sig = Sig::default();
        let mut int_sig: i64 = 0;
        let mut frac_zeros: i64 = 0;
        while i < s.len() && s[i].is_ascii_digit() {
            if s[i] != b'0' || sig.len > 0 {
                int_sig += 1;
                sig.take(s[i] - b'0');
            }
            i += 1;
        }
        if s.get(i) == Some(&b'.') {
            i += 1;
            while i < s.len() && s[i].is_ascii_digit() {
                if s[i] != b'0' || sig.len > 0 {
                    sig.take(s[i] - b'0');
                } else {
                    frac_zeros += 1;
                }
                i += 1;
            }
        }
        let (mut exp, mut exp_neg) = (0i64, false);
        if matches!(s.get(i)?, b'e' | b'E') {
            // An exponent only where a digit follows (after a sign).
            let mut j = i + 1;
            let sign = match *s.get(j)? {
                c @ (b'+' | b'-') => {
                    j += 1;
                    Some(c)
                }
                _ => None,
            };
            if s.get(j)?.is_ascii_digit() {
                exp_neg = sign == Some(b'-');
                while j < s.len() && s[j].is_ascii_digit() {
                    let d = i64::from(s[j] - b'0');
                    exp = exp.saturating_mul(10).saturating_add(d).min(1 << 40);
                    j += 1;
                }
                if j == s.len() {
                    return None;
                }
                i = j;
            }
        }
        let Sig { m, len, seventh } = sig;
        let (m, e) = if len == 0 {
            (0, 0)
        } else {
            let mut m = m * POW10[DIGITS - (len as usize).min(DIGITS)];
            let written = if exp_neg { -exp } else { exp };
            let mut e = if int_sig > 0 { int_sig } else { -frac_zeros } + written;
            if len > DIGITS as u32 && seventh >= 5 {
                m += 1;
                if m == 1_000_000 {
                    m = 100_000;
                    e += 1;
                }
            }
            (m, e.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32)
        };
        self.push_number(m, e);
        #[cfg(test)]
        READ_WHOLE.with(|n| n.set(n.get() + 1));
        Some(i)
    }

    /// `v1 sha256:` and 16 hex digits.
    pub fn finish(mut self) -> String {
        self.end_token();
        self.sha.update(&self.buf);
        let digest = self.sha.finalize();
        let hex: String = digest.iter().take(8).map(|b| format!("{b:02x}")).collect();
        format!("{VERSION} sha256:{hex}")
    }

    /// The tokens a piece of a file adds (its encoded numbers and signs),
    /// read alone: for a piece that starts and ends between tokens (at a
    /// robtarget's `[`), read on any thread and added in file order with
    /// [`NumberPrint::absorb`]. `None` where it ends inside a comment or a
    /// string (the piece is then fed).
    pub fn tokens_of(piece: &[u8]) -> Option<Vec<u8>> {
        // A file of numbers has more bytes of tokens (nine a number)
        // than of text: room for them at once, not grown by copies.
        Self::tokens_into(piece, Vec::with_capacity(piece.len() + piece.len() / 2))
    }

    /// [`NumberPrint::tokens_of`] into `buf` (emptied first): a buffer
    /// used before, whose pages are already the program's.
    pub fn tokens_into(piece: &[u8], mut buf: Vec<u8>) -> Option<Vec<u8>> {
        buf.clear();
        let mut p = NumberPrint {
            sha: Sha256::new(),
            buf,
            state: State::Normal,
            num: Num::default(),
        };
        p.lex(piece);
        if matches!(p.state, State::Comment | State::Str) {
            return None;
        }
        p.end_token();
        Some(p.buf)
    }

    /// Add the tokens of a piece ([`NumberPrint::tokens_of`]) that follows
    /// what was fed, starting with a byte that ends any token but a
    /// comment or a string (a `[`). `false` (nothing added) where what was
    /// fed ends inside a comment or a string: feed the piece instead.
    pub fn absorb(&mut self, tokens: &[u8]) -> bool {
        if matches!(self.state, State::Comment | State::Str) {
            return false;
        }
        // What `[` would do: end the word or number before it.
        self.end_token();
        self.buf.extend_from_slice(tokens);
        self.flush_page();
        true
    }

    fn flush_page(&mut self) {
        if self.buf.len() >= PAGE {
            self.sha.update(&self.buf);
            self.buf.clear();
        }
    }

    fn op(&mut self, b: u8) {
        self.buf.push(if b == b'-' { 2 } else { 3 });
    }

    fn emit_number(&mut self) {
        let (m, e) = self.num.canonical();
        self.push_number(m, e);
        let pending = self.num.pending_sign.take();
        self.num = Num::default();
        if let Some(s) = pending {
            self.op(s);
        }
    }

    /// A number's nine bytes: 1, its six digits, its exponent.
    fn push_number(&mut self, m: u32, e: i32) {
        let mut b = [1u8; 9];
        b[1..5].copy_from_slice(&m.to_le_bytes());
        b[5..].copy_from_slice(&e.to_le_bytes());
        self.buf.extend_from_slice(&b);
    }

    /// The end of the input: a number being read is complete.
    fn end_token(&mut self) {
        match self.state {
            State::Int | State::Frac | State::Exp => self.emit_number(),
            // `1E` or `1E+` at the very end: the number, a word, a sign.
            State::ExpMark => self.emit_number(),
            State::ExpSign => self.emit_number(),
            _ => {}
        }
        self.state = State::Normal;
    }

    fn byte(&mut self, b: u8) {
        match self.state {
            State::Comment => {
                if b == b'\n' || b == b'\r' {
                    self.state = State::Normal;
                }
            }
            State::Str => {
                if b == b'"' {
                    self.state = State::StrQuote;
                }
            }
            State::StrQuote => {
                if b == b'"' {
                    self.state = State::Str;
                } else {
                    self.state = State::Normal;
                    self.byte(b);
                }
            }
            State::Ident => {
                if !is_word(b) {
                    self.state = State::Normal;
                    self.byte(b);
                }
            }
            State::Dot => {
                if b.is_ascii_digit() {
                    self.state = State::Frac;
                    self.num.digit(b, true);
                } else {
                    self.state = State::Normal;
                    self.byte(b);
                }
            }
            State::Int => match b {
                b'0'..=b'9' => self.num.digit(b, false),
                b'.' => self.state = State::Frac,
                b'e' | b'E' => self.state = State::ExpMark,
                _ => self.after_number(b),
            },
            State::Frac => match b {
                b'0'..=b'9' => self.num.digit(b, true),
                b'e' | b'E' => self.state = State::ExpMark,
                _ => self.after_number(b),
            },
            State::ExpMark => match b {
                b'0'..=b'9' => {
                    self.state = State::Exp;
                    self.exp_digit(b);
                }
                b'+' | b'-' => {
                    self.num.exp_neg = b == b'-';
                    self.num.pending_sign = Some(b);
                    self.state = State::ExpSign;
                }
                // `1THEN` read as far as `1E` of `1ELSE`: the number ends
                // before the `E`, which starts a word.
                _ => {
                    self.emit_number();
                    self.state = State::Ident;
                    self.byte(b);
                }
            },
            State::ExpSign => {
                if b.is_ascii_digit() {
                    self.num.pending_sign = None;
                    self.state = State::Exp;
                    self.exp_digit(b);
                } else {
                    // `1E+x`: the number 1, the word E, a sign, then `x`.
                    self.num.exp_neg = false;
                    self.emit_number();
                    self.state = State::Normal;
                    self.byte(b);
                }
            }
            State::Exp => {
                if b.is_ascii_digit() {
                    self.exp_digit(b);
                } else {
                    self.after_number(b);
                }
            }
            State::Normal => match b {
                b'!' => self.state = State::Comment,
                b'"' => self.state = State::Str,
                b'0'..=b'9' => {
                    self.state = State::Int;
                    self.num.digit(b, false);
                }
                b'.' => self.state = State::Dot,
                b'-' | b'+' => self.op(b),
                _ if is_word_start(b) => self.state = State::Ident,
                _ => {}
            },
        }
    }

    fn exp_digit(&mut self, b: u8) {
        // Saturating: an exponent of a thousand digits is still one.
        self.num.exp = self
            .num
            .exp
            .saturating_mul(10)
            .saturating_add(i64::from(b - b'0'))
            .min(1 << 40);
    }

    /// The byte after a number: the number is complete; a letter right
    /// after it starts a word (`1THEN`).
    fn after_number(&mut self, b: u8) {
        self.emit_number();
        self.state = State::Normal;
        self.byte(b);
    }
}

#[cfg(test)]
thread_local! {
    /// How many numbers this thread read whole ([`NumberPrint::number`]).
    static READ_WHOLE: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Powers of ten that pad fewer than six digits to six.
const POW10: [u32; DIGITS + 1] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];

/// Bytes gathered before they are hashed.
const PAGE: usize = 1 << 16;

/// What a byte starts outside any token.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Class {
    Other,
    Digit,
    Word,
    Comment,
    Quote,
    Dot,
    Sign,
}

/// Each byte's [`Class`], looked up rather than worked out per byte.
static CLASS: [Class; 256] = {
    let mut t = [Class::Other; 256];
    let mut b = 0;
    while b < 256 {
        let c = b as u8;
        t[b] = if c.is_ascii_digit() {
            Class::Digit
        } else if c.is_ascii_alphabetic() || c == b'_' || c >= 0x80 {
            Class::Word
        } else if c == b'!' {
            Class::Comment
        } else if c == b'"' {
            Class::Quote
        } else if c == b'.' {
            Class::Dot
        } else if c == b'-' || c == b'+' {
            Class::Sign
        } else {
            Class::Other
        };
        b += 1;
    }
    t
};

fn is_word_start(b: u8) -> bool {
    CLASS[usize::from(b)] == Class::Word
}

fn is_word(b: u8) -> bool {
    matches!(CLASS[usize::from(b)], Class::Word | Class::Digit)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn same(a: &str, b: &str) -> bool {
        NumberPrint::of(a.as_bytes()) == NumberPrint::of(b.as_bytes())
    }

    #[test]
    fn numbers_to_six_digits_and_nothing_else_count() {
        assert!(same("x := 1234.567;", "x := 1234.57;"));
        assert!(same("[9E+09, 9e9]", "[9000000000,9E9]"));
        assert!(same("0.707107", "0.70710678"));
        assert!(same("0.5", ".5"));
        assert!(same("100", "1E2"));
        assert!(same("0", "0.000"));
        assert!(same("p10 := [1,2]; ! 99\r\n", "p11 := [1,2]; ! 98\n"));
        assert!(same("s := \"a 5 \"\" 6\";", "s := \"b\";"));
        assert!(!same("[1,2,3]", "[1,2,4]"));
        assert!(!same("[1,2]", "[1,2,0]"));
        assert!(!same("-1", "1"));
        assert!(!same("1234.56", "1234.58"));
        // The seventh digit rounds, with a carry into the exponent.
        assert!(same("9999995", "10000000"));
        // `1THEN` is the number 1 and a word; `1E+x` the number 1, a word,
        // a sign and a word.
        assert!(same("IF a=1THEN", "IF a=1 THEN"));
        assert!(same("IF a=1ELSE", "IF a=1 ELSE"));
        assert!(same("1E+x", "1 E + x"));
        assert!(!same("1E+5", "1 E + 5"));
    }

    #[test]
    fn pieces_cut_anywhere_give_the_same_fingerprint() {
        let text = b"MODULE M\r\n  ! c 12\r\n  CONST robtarget p:=[[612.345,-0.5,1E+3],[0.707107,0,.5,0],[0,-1,0,0],[9E+09,9E9,9E+09,9E+09,9E+09,9E+09]];\r\n  IF n=1THEN s:=\"a\"\"1\"; ENDIF\r\nENDMODULE\r\n";
        let whole = NumberPrint::of(text);
        for cut in 0..text.len() {
            let mut p = NumberPrint::new();
            p.feed(&text[..cut]);
            p.feed(&text[cut..]);
            assert_eq!(p.finish(), whole, "cut at {cut}");
        }
        let mut p = NumberPrint::new();
        for b in text {
            p.feed(std::slice::from_ref(b));
        }
        assert_eq!(p.finish(), whole);
    }

    #[test]
    fn pieces_read_alone_and_absorbed_give_the_same_fingerprint() {
        let text = b"MODULE M\n  ! c 12\n  MoveL [[612.345,-0.5,1E+3],[1,0,0,0]], v100, z1, t;\n  MoveL [[1,2,3],[0,1,0,0]], v1000\\V:=5, fine, t;\n  s:=\"a[1\"; n:=1E[2];\nENDMODULE\n";
        let whole = NumberPrint::of(text);
        let cuts: Vec<usize> = (0..text.len()).filter(|&i| text[i] == b'[').collect();
        let mut taken = 0;
        for (k, &a) in cuts.iter().enumerate() {
            for &b in &cuts[k..] {
                let mut p = NumberPrint::new();
                p.feed(&text[..a]);
                let absorbed = match NumberPrint::tokens_of(&text[a..b]) {
                    Some(t) => p.absorb(&t),
                    None => false,
                };
                if absorbed {
                    taken += 1;
                } else {
                    p.feed(&text[a..b]);
                }
                p.feed(&text[b..]);
                assert_eq!(p.finish(), whole, "pieces {a}..{b}");
            }
        }
        // The pieces read alone were added, except those that start in the
        // string (`"a[1"`: 2 of the 8 cuts' 36 pairs) or end in it (6).
        assert_eq!((cuts.len(), taken), (8, 36 - 2 - 6));
    }

    /// The numbers read whole (the fast reader) give the tokens the byte
    /// by byte reader gives, on numbers of every form: leading and
    /// trailing zeros, more than seven digits, a seventh digit that
    /// rounds and carries, exponents, `1THEN`.
    #[test]
    fn numbers_read_whole_as_byte_by_byte() {
        let mut text = String::new();
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let forms = [
            "0",
            "00",
            "0.0",
            ".5",
            "0.000123",
            "1234567",
            "9999995",
            "99999949",
            "0.9999995",
            "12.3456789",
            "100",
            "1E5",
            "1e-3",
            "9E+09",
            "2.5E+400000000000",
            "7E",
            "7E+",
            "1THEN",
            "1ELSE",
            "000120.5000",
        ];
        for f in forms {
            text.push_str(f);
            text.push(',');
        }
        for _ in 0..5_000 {
            let r = next();
            let int: String = (0..(r % 9))
                .map(|k| char::from(b'0' + ((r >> (4 + k)) % 10) as u8))
                .collect();
            let frac: String = (0..((r >> 40) % 10))
                .map(|k| char::from(b'0' + ((r >> (8 + k)) % 10) as u8))
                .collect();
            let lead = if r & (1 << 50) != 0 { "000" } else { "" };
            let int = if int.is_empty() && frac.is_empty() {
                "0".to_string()
            } else {
                int
            };
            text.push_str(lead);
            text.push_str(&int);
            if !frac.is_empty() || r & (1 << 51) != 0 {
                text.push('.');
                text.push_str(&frac);
            }
            if r & (3 << 52) == 0 {
                text.push_str(if r & (1 << 54) != 0 { "E-" } else { "E+" });
                text.push_str(&((r >> 56) % 40).to_string());
            }
            text.push_str([",", " ", "]", "\r\n", "-", "+"][(r >> 60) as usize % 6]);
        }
        let bytes = text.as_bytes();
        READ_WHOLE.with(|n| n.set(0));
        let whole = NumberPrint::of(bytes);
        // The whole reading took (nearly) every number: all but those cut
        // by the end of a page.
        assert!(READ_WHOLE.with(std::cell::Cell::get) > 5_000);
        let mut p = NumberPrint::new();
        for b in bytes {
            p.feed(std::slice::from_ref(b));
        }
        assert_eq!(p.finish(), whole);
        let mut t = NumberPrint::new();
        let tokens = NumberPrint::tokens_of(bytes).unwrap();
        assert!(t.absorb(&tokens));
        assert_eq!(t.finish(), whole);
    }

    /// The encoding is pinned: a marked file must read the same in every
    /// later version.
    #[test]
    fn the_encoding_is_pinned() {
        // The bytes the documentation says, written out by hand.
        let mut bytes = Vec::new();
        let num = |bytes: &mut Vec<u8>, m: u32, e: i32| {
            bytes.push(1);
            bytes.extend_from_slice(&m.to_le_bytes());
            bytes.extend_from_slice(&e.to_le_bytes());
        };
        num(&mut bytes, 612_345, 3);
        bytes.push(2);
        num(&mut bytes, 500_000, 0);
        num(&mut bytes, 100_000, 4);
        num(&mut bytes, 100_000, 1);
        for _ in 0..3 {
            num(&mut bytes, 0, 0);
        }
        let digest = Sha256::digest(&bytes);
        let hex: String = digest.iter().take(8).map(|b| format!("{b:02x}")).collect();
        let printed = NumberPrint::of(b"CONST robtarget p:=[[612.345,-0.5,1E+3],[1,0,0,0]];");
        assert_eq!(printed, format!("v1 sha256:{hex}"));
        assert_eq!(printed, "v1 sha256:787c66029705ac4c");
    }
}
