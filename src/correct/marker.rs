//! The marker a corrected file carries: a RAPID comment under its module
//! header that says it is corrected, by which version, for which moment or
//! schedule, with which model and arm, and the fingerprint (SHA-256) of
//! the cold original it was made from:
//!
//! ```text
//! MODULE Fixtures
//!     ! rapidtherm 0.1.0 corrected: basis=minute 120; model=embedded default model, embedded IRB 140 arm; cold=sha256:5f1c…
//! ```
//!
//! A run asked to split targets moved to with several tools or work
//! objects adds `; shared=split`.
//!
//! The marker proves what it claims with a second line, above the file's
//! last `ENDMODULE`: the seal, a fingerprint of the marker's fields and
//! of the numbers the corrected file holds ([`NumberPrint`]), format `v2`:
//!
//! ```text
//!     ! rapidtherm numbers v2 sha256:787c66029705ac4c
//! ENDMODULE
//! ```
//!
//! A target re-taught or added after the correction, a basis or model
//! edited in the marker's text, or a marker pasted into another file,
//! leaves the seal unmatched: such a marker is not trusted
//! ([`untrusted`]).
//!
//! Both lines are recognised wherever they stand in the file and however
//! they are spaced or cased (`!rapidtherm`, `! RAPIDTHERM … CORRECTED :
//! BASIS = …`): every comment whose first word is `rapidtherm` and whose
//! next is `numbers`, or that says `corrected` and gives a field, is one
//! of them. A file with exactly one marker and one seal that matches is
//! corrected; a file with any other mix (a seal without its marker, a
//! marker without its seal, two of either, a marker whose fields cannot
//! be read, a seal of the older format `v1`, which did not cover the
//! marker's fields) is not trusted: never corrected a second time.
//!
//! A run on a marked program never corrects it a second time: on the same
//! basis and model there is nothing to do (the file already is what the
//! run would write), on another it is refused, since the numbers in the
//! file are no longer the cold ones the correction starts from.

use super::marker_fields::canonical;
pub use super::marker_fields::{Basis, BasisKind, MarkerModel, ModelArmKind, ModelUsed};
use crate::error::{Error, Location};
use crate::rapid::numprint::NumberPrint;
use crate::rapid::rewrite::Edit;
use crate::rapid::Program;

const PREFIX: &str = "! rapidtherm ";
const CORRECTED: &str = " corrected: ";
/// The second line's start: the seal follows.
const NUMBERS: &str = "! rapidtherm numbers ";
/// The seal's format: the marker's fields and the numbers (`v1`, before,
/// covered the numbers alone).
pub const SEAL_VERSION: &str = "v2";

/// What a marker records.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Marker {
    pub version: String,
    /// When the targets were corrected for (`minute 120`, `steady state`,
    /// `schedule v1 sha256:…`).
    pub basis: Basis,
    /// The model and arm used.
    pub model: MarkerModel,
    /// `sha256:` and the first 16 hex digits of the cold original's bytes.
    pub cold: String,
    /// The run was asked to split targets moved to with several tools or
    /// work objects (written `shared=split`; absent: each such target
    /// corrected for its first use).
    pub split: bool,
}

