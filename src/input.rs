//! Reading an input whole, bounded: a regular file is read at its size;
//! anything else (standard input, a pipe, a device such as `/dev/zero`)
//! has no size to trust, so at most [`MAX_STREAM_BYTES`] are read and a
//! longer stream is refused rather than filling the memory.

use crate::error::{Error, ErrorKind, Result};
use std::io::Read;
use std::path::Path;

/// The most bytes read from a stream: a gibibyte, eight times the largest
/// program the benchmarks correct (a million targets, 117 MB). See
/// docs/limits.md.
pub const MAX_STREAM_BYTES: u64 = 1 << 30;

/// The bytes of the file at `path`, bounded as the module says.
pub fn read_path(path: &Path) -> Result<Vec<u8>> {
    let io = |e: std::io::Error| Error::io(path, &e);
    let file = std::fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if meta.is_dir() {
        return Err(Error::new(
            ErrorKind::Io,
            format!("{}: is a folder, not a file", path.display()),
        ));
    }
    if meta.is_file() {
        let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
        (&file).read_to_end(&mut bytes).map_err(io)?;
        return Ok(bytes);
    }
    read_stream(file, &path.display().to_string())
}

/// Standard input, bounded as a stream.
pub fn read_stdin() -> Result<Vec<u8>> {
    read_stream(std::io::stdin().lock(), "<stdin>")
}

/// At most [`MAX_STREAM_BYTES`] of `reader`; more is an error naming
/// `name`.
pub fn read_stream(reader: impl Read, name: &str) -> Result<Vec<u8>> {
    read_at_most(reader, name, MAX_STREAM_BYTES)
}

fn read_at_most(reader: impl Read, name: &str, max: u64) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    reader
        .take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(Path::new(name), &e))?;
    if bytes.len() as u64 > max {
        return Err(Error::new(
            ErrorKind::Io,
            format!(
                "{name}: more than {} from a stream without an end in sight; save it to a file first if it is really this large",
                size(max)
            ),
        ));
    }
    Ok(bytes)
}

/// A text encoding rapidtherm does not read, as a file's first bytes give
/// it away: a byte-order mark, or (UTF-16 saved without one) a NUL beside
/// every ASCII character.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unread {
    Utf16Le,
    Utf16Be,
    Utf32Le,
    Utf32Be,
}

impl Unread {
    /// Its name, as messages give it.
    pub fn name(self) -> &'static str {
        match self {
            Unread::Utf16Le => "UTF-16 (little-endian)",
            Unread::Utf16Be => "UTF-16 (big-endian)",
            Unread::Utf32Le => "UTF-32 (little-endian)",
            Unread::Utf32Be => "UTF-32 (big-endian)",
        }
    }
}

/// The encoding `bytes` are in, where it is one that is not read (the
/// readers take UTF-8, with or without its byte-order mark, or Latin-1:
/// every byte of either is the file's own, so offsets stay exact).
pub fn unread_encoding(bytes: &[u8]) -> Option<Unread> {
    match bytes {
        [0xFF, 0xFE, 0, 0, ..] => Some(Unread::Utf32Le),
        [0, 0, 0xFE, 0xFF, ..] => Some(Unread::Utf32Be),
        [0xFF, 0xFE, ..] => Some(Unread::Utf16Le),
        [0xFE, 0xFF, ..] => Some(Unread::Utf16Be),
        // No mark: text whose first two characters are ASCII, each beside
        // a NUL. No RAPID, XML or CSV text starts with a NUL.
        [a, 0, b, 0, ..] if *a != 0 && a.is_ascii() && *b != 0 && b.is_ascii() => {
            Some(Unread::Utf16Le)
        }
        [0, a, 0, b, ..] if *a != 0 && a.is_ascii() && *b != 0 && b.is_ascii() => {
            Some(Unread::Utf16Be)
        }
        _ => None,
    }
}

/// An input error at the start of the file `name` when its `bytes` are in
/// an encoding that is not read, naming it and what to save it as
/// (`save_as`: "UTF-8 or ISO-8859-1 (Latin-1)").
pub fn refuse_unread_encoding(name: &str, bytes: &[u8], save_as: &str) -> Result<()> {
    match unread_encoding(bytes) {
        None => Ok(()),
        Some(e) => Err(Error::input(format!(
            "{} is not read; save the file as {save_as}",
            e.name()
        ))
        .at(crate::error::Location {
            file: name.to_string(),
            line: 1,
            col: 1,
            line_text: Box::default(),
        })),
    }
}

/// A byte count in words: `1024 MiB`, `100 bytes`.
fn size(n: u64) -> String {
    if n >= 1 << 20 {
        format!("{} MiB", n >> 20)
    } else {
        format!("{n} bytes")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_endless_stream_is_refused_at_the_bound() {
        let e = read_stream(std::io::repeat(0).take(MAX_STREAM_BYTES + 10), "zeros").unwrap_err();
        assert!(
            e.message.contains("zeros: more than 1024 MiB"),
            "{}",
            e.message
        );
        let ok = read_stream(&b"MODULE m\nENDMODULE\n"[..], "short").unwrap();
        assert_eq!(ok.len(), 19);
    }

    #[test]
    fn utf16_and_utf32_are_named_with_or_without_their_mark() {
        let utf16le: Vec<u8> = "\u{FEFF}MODULE m"
            .encode_utf16()
            .flat_map(u16::to_le_bytes)
            .collect();
        assert_eq!(utf16le[..3], [0xFF, 0xFE, b'M']);
        assert_eq!(unread_encoding(&utf16le), Some(Unread::Utf16Le));
        assert_eq!(unread_encoding(&utf16le[2..]), Some(Unread::Utf16Le));
        let utf16be: Vec<u8> = "\u{FEFF}MODULE m"
            .encode_utf16()
            .flat_map(u16::to_be_bytes)
            .collect();
        assert_eq!(unread_encoding(&utf16be), Some(Unread::Utf16Be));
        assert_eq!(unread_encoding(&utf16be[2..]), Some(Unread::Utf16Be));
        assert_eq!(
            unread_encoding(&[0xFF, 0xFE, 0, 0, b'M', 0, 0, 0]),
            Some(Unread::Utf32Le)
        );
        assert_eq!(
            unread_encoding(&[0, 0, 0xFE, 0xFF, 0, 0, 0, b'M']),
            Some(Unread::Utf32Be)
        );
        // UTF-8 with and without its mark, Latin-1, empty: read.
        for ok in [
            &b"\xEF\xBB\xBFMODULE m"[..],
            b"MODULE m",
            b"! \xe9t\xe9\nMODULE m",
            b"",
            b"M",
        ] {
            assert_eq!(unread_encoding(ok), None, "{ok:?}");
        }
        let e = refuse_unread_encoding("a.mod", &utf16le, "UTF-8").unwrap_err();
        assert_eq!(
            e.to_string(),
            "a.mod:1:1: error: UTF-16 (little-endian) is not read; save the file as UTF-8"
        );
    }
}
