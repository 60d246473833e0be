//! The touch-up block: RAPID comment lines a correction is to write above
//! its seal, one entry per corrected target, so that a target re-taught
//! after the correction (a ModPos on the pendant) is named alone and the
//! cold program can be given back byte for byte.
//!
//! An entry records the target's name (with `#n` where it is the n-th
//! declaration of that name in the file, n > 1), a fingerprint of its
//! value as the correction wrote it (the literal `[[…],…]`, its bytes),
//! and its value as the cold original wrote it, its bytes exactly:
//!
//! ```text
//!     ! rapidtherm target p10 warm=sha256:0123456789abcdef
//!     ! rapidtherm cold [[500,0,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+
//!     ! rapidtherm cold 09,9E+09,9E+09,9E+09]]
//! ```
//!
//! Each line stays within [`LINE_MAX`] characters (RAPID's editors and
//! controllers keep comments of that length through load and save); the
//! cold value is cut over as many `cold` lines as it takes and read back
//! by joining them. Bytes outside printable ASCII, and `\`, are written
//! `\xHH`: a literal written over several lines, or a Latin-1 comment
//! inside it, comes back as it was.
//!
//! This file holds the block's format and the giving back of the cold
//! bytes over spans already found; where the spans are found (the
//! program's declarations) and when the block is written belong to the
//! correction's writer.

use crate::digest::fingerprint;
use std::ops::Range;

/// The most characters a block line holds, its indentation included
/// (80 is safe on every RAPID editor and controller).
pub const LINE_MAX: usize = 80;

/// The indentation the block's lines are written with.
const INDENT: &str = "    ";
const TARGET: &str = "! rapidtherm target ";
const COLD: &str = "! rapidtherm cold ";

/// One corrected target as the block records it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// The target's name, `#n` added for the n-th declaration (n > 1) of
    /// that name in its file.
    pub name: String,
    /// `sha256:` and 16 hex digits of its value's bytes as written warm.
    pub warm: String,
    /// Its value's bytes as the cold original wrote them.
    pub cold: Vec<u8>,
}

impl Entry {
    /// The entry of a target named `name`, written `warm` by the
    /// correction from `cold`.
    pub fn new(name: &str, warm: &[u8], cold: &[u8]) -> Entry {
        Entry {
            name: name.to_string(),
            warm: fingerprint(warm),
            cold: cold.to_vec(),
        }
    }

    /// Whether a value as the file now holds it is the one the correction
    /// wrote (else the target was touched since).
    pub fn untouched(&self, now: &[u8]) -> bool {
        fingerprint(now) == self.warm
    }

    /// The entry's lines, without indentation or line ends.
    fn lines(&self) -> Vec<String> {
        let mut out = vec![format!("{TARGET}{} warm={}", self.name, self.warm)];
        let room = LINE_MAX - INDENT.len() - COLD.len();
        let mut line = String::new();
        for piece in self.cold.iter().map(|&b| escaped(b)) {
            if line.len() + piece.len() > room {
                out.push(format!("{COLD}{}", std::mem::take(&mut line)));
            }
            line.push_str(&piece);
        }
        out.push(format!("{COLD}{line}"));
        out
    }
}

/// A byte as the block writes it.
fn escaped(b: u8) -> String {
    match b {
        b'\\' => "\\x5c".to_string(),
        0x20..=0x7e => (b as char).to_string(),
        _ => format!("\\x{b:02x}"),
    }
}

/// The block's text for `entries`, each line indented and ended by `eol`.
pub fn block_text(entries: &[Entry], eol: &str) -> Vec<u8> {
    let mut out = String::new();
    for line in entries.iter().flat_map(Entry::lines) {
        out.push_str(INDENT);
        out.push_str(&line);
        out.push_str(eol);
    }
    out.into_bytes()
}

/// Why a block cannot be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BadBlock {
    /// A `cold` line before any `target` line (line, from 1).
    ColdFirst(usize),
    /// A `target` line without `name warm=sha256:…` (line).
    Target(usize),
    /// A `\x` not followed by two hex digits (line).
    Escape(usize),
}

/// The entries of a file's block, read from its comment lines (each with
/// its number, from 1, and its text after `!`); lines that are not the
/// block's are passed over.
pub fn read_block<'a>(
    comments: impl Iterator<Item = (usize, &'a str)>,
) -> Result<Vec<Entry>, BadBlock> {
    let mut out: Vec<Entry> = Vec::new();
    for (n, text) in comments {
        let text = text.trim_start();
        let Some(rest) = text.strip_prefix("rapidtherm ") else {
            continue;
        };
        if let Some(cold) = rest.strip_prefix("cold ") {
            let entry = out.last_mut().ok_or(BadBlock::ColdFirst(n))?;
            unescape(cold.trim_end_matches(['\r', '\n']), &mut entry.cold)
                .ok_or(BadBlock::Escape(n))?;
        } else if let Some(target) = rest.strip_prefix("target ") {
            let (name, warm) = target
                .trim()
                .split_once(" warm=")
                .ok_or(BadBlock::Target(n))?;
            if name.is_empty() || !warm.starts_with("sha256:") {
                return Err(BadBlock::Target(n));
            }
            out.push(Entry {
                name: name.to_string(),
                warm: warm.trim().to_string(),
                cold: Vec::new(),
            });
        }
    }
    Ok(out)
}

