//! The marker a corrected file carries: a RAPID comment under its module
//! header that says it is corrected, by which version, for which moment or
//! schedule, with which model, and the fingerprint (SHA-256) of the cold
//! original it was made from:
//!
//! ```text
//! MODULE Fixtures
//!     ! rapidtherm 0.1.0 corrected: basis=minute 120; model=embedded IRB 140; cold=sha256:5f1c…
//! ```
//!
//! A run asked to split targets moved to with several tools or work
//! objects adds `; shared=split`.
//!
//! The marker proves what it claims with a second line, above the file's
//! last `ENDMODULE`: the fingerprint of the numbers the corrected file
//! holds ([`NumberPrint`], encoding `v1`):
//!
//! ```text
//!     ! rapidtherm numbers v1 sha256:787c66029705ac4c
//! ENDMODULE
//! ```
//!
//! A target re-taught or added after the correction, or a marker pasted
//! into another file, leaves the numbers without a matching fingerprint:
//! such a marker is not trusted ([`untrusted`]).
//!
//! A run on a marked program never corrects it a second time: on the same
//! basis and model there is nothing to do (the file already is what the
//! run would write), on another it is refused, since the numbers in the
//! file are no longer the cold ones the correction starts from.

use crate::error::{Error, Location};
use crate::rapid::numprint::NumberPrint;
use crate::rapid::rewrite::Edit;
use crate::rapid::Program;

const PREFIX: &str = "! rapidtherm ";
const CORRECTED: &str = " corrected: ";
/// The second line's start: the fingerprint of the numbers follows.
const NUMBERS: &str = "! rapidtherm numbers ";

/// What a marker records.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Marker {
    pub version: String,
    /// When the targets were corrected for (`minute 120`, `steady state`,
    /// `schedule sha256:…`).
    pub basis: String,
    /// The model and arm used.
    pub model: String,
    /// `sha256:` and the first 16 hex digits of the cold original's bytes.
    pub cold: String,
    /// The run was asked to split targets moved to with several tools or
    /// work objects (written `shared=split`; absent: each such target
    /// corrected for its first use).
    pub split: bool,
}

/// A marker found in a file, and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Found {
    pub marker: Marker,
    pub file: usize,
    pub line: usize,
}

pub use crate::digest::fingerprint;

impl Marker {
    /// The comment line (without indentation or line end).
    pub fn line(&self) -> String {
        let split = if self.split { "; shared=split" } else { "" };
        format!(
            "{PREFIX}{}{CORRECTED}basis={}; model={}; cold={}{split}",
            self.version, self.basis, self.model, self.cold
        )
    }

    fn parse(comment: &str) -> Option<Marker> {
        let rest = comment.strip_prefix(PREFIX)?;
        let (version, fields) = rest.split_once(CORRECTED)?;
        let mut basis = None;
        let mut model = None;
        let mut cold = None;
        let mut split = false;
        for field in fields.split("; ") {
            match field.split_once('=') {
                Some(("basis", v)) => basis = Some(v.to_string()),
                Some(("model", v)) => model = Some(v.to_string()),
                Some(("cold", v)) => cold = Some(v.trim_end().to_string()),
                Some(("shared", v)) => split = v.trim_end() == "split",
                _ => {}
            }
        }
        Some(Marker {
            version: version.to_string(),
            basis: basis?,
            model: model?,
            cold: cold?,
            split,
        })
    }

    /// The run's marker matches this one: same basis, same model (the
    /// version may differ; the correction it made is the same). Whether
    /// targets were split does not count: a split program is right for
    /// a run without one, and a run asking for a split of a program
    /// corrected without one is told so (it cannot start from corrected
    /// numbers).
    pub fn same_correction(&self, other: &Marker) -> bool {
        self.basis == other.basis && self.model == other.model
    }
}

/// The first marker among the program's files: on the line under a
/// module header, where [`insert`] writes it (so a huge program is not
/// read line by line for it).
pub fn find(program: &Program) -> Option<Found> {
    program.modules.iter().find_map(|module| {
        let src = program.source(module.file);
        let start = header_end(src, module.pos.offset)?;
        let end = crate::error::line_end(src, start);
        let text = String::from_utf8_lossy(&src[start..end]);
        let marker = Marker::parse(text.trim())?;
        let line = 1 + crate::error::breaks_in(src, 0..start);
        Some(Found {
            marker,
            file: module.file,
            line,
        })
    })
}

/// Where the line after a module header (at `offset`) starts (after any
/// line end: LF, CRLF or a lone CR).
fn header_end(src: &[u8], offset: usize) -> Option<usize> {
    src.get(offset..)?;
    crate::error::next_line_start(src, offset)
}

