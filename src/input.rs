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
}
