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
        for &b in bytes {
            self.byte(b);
        }
        if self.buf.len() >= PAGE {
            self.sha.update(&self.buf);
            self.buf.clear();
        }
    }

    /// `v1 sha256:` and 16 hex digits.
    pub fn finish(mut self) -> String {
        self.end_token();
        self.sha.update(&self.buf);
        let digest = self.sha.finalize();
        let hex: String = digest.iter().take(8).map(|b| format!("{b:02x}")).collect();
        format!("{VERSION} sha256:{hex}")
    }

    fn op(&mut self, b: u8) {
        self.buf.push(if b == b'-' { 2 } else { 3 });
    }

    fn emit_number(&mut self) {
        let (m, e) = self.num.canonical();
        self.buf.push(1);
        self.buf.extend_from_slice(&m.to_le_bytes());
        self.buf.extend_from_slice(&e.to_le_bytes());
        let pending = self.num.pending_sign.take();
        self.num = Num::default();
        if let Some(s) = pending {
            self.op(s);
        }
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

/// Bytes gathered before they are hashed.
const PAGE: usize = 1 << 16;

fn is_word_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_' || b >= 0x80
}

fn is_word(b: u8) -> bool {
    is_word_start(b) || b.is_ascii_digit()
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