/// The edit inserting `marker` as a new line after the first module
/// header of file `file`, indented like the line after it, with the line
/// end the header uses. `None` when the file has no module.
pub fn insert(program: &Program, file: usize, marker: &Marker) -> Option<Edit> {
    let module = program.modules.iter().find(|m| m.file == file)?;
    let src = program.source(file);
    let (at, eol, lead) = match header_end(src, module.pos.offset) {
        Some(at) => {
            let eol = match &src[..at] {
                [.., b'\r', b'\n'] => "\r\n",
                [.., b'\r'] => "\r",
                _ => "\n",
            };
            (at, eol, "")
        }
        // A module header on the file's last line, without a line end.
        None => (src.len(), "", "\n"),
    };
    let next = &src[at.min(src.len())..];
    let indent: String = next
        .iter()
        .take_while(|&&b| b == b' ' || b == b'\t')
        .map(|&b| b as char)
        .collect();
    let indent = if indent.is_empty() {
        "    ".to_string()
    } else {
        indent
    };
    let new = format!("{lead}{indent}{}{eol}", marker.line());
    Some(Edit {
        span: at..at,
        expected_old: Vec::new(),
        new: new.into_bytes(),
    })
}

/// Where the line holding a file's last `ENDMODULE` starts (the end of
/// the file where it has none): the numbers' line goes there, and the
/// fingerprint covers every number before it.
pub fn numbers_at(src: &[u8]) -> usize {
    let mut end = src.len();
    // Line by line from the end: the last module closes near it.
    loop {
        let start = crate::error::line_start(src, end);
        let line = &src[start..end];
        let text = line.trim_ascii_start();
        if text.len() >= 9 && text[..9].eq_ignore_ascii_case(b"ENDMODULE") {
            return start;
        }
        if start == 0 {
            return src.len();
        }
        end = start - 1;
    }
}

/// The numbers' line (its indentation and line end as the file's
/// marker line has them), for a fingerprint `print`.
pub fn numbers_line(src: &[u8], at: usize, print: &str) -> Vec<u8> {
    let crlf = src.windows(2).any(|w| w == b"\r\n");
    let eol = match (crlf, memchr::memchr(b'\r', src)) {
        (true, _) => "\r\n",
        (false, Some(_)) => "\r",
        (false, None) => "\n",
    };
    // After a last line without a line end, the line starts anew.
    let lead =
        if at == src.len() && !src.is_empty() && !src.ends_with(b"\n") && !src.ends_with(b"\r") {
            eol
        } else {
            ""
        };
    format!("{lead}    {NUMBERS}{print}{eol}").into_bytes()
}

/// The fingerprint the numbers' line of a file records, where it has one:
/// on the line above its last `ENDMODULE`.
fn recorded_numbers(src: &[u8]) -> Option<String> {
    let at = numbers_at(src);
    let start = crate::error::line_start(src, at.saturating_sub(1));
    let line = String::from_utf8_lossy(&src[start..at]);
    line.trim()
        .strip_prefix(NUMBERS)
        .map(|p| p.trim().to_string())
}

/// Why a marker is not trusted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Distrust {
    /// The file has no numbers' line (a marker pasted, or written by a
    /// version before the fingerprint).
    NoFingerprint,
    /// The numbers changed since: a target re-taught, added or removed.
    NumbersChanged { recorded: String, now: String },
}

/// A marked file whose marker is not trusted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Untrusted {
    pub file: usize,
    pub line: usize,
    pub why: Distrust,
}

/// The first marked file of `program` whose numbers do not match its
/// marker's fingerprint (every number of the file, outside comments and
/// strings, before its last `ENDMODULE`).
pub fn untrusted(program: &Program) -> Option<Untrusted> {
    let mut marked: Vec<(usize, usize)> = Vec::new();
    for module in &program.modules {
        if marked.iter().any(|(f, _)| *f == module.file) {
            continue;
        }
        let src = program.source(module.file);
        let Some(start) = header_end(src, module.pos.offset) else {
            continue;
        };
        let end = crate::error::line_end(src, start);
        if Marker::parse(String::from_utf8_lossy(&src[start..end]).trim()).is_some() {
            let line = 1 + crate::error::breaks_in(src, 0..start);
            marked.push((module.file, line));
        }
    }
    marked.into_iter().find_map(|(file, line)| {
        let src = program.source(file);
        let why = match recorded_numbers(src) {
            None => Distrust::NoFingerprint,
            Some(recorded) => {
                let now = NumberPrint::of(&src[..numbers_at(src)]);
                if now == recorded {
                    return None;
                }
                Distrust::NumbersChanged { recorded, now }
            }
        };
        Some(Untrusted { file, line, why })
    })
}

