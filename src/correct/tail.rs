//! A corrected file's tail, after its last target: its bytes straight
//! from the file with the edits there, the numbers of large tails read on
//! every core.

use super::printed::Printed;
use super::splice::{write_error, Splice};
use crate::error::Result;
use crate::rapid::numprint::NumberPrint;
use crate::rapid::rewrite::Edit;
use std::borrow::Cow;

/// A piece of a file's tail: its bytes (the file's own where no edit
/// falls in it) and their tokens for the fingerprint.
type Piece<'s> = (Cow<'s, [u8]>, Option<Vec<u8>>);

/// How much of a file's tail is read for the fingerprint at a time.
const TAIL_PIECE: usize = 1 << 20;

/// After the last target, the file's bytes from `from` to `end` with the
/// edits there, straight from the file: a RobotStudio export's million
/// moves by name. Cut after line ends into pieces whose numbers are read
/// on every core (a line end ends any token but a string, which
/// [`NumberPrint::absorb`] refuses: such a piece is read in order) and
/// written in order; the first piece, which may continue the last
/// target's token, and any piece an edit crosses into, in order. How
/// many pieces were read on every core.
pub(super) fn write_tail(
    src: &[u8],
    (from, end): (usize, usize),
    fixed: &[Edit],
    out: &mut Printed,
) -> Result<usize> {
    use rayon::prelude::*;
    let edits: Vec<&Edit> = fixed.iter().filter(|e| e.span.start >= from).collect();
    let mut cuts = vec![from];
    let mut at = from;
    while end - at > TAIL_PIECE {
        // A line's start (after LF, CRLF or a lone CR) is no token's middle.
        let Some(cut) = crate::error::next_line_start(src, at + TAIL_PIECE).filter(|&c| c <= end)
        else {
            break;
        };
        // The edit starting last before the cut must end by it.
        let before = edits.partition_point(|e| e.span.start < cut);
        if cut >= end || before > 0 && edits[before - 1].span.end > cut {
            break;
        }
        cuts.push(cut);
        at = cut;
    }
    cuts.push(end);
    let piece = |a: usize, b: usize| -> Result<Piece> {
        let (lo, hi) = (
            edits.partition_point(|e| e.span.start < a),
            edits.partition_point(|e| e.span.start < b),
        );
        let bytes = match lo == hi {
            true => Cow::Borrowed(&src[a..b]),
            false => {
                let mut v = Vec::with_capacity(b - a + (b - a) / 64);
                let mut splice = Splice {
                    src,
                    at: a,
                    out: &mut v,
                };
                splice.finish_at(&mut edits[lo..hi].iter().copied().peekable(), b)?;
                Cow::Owned(v)
            }
        };
        let tokens = NumberPrint::tokens_of(&bytes);
        Ok((bytes, tokens))
    };
    // The first piece through the writer that reads as it writes.
    let first_end = cuts[1];
    let mut first = edits
        .iter()
        .copied()
        .take_while(|e| e.span.start < first_end)
        .peekable();
    Splice { src, at: from, out }.finish_at(&mut first, first_end)?;
    let pieces: Vec<(usize, usize)> = cuts[1..].windows(2).map(|w| (w[0], w[1])).collect();
    let mut taken = 0;
    for batch in pieces.chunks(4 * rayon::current_num_threads()) {
        let done: Vec<Result<_>> = batch.par_iter().map(|&(a, b)| piece(a, b)).collect();
        for d in done {
            let (bytes, tokens) = d?;
            taken += usize::from(out.chunk(&bytes, tokens.as_deref()).map_err(write_error)?);
        }
    }
    Ok(taken)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tail of five pieces, with comments, strings (holding a `[` and
    /// a quote) and numbers, edits in its first piece and in a later one:
    /// the bytes are the file's with the edits, the fingerprint is the
    /// whole text's read in order, and the pieces after the first were
    /// read on the cores, but the two a string runs across (left open in
    /// the third piece, closed in the fourth), read in order.
    #[test]
    fn a_long_tail_is_read_in_pieces_as_in_order() {
        let mut src = b"MODULE M\r\n  CONST robtarget p:=[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\r\n".to_vec();
        let from = src.len() - 2;
        let mut k = 0;
        let mut line = |src: &mut Vec<u8>, strings: bool| {
            let l = match k % 4 {
                0 => format!("  MoveL Target_{k},v1000,z1,tool1\\WObj:=wobj1;\r\n"),
                1 if strings => format!("  WaitTime 0.{k}; ! {k}.5 mm \"\r\n"),
                1 => format!("  WaitTime 0.{k}; ! {k}.5 mm\r\n"),
                2 if strings => format!("  TPWrite \"a[{k} \"\"{k}\"\" 1E3\";\r\n"),
                _ => format!("  n:=-{k}E-2+1THEN;\r\n"),
            };
            src.extend_from_slice(l.as_bytes());
            k += 1;
        };
        let mib = TAIL_PIECE;
        while src.len() < 2 * mib + mib / 2 {
            let strings = src.len() < mib + mib / 2;
            line(&mut src, strings);
        }
        src.extend_from_slice(b"  s:=\"open\r\n");
        while src.len() < 3 * mib + mib / 2 {
            line(&mut src, false);
        }
        src.extend_from_slice(b"  closed\";\r\n");
        while src.len() < 5 * mib - 1000 {
            line(&mut src, true);
        }
        src.extend_from_slice(b"ENDMODULE\r\n");
        let end = src.len() - b"ENDMODULE\r\n".len();
        let edit = |at: usize, len: usize, new: &[u8]| Edit {
            span: at..at + len,
            expected_old: src[at..at + len].to_vec(),
            new: new.to_vec(),
        };
        let later = 4 * mib + 5000;
        let later = later + memchr::memchr(b'\n', &src[later..]).unwrap() + 1;
        let fixed = vec![edit(from + 40, 3, b"12345"), edit(later, 2, b" ")];
        let mut want = src[from..end].to_vec();
        for e in fixed.iter().rev() {
            let (a, b) = (e.span.start - from, e.span.end - from);
            want.splice(a..b, e.new.iter().copied());
        }
        let mut written = Vec::new();
        let mut printed = Printed {
            out: &mut written,
            print: NumberPrint::new(),
            held: Vec::new(),
        };
        let taken = write_tail(&src, (from, end), &fixed, &mut printed).unwrap();
        let Printed {
            mut print, held, ..
        } = printed;
        print.feed(&held);
        assert_eq!(written, want);
        assert_eq!(print.finish(), NumberPrint::of(&want));
        assert_eq!(taken, 2);
    }
}
