//! Places in a file: where its lines start, and a byte's column.

use super::values::Pos;

/// Where each line of `src` starts (after each `\n`, `\r\n` or lone
/// `\r`: see [`crate::error::ends_line`]): found a megabyte at a time on every
/// core, then gathered into a list made at its full size (a file of two
/// million lines took a tenth of a second on one core, its list growing
/// by copies).
pub(crate) fn line_starts(src: &[u8]) -> Vec<usize> {
    use rayon::prelude::*;
    const PIECE: usize = 1 << 20;
    let pieces: Vec<Vec<usize>> = src
        .par_chunks(PIECE)
        .enumerate()
        .map(|(k, piece)| {
            let at = k * PIECE;
            memchr::memchr2_iter(b'\n', b'\r', piece)
                .filter(|&i| crate::error::ends_line(src, at + i))
                .map(|i| at + i + 1)
                .collect()
        })
        .collect();
    let mut v = Vec::with_capacity(1 + pieces.iter().map(Vec::len).sum::<usize>());
    v.push(0);
    for p in &pieces {
        v.extend_from_slice(p);
    }
    v
}

/// The place of `offset` in `src`, whose lines start at `lines`.
pub(crate) fn pos_of(src: &[u8], lines: &[usize], offset: usize) -> Pos {
    let offset = offset.min(src.len());
    let line = lines.partition_point(|&s| s <= offset).max(1);
    let start = lines.get(line - 1).copied().unwrap_or(0);
    Pos {
        offset,
        line: line as u32,
        col: column(&src[start..offset]),
    }
}

/// The place of `offset` in `src`, on line `line` (its column counted
/// from the line's start).
pub(crate) fn pos_on(src: &[u8], offset: usize, line: u32) -> Pos {
    let start = crate::error::line_start(src, offset);
    Pos {
        offset,
        line,
        col: column(&src[start..offset]),
    }
}

/// The 1-based column after `prefix`, the line up to a place: characters
/// where it is UTF-8, bytes otherwise.
pub(crate) fn column(prefix: &[u8]) -> u32 {
    let n = match std::str::from_utf8(prefix) {
        Ok(s) => s.chars().count(),
        Err(_) => prefix.len(),
    };
    1 + n as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lines of a file of several pieces, cut anywhere (a CRLF across
    /// a piece's end), as one scan finds them.
    #[test]
    fn line_starts_across_pieces() {
        let mut text = Vec::new();
        let mut k = 0usize;
        while text.len() < 3 * (1 << 20) + 17 {
            text.extend_from_slice(b"MoveL p;");
            text.extend(std::iter::repeat_n(b'x', k % 97));
            text.extend_from_slice(if k.is_multiple_of(3) { b"\n" } else { b"\r\n" });
            k += 1;
        }
        let mut one = vec![0];
        one.extend(
            text.iter()
                .enumerate()
                .filter(|(_, &b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
        assert_eq!(line_starts(&text), one);
        assert_eq!(line_starts(b""), vec![0]);
        assert_eq!(line_starts(b"a\nb"), vec![0, 2]);
        // A lone `\r` ends a line too; `\r\n` once.
        assert_eq!(line_starts(b"a\rb\r\nc\n\rd"), vec![0, 2, 5, 7, 8]);
        // A `\r\n` across two pieces of a megabyte.
        let mut cut = vec![b'x'; (1 << 20) - 1];
        cut.extend_from_slice(b"\r\ny\rz");
        assert_eq!(line_starts(&cut), vec![0, (1 << 20) + 1, (1 << 20) + 3]);
    }
}
