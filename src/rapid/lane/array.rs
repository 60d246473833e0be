//! The literals of a large robtarget array read on every core. A
//! generator's one array of a million elements is one statement, and
//! read one literal after another it was most of the time the parse of
//! such a file took on one core while the others waited.
//!
//! The value is cut into pieces at element starts found by their form
//! alone, each piece read as the whole would read it, and the pieces
//! taken only where each ends exactly where the next begins: then every
//! literal was read from the place the reading in order would have read
//! it from, and so read the same. Anything else gives `None`, and the
//! caller reads the value in order (which also finds where it fails).

use super::cursor::{Cursor, Seen};
use rayon::prelude::*;

/// Values shorter than this are read in order: cutting them costs more
/// than it saves.
const PARALLEL_BYTES: usize = 1 << 20;

/// The literals of an array's value whose `[` is just before `from`:
/// each literal's `[`, and where the value's `]` is. `None` where the
/// value is short, or is not read whole this way.
pub(crate) fn elements(src: &[u8], from: usize) -> Option<(Vec<usize>, usize)> {
    // The lane reads no comment and no string, so where it reads the
    // declaration at all, its first `;` ends it.
    let end = from + memchr::memchr(b';', src.get(from..)?)?;
    if end - from < PARALLEL_BYTES {
        return None;
    }
    let pieces = 4 * rayon::current_num_threads().max(1);
    let step = (end - from) / pieces;
    let mut starts = vec![from];
    for k in 1..pieces {
        let Some(s) = element_start(src, from + k * step, end) else {
            break;
        };
        if s > *starts.last()? {
            starts.push(s);
        }
    }
    let read: Vec<Option<(Vec<usize>, Option<usize>)>> = (0..starts.len())
        .into_par_iter()
        .map(|k| piece(src, starts[k], starts.get(k + 1).copied()))
        .collect();
    let mut all = Vec::new();
    let mut close = None;
    for r in read {
        let (found, end) = r?;
        all.extend(found);
        close = end;
    }
    Some((all, close?))
}

/// The first literal's `[` at or after `p` (before `end`) that is an
/// element's by its form: a `,` before it and a `[` after it, blanks
/// and line ends aside. Inside a robtarget literal, a `[` after a `,`
/// opens a group of numbers, so a `[` follows none.
fn element_start(src: &[u8], mut p: usize, end: usize) -> Option<usize> {
    let blank = |b: &u8| matches!(b, b' ' | b'\t' | b'\r' | b'\n');
    while p < end {
        let q = p + memchr::memchr(b'[', &src[p..end])?;
        let before = src[..q].iter().rev().find(|b| !blank(b));
        let after = src[q + 1..end].iter().find(|b| !blank(b));
        if before == Some(&b',') && after == Some(&b'[') {
            return Some(q);
        }
        p = q + 1;
    }
    None
}

/// The literals from `p` on, read as the value in order reads them: up
/// to the literal at `stop` (`None` where a separator does not lead to
/// it exactly), or to the value's `]` where `stop` is `None` (and where
/// that `]` is).
fn piece(src: &[u8], p: usize, stop: Option<usize>) -> Option<(Vec<usize>, Option<usize>)> {
    let mut seen = Seen::default();
    let mut c = Cursor::form(src, p, &mut seen);
    c.lines = true;
    let mut found = Vec::new();
    loop {
        found.push(c.literal()?);
        c.blank();
        match (c.s.get(c.p), stop) {
            (Some(b','), Some(stop)) => {
                c.p += 1;
                c.blank();
                if c.p == stop {
                    return Some((found, None));
                }
                if c.p > stop {
                    return None;
                }
            }
            (Some(b','), None) => c.p += 1,
            (Some(b']'), None) => return Some((found, Some(c.p))),
            _ => return None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An array value of `n` literals as a generator writes it, from
    /// just after its `[`, lines ended by `eol`.
    fn value(n: usize, eol: &str) -> String {
        let mut s = String::from("CONST robtarget pScan{N} := [");
        for k in 0..n {
            if k > 0 {
                s.push(',');
                s.push_str(eol);
            }
            s.push_str(&format!(
                "[[{}.5,-{k},.25e1],[1,0,0,0],[0,-1,0,1],[9E+09,9E9,9E9,9E9,9E9,9E9]]",
                k % 977
            ));
        }
        s.push_str("];");
        s
    }

    /// The value read in order, as the lane did before.
    fn in_order(src: &[u8], from: usize) -> Option<(Vec<usize>, usize)> {
        let mut seen = Seen::default();
        let mut c = Cursor::form(src, from, &mut seen);
        c.lines = true;
        let mut found = Vec::new();
        loop {
            found.push(c.literal()?);
            c.blank();
            match c.s.get(c.p) {
                Some(b',') => c.p += 1,
                Some(b']') => return Some((found, c.p)),
                _ => return None,
            }
        }
    }

    #[test]
    fn a_large_value_is_read_in_pieces_as_in_order() {
        for eol in ["\r\n", "\n", " ", "\r\n  \t"] {
            let s = value(30_000, eol);
            let from = s.find(":= [").unwrap() + 4;
            let whole = in_order(s.as_bytes(), from).unwrap();
            // The pieces were taken (not the reading in order).
            let pieces = elements(s.as_bytes(), from).expect("read in pieces");
            assert_eq!(pieces, whole);
            assert_eq!(pieces.0.len(), 30_000);
        }
    }

    #[test]
    fn a_value_not_read_whole_in_pieces_is_left_to_the_reading_in_order() {
        let good = value(30_000, "\n");
        let from = good.find(":= [").unwrap() + 4;
        // A literal broken in the middle, a separator missing, a value
        // ended early, and a short value.
        let broken = good.replacen("[[345.5,-15000,", "[[345.5,-15000;", 1);
        let joined = good.replacen("]],\n[[460.5,-20000", "]]\n[[460.5,-20000", 1);
        let early = good.replacen("]],\n[[575.5,-25000", "]]],\n[[575.5,-25000", 1);
        for bad in [&broken, &joined, &early] {
            assert_ne!(bad, &good);
            assert_eq!(elements(bad.as_bytes(), from), None);
        }
        // In order, the first two fail; the third ends the value early
        // (and the declaration then fails at its `;`).
        assert_eq!(in_order(broken.as_bytes(), from), None);
        assert_eq!(in_order(joined.as_bytes(), from), None);
        assert_eq!(
            in_order(early.as_bytes(), from).map(|r| r.0.len()),
            Some(25_000)
        );
        let short = value(100, "\n");
        assert_eq!(elements(short.as_bytes(), from), None);
        assert!(in_order(short.as_bytes(), from).is_some());
    }
}