/// A marker found in a file, and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FoundMarker {
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

    /// The marker of a comment's text after its `!`, read leniently: any
    /// spacing, any case. `Err` with what is missing where the comment is
    /// rapidtherm's marker but its fields cannot be read.
    fn parse(comment: &str) -> Result<Marker, String> {
        let lower = comment.to_ascii_lowercase();
        let trimmed = lower.trim_start();
        let rest = trimmed
            .strip_prefix('!')
            .unwrap_or(trimmed)
            .trim_start()
            .strip_prefix("rapidtherm")
            .ok_or("it does not start with `rapidtherm`")?;
        let at = rest
            .find("corrected")
            .ok_or("it does not say `corrected`")?;
        // The original's case of the values, at the same places (ASCII
        // folding keeps every byte where it was).
        let offset = comment.len() - rest.len();
        let version = canonical(&comment[offset..offset + at]);
        let fields = comment[offset + at + "corrected".len()..].trim_start();
        let fields = fields.strip_prefix(':').unwrap_or(fields);
        let (mut basis, mut model, mut cold, mut split) = (None, None, None, false);
        for field in fields.split(';') {
            let Some((key, value)) = field.split_once('=') else {
                if !field.trim().is_empty() {
                    return Err(format!("`{}` is not a field (key=value)", excerpt(field)));
                }
                continue;
            };
            let value = value.split_ascii_whitespace().collect::<Vec<_>>().join(" ");
            let slot = match canonical(key).as_str() {
                "basis" => &mut basis,
                "model" => &mut model,
                "cold" => &mut cold,
                "shared" => {
                    split = canonical(&value) == "split";
                    continue;
                }
                other => return Err(format!("its field `{}` is unknown", excerpt(other))),
            };
            if slot.replace(value).is_some() {
                return Err(format!("its field `{}` is given twice", canonical(key)));
            }
        }
        let need = |v: Option<String>, name: &str| v.ok_or(format!("it has no `{name}=`"));
        Ok(Marker {
            version,
            basis: Basis::parse(&need(basis, "basis")?),
            model: MarkerModel::parse(&need(model, "model")?),
            cold: need(cold, "cold")?,
            split,
        })
    }

    /// The run's marker matches this one: same basis, same model (the
    /// version may differ; the correction it made is the same; case and
    /// spacing do not count). Whether targets were split does not count:
    /// a split program is right for a run without one, and a run asking
    /// for a split of a program corrected without one is told so (it
    /// cannot start from corrected numbers).
    pub fn same_correction(&self, other: &Marker) -> bool {
        self.basis.same(&other.basis) && self.model.same(&other.model)
    }

    /// The seal of this marker over a file's numbers (`print`, the
    /// [`NumberPrint`] of everything before the file's last `ENDMODULE`):
    /// `v2 sha256:` and 16 hex digits of the SHA-256 of
    /// `rapidtherm seal 2\0`, then each of version, basis, model, cold
    /// ([`canonical`]) and `split` or `first`, and `print`, each as its
    /// length (u32, little-endian) and its bytes. Documented in
    /// docs/correct.md; a test pins it.
    pub fn seal(&self, print: &str) -> String {
        let mut b = b"rapidtherm seal 2\0".to_vec();
        let split = if self.split { "split" } else { "first" };
        let fields = [
            canonical(&self.version),
            self.basis.canonical(),
            self.model.canonical(),
            canonical(&self.cold),
            split.to_string(),
            print.to_string(),
        ];
        for f in &fields {
            b.extend_from_slice(&(f.len() as u32).to_le_bytes());
            b.extend_from_slice(f.as_bytes());
        }
        format!("{SEAL_VERSION} {}", fingerprint(&b))
    }
}

/// At most a few dozen characters of a field, for a message.
fn excerpt(s: &str) -> String {
    let s = s.trim();
    match s.char_indices().nth(40) {
        Some((at, _)) => format!("{}…", &s[..at]),
        None => s.to_string(),
    }
}

/// One of rapidtherm's lines as a file holds it.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Line {
    /// A marker, read or not.
    Marker(Result<Marker, String>),
    /// A seal: its format's version and its fingerprint (both lower case).
    Seal { version: String, print: String },
}

/// rapidtherm's lines of a file: (the line's number, from 1; the line).
fn lines_of(src: &[u8]) -> Vec<(usize, Line)> {
    own_lines(src).into_iter().map(|(n, _, l)| (n, l)).collect()
}

/// The byte spans of rapidtherm's own lines of a file (its marker and
/// its seal, each line with its line end): what a rewrite added, and
/// what giving the cold original back takes out.
pub fn own_line_spans(src: &[u8]) -> Vec<std::ops::Range<usize>> {
    own_lines(src).into_iter().map(|(_, r, _)| r).collect()
}