/// The note of a run that takes a file whose marker is not trusted as
/// cold (a check, a report).
pub fn untrusted_note(program: &Program, u: &Untrusted) -> String {
    format!(
        "{} line {}: rapidtherm's marker is not trusted: {}; every target is taken as cold",
        program.files[u.file],
        u.line,
        distrust_words(&u.why)
    )
}

fn distrust_words(why: &Distrust) -> String {
    match why {
        Distrust::NoFingerprint => {
            "it has no fingerprint of its numbers (a marker copied into it, or written before rapidtherm recorded one)".to_string()
        }
        Distrust::NumbersChanged { recorded, now } => format!(
            "its numbers changed since (fingerprint {recorded} recorded, {now} now): a target re-taught, added or removed after the correction"
        ),
    }
}

/// The refusal to correct a file whose marker is not trusted: its numbers
/// cannot be told corrected from cold.
pub fn refuse_untrusted(program: &Program, u: &Untrusted) -> Error {
    let why = distrust_words(&u.why);
    Error::input(format!(
        "rapidtherm's marker says this file is corrected, but {why}; which of its targets are corrected and which are cold cannot be told"
    ))
    .with_note("correct its cold original; or, if every target in it is cold, delete the two `! rapidtherm` lines")
    .at(marker_line(program, u.file, u.line))
}

/// The place of the marker's line `line` of file `file`.
fn marker_line(program: &Program, file: usize, line: usize) -> Location {
    let src = program.source(file);
    let offset = crate::error::start_of_line(src, line);
    Location {
        col: 1,
        ..Location::from_offset(&program.files[file], src, offset)
    }
}

/// The refusal to correct a corrected program on another basis.
pub fn refuse(program: &Program, found: &Found, wanted: &Marker) -> Error {
    let m = &found.marker;
    Error::input(format!(
        "this program was already corrected by rapidtherm {} for {} with {}; correcting it again (for {} with {}) would add a second correction on top of the first",
        m.version, m.basis, m.model, wanted.basis, wanted.model
    ))
    .with_note(format!(
        "correct its cold original instead (fingerprint {})",
        m.cold
    ))
    .at(marker_line(program, found.file, found.line))
}

/// The marker's fields of a run, for a cold file's bytes.
pub fn for_run(basis: &str, model: &str, split: bool, cold: &[u8]) -> Marker {
    for_run_printed(basis, model, split, fingerprint(cold))
}

/// [`for_run`] with the cold file's fingerprint read before
/// ([`crate::digest::fingerprint`]).
pub fn for_run_printed(basis: &str, model: &str, split: bool, cold: String) -> Marker {
    let clean = |s: &str| s.replace(['\n', '\r', ';'], " ");
    Marker {
        version: env!("CARGO_PKG_VERSION").to_string(),
        basis: clean(basis),
        model: clean(model),
        cold,
        split,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_marker_reads_back() {
        let m = for_run(
            "minute 120",
            "embedded IRB 140",
            false,
            b"MODULE A\nENDMODULE\n",
        );
        assert_eq!(Marker::parse(&m.line()), Some(m.clone()));
        let split = for_run(
            "minute 120",
            "embedded IRB 140",
            true,
            b"MODULE A\nENDMODULE\n",
        );
        assert!(split.line().ends_with("; shared=split"));
        assert_eq!(Marker::parse(&split.line()), Some(split.clone()));
        assert!(split.same_correction(&m));
        assert!(m.cold.starts_with("sha256:") && m.cold.len() == 7 + 16);
    }

    #[test]
    fn the_marker_goes_under_the_header_with_its_line_end() {
        let src = b"%%%\r\n  VERSION:1\r\n%%%\r\nMODULE A\r\n  CONST num n := 1;\r\nENDMODULE\r\n";
        let p = crate::rapid::parse("a.mod", src).unwrap();
        let m = for_run("minute 1", "m", false, src);
        let e = insert(&p, 0, &m).unwrap();
        let out = crate::rapid::rewrite::apply_edits("a.mod", src, &[e]).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(
            text.contains(&format!("MODULE A\r\n  {}\r\n  CONST", m.line())),
            "{text}"
        );
        let p2 = crate::rapid::parse("a.mod", text.as_bytes()).unwrap();
        assert_eq!(find(&p2).map(|f| (f.marker, f.line)), Some((m, 5)));
    }
}
