//! One error type for the whole library: every failure is a value with a
//! kind (which decides the exit code in the CLI), a message, and, for bad
//! input, the file, line and column it concerns.
//!
//! The bottom of the library: imports nothing of it. Messages say what is
//! wrong in the terms of the data; the CLI alone names its flags.

use std::fmt;
use std::path::Path;

/// What went wrong, coarsely: the CLI maps this to an exit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The input text is not valid RAPID.
    Syntax,
    /// A data file (CSV, TOML, URDF) is malformed or inconsistent.
    Input,
    /// The file system refused a read or write.
    Io,
    /// A target cannot be reached by the robot (with its robconf).
    Unreachable,
    /// The input asks for something the tool does not model (and says so
    /// rather than computing something silently wrong).
    Unsupported,
    /// An iterative computation (fit, Newton) did not converge.
    NoConvergence,
    /// Invalid combination of arguments or model settings.
    Usage,
}

/// A place in a source file. `line` and `col` are 1-based; `col` counts
/// characters (Latin-1 bytes count as one character each).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line: usize,
    pub col: usize,
    /// The text of the offending line, without its line terminator, for the
    /// caret display. Empty when unknown.
    pub line_text: String,
}

impl Location {
    /// Location of byte `offset` in `src` (any encoding: UTF-8 where valid,
    /// otherwise each byte is one Latin-1 character).
    pub fn from_offset(file: &str, src: &[u8], offset: usize) -> Location {
        let offset = offset.min(src.len());
        let line_start = src[..offset]
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1);
        let line_end = src[offset..]
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .map_or(src.len(), |p| offset + p);
        let line = 1 + src[..line_start].iter().filter(|&&b| b == b'\n').count();
        let col = 1 + decode_lossless(&src[line_start..offset]).chars().count();
        Location {
            file: file.to_string(),
            line,
            col,
            line_text: decode_lossless(&src[line_start..line_end]),
        }
    }
}

/// Bytes as text for display: UTF-8 when valid, otherwise Latin-1 (every
/// byte maps to one character, so nothing is lost or replaced).
pub fn decode_lossless(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    pub kind: ErrorKind,
    pub message: String,
    pub location: Option<Location>,
    /// Extra lines shown after the caret (for example what was expected).
    pub notes: Vec<String>,
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error {
            kind,
            message: message.into(),
            location: None,
            notes: Vec::new(),
        }
    }

    pub fn at(mut self, location: Location) -> Error {
        self.location = Some(location);
        self
    }

    pub fn with_note(mut self, note: impl Into<String>) -> Error {
        self.notes.push(note.into());
        self
    }

    pub fn input(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Input, message)
    }

    pub fn usage(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::Usage, message)
    }

    pub fn io(path: &Path, err: &std::io::Error) -> Error {
        Error::new(ErrorKind::Io, format!("{}: {}", path.display(), err))
    }

    /// An input error at a line and column of a file, without source text.
    pub fn input_at(file: &str, line: usize, col: usize, message: impl Into<String>) -> Error {
        Error::input(message).at(Location {
            file: file.to_string(),
            line,
            col,
            line_text: String::new(),
        })
    }
}

impl fmt::Display for Error {
    /// `file:line:col: error: message`, then the line and a caret under the
    /// column, then notes: the layout of rustc and most compilers, which
    /// editors turn into clickable locations.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(loc) => {
                write!(
                    f,
                    "{}:{}:{}: error: {}",
                    loc.file, loc.line, loc.col, self.message
                )?;
                if !loc.line_text.is_empty() {
                    let gutter = loc.line.to_string().len();
                    write!(f, "\n{:gutter$} |", "")?;
                    write!(f, "\n{} | {}", loc.line, loc.line_text)?;
                    let pad: String = loc
                        .line_text
                        .chars()
                        .take(loc.col.saturating_sub(1))
                        .map(|c| if c == '\t' { '\t' } else { ' ' })
                        .collect();
                    write!(f, "\n{:gutter$} | {}^", "", pad)?;
                }
            }
            None => write!(f, "error: {}", self.message)?,
        }
        for note in &self.notes {
            write!(f, "\n  = {note}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Error {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn location_counts_lines_and_latin1_columns() {
        let src = b"MODULE m\r\n  ! \xe9t\xe9\r\n  x := 1;\n";
        let off = src.iter().position(|&b| b == b'x').unwrap();
        let loc = Location::from_offset("a.mod", src, off);
        assert_eq!((loc.line, loc.col), (3, 3));
        let off = src.iter().position(|&b| b == b't').unwrap();
        let loc = Location::from_offset("a.mod", src, off);
        assert_eq!((loc.line, loc.col), (2, 6));
        assert_eq!(loc.line_text, "  ! été");
    }

    #[test]
    fn display_has_caret_under_column() {
        let src = b"abc def\n";
        let e = Error::input("bad word").at(Location::from_offset("f", src, 4));
        assert_eq!(
            e.to_string(),
            "f:1:5: error: bad word\n  |\n1 | abc def\n  |     ^"
        );
    }
}