/// rapidtherm's lines of a file: each one's number, span (its line end
/// included) and what it is.
fn own_lines(src: &[u8]) -> Vec<(usize, std::ops::Range<usize>, Line)> {
    let mut out = Vec::new();
    let mut done_line = usize::MAX;
    let mut counted = (0, 1);
    for bang in memchr::memchr_iter(b'!', src) {
        // Lines end at LF, CRLF or a lone CR (crate::error's one rule).
        let start = crate::error::line_start(src, bang);
        if start == done_line {
            continue;
        }
        done_line = start;
        let end = crate::error::line_end(src, bang);
        let Some(comment) = comment_of(&src[start..end]) else {
            continue;
        };
        let text = String::from_utf8_lossy(comment);
        let Some(line) = classify(&text) else {
            continue;
        };
        // Line numbers counted on from the last found: one pass in all.
        let (from, n) = counted;
        let n = n + crate::error::breaks_in(src, from..start);
        counted = (start, n);
        let next = crate::error::next_line_start(src, end).unwrap_or(src.len());
        out.push((n, start..next, line));
    }
    out
}

/// The comment of a line (after its `!`), outside strings (RAPID strings
/// end on their line; `""` inside one is a quote, which toggling twice
/// keeps).
fn comment_of(line: &[u8]) -> Option<&[u8]> {
    let mut in_string = false;
    for (i, &b) in line.iter().enumerate() {
        match b {
            b'"' => in_string = !in_string,
            b'!' if !in_string => return Some(&line[i + 1..]),
            _ => {}
        }
    }
    None
}

/// Whether a comment's text (after its `!`) is one of rapidtherm's lines:
/// its first word `rapidtherm` (any case, any spacing), then `numbers`
/// (a seal) or a text that says `corrected` and gives a field (`=`: a
/// marker). Other comments naming rapidtherm are a person's notes.
fn classify(text: &str) -> Option<Line> {
    let lower = text.trim().to_ascii_lowercase();
    let rest = lower.strip_prefix("rapidtherm")?;
    if rest.starts_with(|c: char| c.is_ascii_alphanumeric()) {
        return None;
    }
    let words: Vec<&str> = rest.split_ascii_whitespace().collect();
    if words.first() == Some(&"numbers") {
        // `v2 sha256:…`, however spaced (`sha256 : …`).
        let version = words.get(1).map_or(String::new(), |v| v.to_string());
        let print: String = words.get(2..).unwrap_or_default().concat();
        return Some(Line::Seal { version, print });
    }
    // A marker says it is corrected and gives a field: a note such as
    // `! rapidtherm corrected this by hand` is a person's.
    if rest.contains("corrected") && rest.contains('=') {
        return Some(Line::Marker(Marker::parse(text)));
    }
    None
}

/// The first marker among the program's files (the first of its file
/// where it has several), its fields read.
pub fn find(program: &Program) -> Option<FoundMarker> {
    (0..program.files.len()).find_map(|file| {
        lines_of(program.source(file))
            .into_iter()
            .find_map(|(line, l)| match l {
                Line::Marker(Ok(marker)) => Some(FoundMarker { marker, file, line }),
                _ => None,
            })
    })
}

/// The cold original's fingerprint the first marker of a file records.
pub fn cold_fingerprint(src: &[u8]) -> Option<String> {
    lines_of(src).into_iter().find_map(|(_, l)| match l {
        Line::Marker(Ok(m)) => Some(m.cold),
        _ => None,
    })
}

/// Whether each file of the program holds any of rapidtherm's lines.
pub fn marked_files(program: &Program) -> Vec<bool> {
    (0..program.files.len())
        .map(|f| !lines_of(program.source(f)).is_empty())
        .collect()
}

/// Where the line after a module header (at `offset`) starts.
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
/// the file where it has none): the seal's line goes there, and the
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

/// The seal's line (its indentation and line end as the file's marker
/// line has them), for a seal `seal` ([`Marker::seal`]).
pub fn numbers_line(src: &[u8], at: usize, seal: &str) -> Vec<u8> {
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
    format!("{lead}    {NUMBERS}{seal}{eol}").into_bytes()
}