/// A `cold` line's text back to its bytes, added to `out`.
fn unescape(text: &str, out: &mut Vec<u8>) -> Option<()> {
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'\\' {
            let hex = text.get(i + 2..i + 4)?;
            if bytes.get(i + 1) != Some(&b'x') {
                return None;
            }
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 4;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    Some(())
}

/// A file's bytes with each span of `values` (ascending, apart) given its
/// cold bytes back, and the spans of `drop` (rapidtherm's own lines,
/// ascending, apart from the values) taken out.
pub fn give_back(src: &[u8], values: &[(Range<usize>, &[u8])], drop: &[Range<usize>]) -> Vec<u8> {
    let mut cuts: Vec<(Range<usize>, &[u8])> = values.to_vec();
    cuts.extend(drop.iter().map(|r| (r.clone(), &b""[..])));
    cuts.sort_by_key(|(r, _)| r.start);
    let mut out = Vec::with_capacity(src.len());
    let mut at = 0;
    for (r, new) in cuts {
        if r.start < at || r.end > src.len() {
            continue;
        }
        out.extend_from_slice(&src[at..r.start]);
        out.extend_from_slice(new);
        at = r.end;
    }
    out.extend_from_slice(&src[at..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The comment texts (after `!`) of a block's bytes, numbered.
    fn comments(text: &str) -> Vec<(usize, String)> {
        text.lines()
            .enumerate()
            .filter_map(|(i, l)| Some((i + 1, l.split_once('!')?.1.to_string())))
            .collect()
    }

    #[test]
    fn an_entry_reads_back_byte_for_byte_within_the_line_limit() {
        let cold = b"[[500,0,400],[0,0,1,0],[0,0,0,0],\r\n\t\t[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]] ! caf\xe9 \\ end";
        let e = Entry::new("p10#2", b"[[501.2,0,400],[0,0,1,0]]", cold);
        let text = String::from_utf8(block_text(std::slice::from_ref(&e), "\n")).unwrap();
        assert!(text.lines().count() >= 3, "{text}");
        for line in text.lines() {
            assert!(line.len() <= LINE_MAX, "{line:?}");
        }
        let c = comments(&text);
        let read = read_block(c.iter().map(|(n, t)| (*n, t.as_str()))).unwrap();
        assert_eq!(read, vec![e.clone()]);
        assert!(read[0].untouched(b"[[501.2,0,400],[0,0,1,0]]"));
        assert!(!read[0].untouched(b"[[501.3,0,400],[0,0,1,0]]"));
    }

    #[test]
    fn a_block_out_of_order_or_broken_is_said() {
        let read = |t: &[(usize, &str)]| read_block(t.iter().copied());
        assert_eq!(
            read(&[(4, " rapidtherm cold [1]")]),
            Err(BadBlock::ColdFirst(4))
        );
        assert_eq!(
            read(&[(2, " rapidtherm target p10")]),
            Err(BadBlock::Target(2))
        );
        assert_eq!(
            read(&[
                (1, " rapidtherm target p warm=sha256:00"),
                (2, " rapidtherm cold [\\xZZ]")
            ]),
            Err(BadBlock::Escape(2))
        );
        // Other comments, the marker and the seal among them, pass.
        assert_eq!(
            read(&[(1, " rapidtherm numbers v2 sha256:00"), (2, " a note")]),
            Ok(Vec::new())
        );
    }

    #[test]
    fn the_cold_bytes_are_given_back_and_own_lines_taken_out() {
        let warm = b"MODULE m\n  ! mark\n  CONST robtarget p:=[[2]];\n  CONST robtarget q:=[[5]];\nENDMODULE\n";
        let s = std::str::from_utf8(warm).unwrap();
        let p = s.find("[[2]]").unwrap();
        let q = s.find("[[5]]").unwrap();
        let mark = s.find("  ! mark").unwrap();
        let own_lines = std::iter::once(mark..mark + 9).collect::<Vec<_>>();
        let out = give_back(
            warm,
            &[(p..p + 5, &b"[[1.0]]"[..]), (q..q + 5, &b"[[4]]"[..])],
            &own_lines,
        );
        assert_eq!(
            out,
            b"MODULE m\n  CONST robtarget p:=[[1.0]];\n  CONST robtarget q:=[[4]];\nENDMODULE\n"
        );
    }
}
