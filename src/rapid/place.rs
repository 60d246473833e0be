//! Places in a file: where its lines start, and a byte's column.

use super::values::Pos;

/// Where each line of `src` starts.
pub(crate) fn line_starts(src: &[u8]) -> Vec<usize> {
    let mut v = vec![0];
    v.extend(memchr::memchr_iter(b'\n', src).map(|i| i + 1));
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
    let start = memchr::memrchr(b'\n', &src[..offset]).map_or(0, |i| i + 1);
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