/// Why a marker is not trusted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Distrust {
    /// The file has a marker but no seal (a marker pasted, or written by
    /// a version before the fingerprint).
    NoFingerprint,
    /// The file has a seal but no marker (the marker deleted after the
    /// correction: its numbers are corrected all the same).
    NoMarker,
    /// Two markers or two seals (lines): a file corrected twice, or a
    /// corrected part pasted into another.
    Twice {
        what: &'static str,
        lines: (usize, usize),
    },
    /// The marker's fields cannot be read.
    Unreadable(String),
    /// A seal of another format: `v1` (the numbers alone, not the
    /// marker's fields) or one this version does not know.
    OtherFormat(String),
    /// The numbers or the marker's fields changed since: a target
    /// re-taught, added or removed, a basis or a model edited.
    NumbersChanged { recorded: String, now: String },
}

/// A marked file whose marker is not trusted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Untrusted {
    pub file: usize,
    pub line: usize,
    pub why: Distrust,
}

/// Whether file `file`'s rapidtherm lines make a trusted marker: `None`
/// for a file without any or with one marker and its matching seal.
fn file_distrust(src: &[u8], file: usize) -> Option<Untrusted> {
    let lines = lines_of(src);
    let first = lines.first()?.0;
    let at = |line, why| Some(Untrusted { file, line, why });
    let markers: Vec<(usize, &Result<Marker, String>)> = lines
        .iter()
        .filter_map(|(n, l)| match l {
            Line::Marker(m) => Some((*n, m)),
            Line::Seal { .. } => None,
        })
        .collect();
    let seals: Vec<(usize, &str, &str)> = lines
        .iter()
        .filter_map(|(n, l)| match l {
            Line::Seal { version, print } => Some((*n, version.as_str(), print.as_str())),
            Line::Marker(_) => None,
        })
        .collect();
    if let [(a, _), (b, _), ..] = markers[..] {
        return at(
            a,
            Distrust::Twice {
                what: "markers",
                lines: (a, b),
            },
        );
    }
    if let [(a, ..), (b, ..), ..] = seals[..] {
        return at(
            a,
            Distrust::Twice {
                what: "seals (`rapidtherm numbers` lines)",
                lines: (a, b),
            },
        );
    }
    let Some(&(line, marker)) = markers.first() else {
        return at(first, Distrust::NoMarker);
    };
    let marker = match marker {
        Ok(m) => m,
        Err(why) => return at(line, Distrust::Unreadable(why.clone())),
    };
    let Some(&(_, version, recorded)) = seals.first() else {
        return at(line, Distrust::NoFingerprint);
    };
    if version != SEAL_VERSION {
        return at(line, Distrust::OtherFormat(excerpt(version)));
    }
    let now = marker.seal(&NumberPrint::of(&src[..numbers_at(src)]));
    let recorded = format!("{version} {recorded}");
    if now == recorded {
        return None;
    }
    at(line, Distrust::NumbersChanged { recorded, now })
}

/// The first file of `program` with rapidtherm's lines that do not make
/// a trusted marker: a seal that does not match the marker's fields and
/// the numbers (every number of the file, outside comments and strings,
/// before its last `ENDMODULE`), or any other mix ([`Distrust`]).
pub fn untrusted(program: &Program) -> Option<Untrusted> {
    (0..program.files.len()).find_map(|f| file_distrust(program.source(f), f))
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
            "it has no seal of its numbers (a marker copied into it, or written before rapidtherm recorded one)".to_string()
        }
        Distrust::NoMarker => {
            "it holds rapidtherm's seal of corrected numbers (`rapidtherm numbers`) without its marker (the marker deleted after the correction)".to_string()
        }
        Distrust::Twice { what, lines: (a, b) } => format!(
            "it holds two {what}, on lines {a} and {b} (corrected twice, or a corrected part pasted into it)"
        ),
        Distrust::Unreadable(why) => format!("its marker cannot be read: {why}"),
        Distrust::OtherFormat(v) if v == "v1" => {
            "its seal is of the format v1, written by rapidtherm before the seal covered the marker's basis, model and arm, so what the marker says cannot be checked: make the correction again from the cold original".to_string()
        }
        Distrust::OtherFormat(v) => format!(
            "its seal is of a format this version does not know (`{v}`; this version writes {SEAL_VERSION})"
        ),
        Distrust::NumbersChanged { recorded, now } => format!(
            "its numbers or its marker's text changed since (seal {recorded} recorded, {now} now): a target re-taught, added or removed, or the marker's basis or model edited, after the correction"
        ),
    }
}

/// The refusal to correct a file whose marker is not trusted: its numbers
/// cannot be told corrected from cold.
pub fn refuse_untrusted(program: &Program, u: &Untrusted) -> Error {
    let why = distrust_words(&u.why);
    Error::input(format!(
        "rapidtherm's lines say this file is corrected, but {why}; which of its targets are corrected and which are cold cannot be told"
    ))
    .with_note("correct its cold original; or, if every target in it is cold, delete every `! rapidtherm` line")
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
pub fn refuse(program: &Program, found: &FoundMarker, wanted: &Marker) -> Error {
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
        basis: Basis::parse(&clean(basis)),
        model: MarkerModel::parse(&clean(model)),
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
        assert_eq!(Marker::parse(&m.line()), Ok(m.clone()));
        let split = for_run(
            "minute 120",
            "embedded IRB 140",
            true,
            b"MODULE A\nENDMODULE\n",
        );
        assert!(split.line().ends_with("; shared=split"));
        assert_eq!(Marker::parse(&split.line()), Ok(split.clone()));
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

    // Before, `!rapidtherm` or upper case was no marker: the file was
    // corrected a second time.
    #[test]
    fn a_marker_is_read_however_spaced_or_cased() {
        let want = Marker {
            version: "0.1.0".into(),
            basis: "minute 120".into(),
            model: "embedded IRB 140".into(),
            cold: "sha256:0123456789abcdef".into(),
            split: false,
        };
        for text in [
            "! rapidtherm 0.1.0 corrected: basis=minute 120; model=embedded IRB 140; cold=sha256:0123456789abcdef",
            "!rapidtherm 0.1.0 corrected: basis=minute 120; model=embedded IRB 140; cold=sha256:0123456789abcdef",
            "!  RAPIDTHERM  0.1.0  CORRECTED : BASIS = minute  120 ;MODEL=embedded IRB 140;cold = sha256:0123456789abcdef ",
            "!\trapidtherm 0.1.0 Corrected:basis=minute 120;model=embedded IRB 140;cold=sha256:0123456789abcdef",
        ] {
            let Some(Line::Marker(Ok(m))) = classify(&text[1..]) else {
                panic!("not read: {text}");
            };
            assert!(m.same_correction(&want), "{text}: {m:?}");
            assert_eq!(m.seal("v1 sha256:00"), want.seal("v1 sha256:00"), "{text}");
        }
        // A seal however spaced.
        assert_eq!(
            classify(" RapidTherm  NUMBERS v2 SHA256 : ab12"),
            Some(Line::Seal {
                version: "v2".into(),
                print: "sha256:ab12".into()
            })
        );
        // A person's note is neither.
        assert_eq!(classify(" rapidtherm was run on this file by hand"), None);
        assert_eq!(classify(" rapidthermal notes"), None);
        assert_eq!(classify(" rapidtherm corrected this by hand"), None);
        // A marker that says it is corrected but cannot be read.
        assert!(matches!(
            classify(" rapidtherm corrected: basis=minute 60"),
            Some(Line::Marker(Err(_)))
        ));
    }

    // The seal's bytes, as docs/correct.md writes them down.
    #[test]
    fn the_seal_is_pinned() {
        let m = Marker {
            version: "0.1.0".into(),
            basis: "Minute  120".into(),
            model: "m".into(),
            cold: "sha256:00".into(),
            split: true,
        };
        let mut b = b"rapidtherm seal 2\0".to_vec();
        for f in [
            "0.1.0",
            "minute 120",
            "m",
            "sha256:00",
            "split",
            "v1 sha256:ff",
        ] {
            b.extend_from_slice(&(f.len() as u32).to_le_bytes());
            b.extend_from_slice(f.as_bytes());
        }
        assert_eq!(m.seal("v1 sha256:ff"), format!("v2 {}", fingerprint(&b)));
        let other = Marker {
            basis: "minute 60".into(),
            ..m.clone()
        };
        assert_ne!(other.seal("v1 sha256:ff"), m.seal("v1 sha256:ff"));
    }
}
