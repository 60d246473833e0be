//! One error type for the whole library: every failure is a value with a
//! kind (which decides the exit code in the CLI), a message, and, for bad
//! input, the file, line and column it concerns.
//!
//! The bottom of the library: imports nothing of it. Messages say what is
//! wrong in the terms of the data; the CLI alone names its flags.

use std::fmt;
use std::path::Path;

/// What went wrong, coarsely: the CLI maps this to an exit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
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

/// What the user can do about an error. The library names the remedy; the
/// CLI words it with its own flags (the library never names a flag), and
/// [`Error`]'s `Display` words it without them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Remedy {
    /// Several procedures could be the entry of the program's walk: name
    /// one.
    ChooseEntry,
    /// The program cannot be walked to a schedule: give the schedule of the
    /// real run.
    GiveSchedule,
    /// A schedule lacks a target: give a time for the targets it does not
    /// list.
    GiveDefaultTime,
    /// A model without a steady state: give a minute of the warm-up.
    GiveMinute,
    /// A polynomial heating curve has no steady state: fit a saturating one,
    /// or give a minute.
    FitSaturatingOrGiveMinute,
    /// A minute outside a heating recording: fit a saturating model to it.
    FitBeyondRecording,
    /// A name not in the catalogue of ABB arms: see the list.
    ListArms,
    /// A task's arm is not known from the backup: name it for the task.
    NameTheArm,
    /// A pose the arm used cannot reach (reach or joint limits): a program
    /// for another arm names that arm.
    AnotherArm,
    /// An arm whose thermal behaviour is unknown: give a model file of it,
    /// or use the IRB 140's thermal defaults on its lengths.
    ModelOfTheArm,
    /// An arm said besides a model fitted on another: leave it to the
    /// model.
    ArmOfTheModel,
    /// Tasks that would write one file differently: one at a time.
    OneTaskAtATime,
    /// A backup that does not place a task's robot: mend it, or accept the
    /// default placement (the world origin) explicitly.
    AcceptDefaultPlacement,
    /// A file the user did not name would be replaced: move it away, or
    /// replace it explicitly.
    Force,
}

impl Remedy {
    /// The remedy in the library's own words (no flags), for `Display`.
    pub fn describe(self) -> &'static str {
        match self {
            Remedy::ChooseEntry => " (choose the entry routine)",
            Remedy::GiveSchedule => ": give the schedule of the run instead",
            Remedy::GiveDefaultTime => " (add it, or give a default time)",
            Remedy::GiveMinute => ": give a minute of the warm-up",
            Remedy::FitSaturatingOrGiveMinute => {
                ": fit a saturating model (first-order, two-tau) or give a minute of the warm-up"
            }
            Remedy::FitBeyondRecording => {
                "; fit a saturating model to predict beyond it, or hold the end values explicitly"
            }
            Remedy::ListArms => " (the catalogue lists every name)",
            Remedy::NameTheArm => "; name the arm this task moves",
            Remedy::AnotherArm => "; a program for another arm: name that arm",
            Remedy::ModelOfTheArm => {
                "give a model file of this arm (its heating measured, or a heating recording in it), or use the IRB 140's thermal defaults on this arm's lengths"
            }
            Remedy::ArmOfTheModel => {
                "give a model diagnosed on this arm, or leave the arm to the model"
            }
            Remedy::OneTaskAtATime => "",
            Remedy::AcceptDefaultPlacement => {
                "; mend the backup, or accept the default placement (the world origin) explicitly"
            }
            Remedy::Force => ": move it away, or ask for it to be replaced",
        }
    }
}

/// A place in a source file. `line` and `col` are 1-based; `col` counts
/// characters (Latin-1 bytes count as one character each).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line: usize,
    pub col: usize,
    /// The text of the offending line, without its line terminator, for the
    /// caret display. Empty when unknown. (A `Box<str>`, not a `String`:
    /// the 8 bytes saved pay for [`Error::related`].)
    pub line_text: Box<str>,
}

impl Location {
    /// Location of byte `offset` in `src` (any encoding: UTF-8 where valid,
    /// otherwise each byte is one Latin-1 character).
    pub fn from_offset(file: &str, src: &[u8], offset: usize) -> Location {
        let offset = offset.min(src.len());
        let line_start = line_start(src, offset);
        let line_end = line_end(src, offset);
        let line = 1 + breaks_in(src, 0..line_start);
        let col = 1 + decode_lossless(&src[line_start..offset]).chars().count();
        Location {
            file: file.to_string(),
            line,
            col,
            line_text: decode_lossless(&src[line_start..line_end]).into(),
        }
    }
}

// Line breaks, one rule for every reader and writer: `\r\n`, `\n`, or a
// `\r` alone (the classic Mac OS line end, which some editors still
// write) each end a line. A break is counted at its last byte, so that a
// `\r\n` cut between two ranges counts once; offsets stay those of the
// file's own bytes.

/// Whether the byte at `i` of `src` ends a line (an `\n`, or a `\r` not
/// followed by `\n`).
pub fn ends_line(src: &[u8], i: usize) -> bool {
    match src.get(i) {
        Some(b'\n') => true,
        Some(b'\r') => src.get(i + 1) != Some(&b'\n'),
        _ => false,
    }
}

/// How many line breaks end in `range` of `src`.
pub fn breaks_in(src: &[u8], range: std::ops::Range<usize>) -> usize {
    let (from, to) = (range.start.min(src.len()), range.end.min(src.len()));
    memchr::memchr2_iter(b'\n', b'\r', &src[from..to])
        .filter(|&i| ends_line(src, from + i))
        .count()
}

/// Where the line holding byte `at` starts (the line a break's bytes
/// end).
pub fn line_start(src: &[u8], at: usize) -> usize {
    let mut end = at.min(src.len());
    // A break's own bytes belong to the line it ends.
    if end > 0 && src[end - 1] == b'\r' && src.get(end) == Some(&b'\n') {
        end -= 1;
    }
    memchr::memrchr2(b'\n', b'\r', &src[..end]).map_or(0, |i| i + 1)
}

/// Where the line holding byte `at` ends: at its break's first byte, or
/// the end of `src`.
pub fn line_end(src: &[u8], at: usize) -> usize {
    let at = at.min(src.len());
    memchr::memchr2(b'\n', b'\r', &src[at..]).map_or(src.len(), |i| at + i)
}

/// Where the line after the one holding byte `at` starts; `None` on the
/// last line (no break after it).
pub fn next_line_start(src: &[u8], at: usize) -> Option<usize> {
    let end = line_end(src, at);
    match src.get(end)? {
        b'\r' if src.get(end + 1) == Some(&b'\n') => Some(end + 2),
        _ => Some(end + 1),
    }
}

/// Where 1-based line `line` of `src` starts (the end of `src` past its
/// last line).
pub fn start_of_line(src: &[u8], line: usize) -> usize {
    let mut at = 0;
    for _ in 1..line {
        match next_line_start(src, at) {
            Some(next) => at = next,
            None => return src.len(),
        }
    }
    at
}

/// The lines of `text`, each without its break (as [`str::lines`], which
/// knows `\n` and `\r\n` only, with a lone `\r` ending a line too).
pub fn split_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let t = rest?;
        match next_line_start(t.as_bytes(), 0) {
            Some(next) => {
                rest = (next < t.len()).then(|| &t[next..]);
                Some(&t[..line_end(t.as_bytes(), 0)])
            }
            None => {
                rest = None;
                (!t.is_empty()).then_some(t)
            }
        }
    })
}

/// The line break a file uses (its first), for lines written into it:
/// `\n` where it has none.
pub fn line_break_of(src: &[u8]) -> &'static str {
    match memchr::memchr2(b'\n', b'\r', src) {
        Some(i) if src[i] == b'\r' && src.get(i + 1) == Some(&b'\n') => "\r\n",
        Some(i) if src[i] == b'\r' => "\r",
        _ => "\n",
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

/// What an error is about, where it is one thing of the input: a target
/// of the program by its identifier. Kept apart from the message (which
/// says why), so that the errors of one cause about many targets are told
/// apart by their cause, never by taking their text apart.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Subject {
    Target(String),
    JointTarget(String),
}

impl fmt::Display for Subject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Subject::Target(id) => write!(f, "target {id}"),
            Subject::JointTarget(id) => write!(f, "jointtarget {id}"),
        }
    }
}

/// The longest source line an error shows whole; a longer one (a
/// generated program may hold a megabyte on one line) is cut to
/// [`SHOWN_AROUND`] characters on each side of the column.
pub const SHOWN_WHOLE: usize = 240;

/// See [`SHOWN_WHOLE`].
pub const SHOWN_AROUND: usize = 80;

/// A character as an error message shows it: itself, or an escape when it
/// would be invisible or move the terminal (`\0`, `\u{FEFF}`). Tabs stay
/// tabs, so that the caret lines up under them.
pub fn visible_char(c: char, out: &mut String) {
    match c {
        '\t' => out.push('\t'),
        '\0' => out.push_str("\\0"),
        c if c.is_control()
            || matches!(c, '\u{FEFF}' | '\u{200B}'..='\u{200F}' | '\u{2028}'..='\u{202E}' | '\u{2060}'..='\u{2064}') =>
        {
            out.push_str(&format!("\\u{{{:X}}}", c as u32));
        }
        c => out.push(c),
    }
}

/// Text as an error message shows it (see [`visible_char`]).
pub fn visible(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    text.chars().for_each(|c| visible_char(c, &mut out));
    out
}

/// The most characters of the input a message quotes: a name, a number, a
/// value. A longer one (a number of ten megabytes) is cut, and its length
/// said, so that a message stays a line whatever the input.
pub const QUOTED_AT_MOST: usize = 40;

/// Input as a message quotes it, in backticks: whole up to
/// [`QUOTED_AT_MOST`] characters, else its start, `…` and how long it is;
/// invisible characters made visible (see [`visible_char`]). Every message
/// that echoes input goes through here.
pub fn quoted(text: &str) -> String {
    let mut out = String::from("`");
    let mut chars = text.chars();
    chars
        .by_ref()
        .take(QUOTED_AT_MOST)
        .for_each(|c| visible_char(c, &mut out));
    if chars.next().is_some() {
        out.push_str(&format!("…` ({} characters)", text.chars().count()));
    } else {
        out.push('`');
    }
    out
}

/// The part of `line` an error shows around 1-based column `col`, with
/// invisible characters made visible and `…` where it was cut; and the
/// shown text before the column (the caret goes after it).
fn shown_line(line: &str, col: usize) -> (String, String) {
    let chars: Vec<char> = line.chars().collect();
    let at = col.saturating_sub(1).min(chars.len());
    let (from, to) = if chars.len() <= SHOWN_WHOLE {
        (0, chars.len())
    } else {
        (
            at.saturating_sub(SHOWN_AROUND),
            (at + SHOWN_AROUND).min(chars.len()),
        )
    };
    let mut before = String::new();
    if from > 0 {
        before.push('…');
    }
    chars[from..at]
        .iter()
        .for_each(|&c| visible_char(c, &mut before));
    let mut shown = before.clone();
    chars[at..to]
        .iter()
        .for_each(|&c| visible_char(c, &mut shown));
    if to < chars.len() {
        shown.push('…');
    }
    (shown, before)
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    pub kind: ErrorKind,
    /// Why it is an error (the cause), without what it is about.
    pub message: String,
    /// What it is about, where it is a target: said before the message.
    pub subject: Option<Box<Subject>>,
    pub location: Option<Box<Location>>,
    /// Extra lines shown after the caret (for example what was expected).
    pub notes: Vec<String>,
    /// What the user can do, and the line it completes: the message
    /// (`None`) or the note of that index. (Small on purpose: every
    /// `Result` of the library carries an `Error`'s size.)
    pub remedy: Option<(Remedy, Option<u16>)>,
    /// Further errors of the same run, each with its own place: a run
    /// reports every error it can find (up to [`MAX_RELATED`], gathered by
    /// [`Errors`]) in one `Error`, and [`Error::render`] shows each after
    /// this one as its own `file:line:col: error: ...` block. `None` for
    /// most errors; boxed so that it costs one pointer (see
    /// [`Error::with_related`], [`Error::related`]).
    pub related: Option<Box<Vec<Error>>>,
}

/// How many errors of one run are listed in one [`Error`] (as its
/// [`Error::related`], see [`Errors`]); the count of the rest goes in a
/// note.
pub const MAX_RELATED: usize = 20;

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error {
            kind,
            message: message.into(),
            subject: None,
            location: None,
            notes: Vec::new(),
            remedy: None,
            related: None,
        }
    }

    /// The error is about `subject`.
    pub fn about(mut self, subject: Subject) -> Error {
        self.subject = Some(Box::new(subject));
        self
    }

    /// What it is about and why, as one line: `target p20: unknown tool`.
    pub fn headline(&self) -> String {
        match &self.subject {
            Some(s) => format!("{s}: {}", self.message),
            None => self.message.clone(),
        }
    }

    /// Add an error found beside this one (see [`Error::related`]).
    pub fn with_related(mut self, e: Error) -> Error {
        self.related.get_or_insert_with(Box::default).push(e);
        self
    }

    /// All errors of a run as one: the first, with the others (up to
    /// [`MAX_RELATED`], then a note counting the rest) related to it.
    /// `None` when there are none.
    pub fn many(errors: Vec<Error>) -> Option<Error> {
        let total = errors.len();
        let mut it = errors.into_iter();
        let mut first = it.next()?;
        for e in it.by_ref().take(MAX_RELATED) {
            first = first.with_related(e);
        }
        let rest = total.saturating_sub(MAX_RELATED + 1);
        if rest > 0 {
            first = first.with_note(format!("{rest} more error(s) not shown"));
        }
        Some(first)
    }

    /// The errors found beside this one, in the order they were added.
    pub fn related(&self) -> &[Error] {
        self.related.as_deref().map_or(&[], Vec::as_slice)
    }

    /// The remedy completes the line written last (the message, or the
    /// latest note).
    pub fn with_remedy(mut self, remedy: Remedy) -> Error {
        let last_note = self.notes.len().checked_sub(1);
        self.remedy = Some((remedy, last_note.and_then(|i| u16::try_from(i).ok())));
        self
    }

    /// The error as `Display` shows it, with each remedy in `word`'s
    /// words: the CLI passes its own, which name its flags.
    pub fn render(&self, word: &dyn Fn(Remedy) -> &'static str) -> String {
        self.render_styled(word, &|label| label.to_string())
    }

    /// As [`Error::render`], with the `error:` label as `label` writes it
    /// (the CLI colours it; the library knows no terminal).
    pub fn render_styled(
        &self,
        word: &dyn Fn(Remedy) -> &'static str,
        label: &dyn Fn(&str) -> String,
    ) -> String {
        let error = label("error:");
        let suffix = |line: Option<usize>| match self.remedy {
            Some((r, at)) if at.map(usize::from) == line => word(r),
            _ => "",
        };
        let mut out = String::new();
        let message = format!("{}{}", self.headline(), suffix(None));
        match &self.location {
            Some(loc) => {
                out.push_str(&format!(
                    "{}:{}:{}: {error} {message}",
                    loc.file, loc.line, loc.col
                ));
                if !loc.line_text.is_empty() {
                    let gutter = loc.line.to_string().len();
                    let (shown, before) = shown_line(&loc.line_text, loc.col);
                    out.push_str(&format!("\n{:gutter$} |", ""));
                    out.push_str(&format!("\n{} | {}", loc.line, shown));
                    let pad: String = before
                        .chars()
                        .map(|c| if c == '\t' { '\t' } else { ' ' })
                        .collect();
                    out.push_str(&format!("\n{:gutter$} | {}^", "", pad));
                }
            }
            None => out.push_str(&format!("{error} {message}")),
        }
        for (i, note) in self.notes.iter().enumerate() {
            out.push_str(&format!("\n  = {note}{}", suffix(Some(i))));
        }
        for e in self.related() {
            out.push('\n');
            out.push_str(&e.render_styled(word, label));
        }
        out
    }

    pub fn at(mut self, location: Location) -> Error {
        self.location = Some(Box::new(location));
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
            line_text: Box::default(),
        })
    }
}

/// The errors of one run, gathered so that the run reports every error it
/// can rather than stopping at the first: the first [`MAX_RELATED`] are
/// kept, the rest counted; [`Errors::into_error`] makes them one.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Errors {
    kept: Vec<Error>,
    count: usize,
}

impl Errors {
    pub fn push(&mut self, e: Error) {
        self.count += 1;
        if self.kept.len() < MAX_RELATED {
            self.kept.push(e);
        }
    }

    /// How many errors were pushed (kept or not).
    pub fn len(&self) -> usize {
        self.count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// `None` for no error; the error itself for one; for more,
    /// `summary(count)` (the caller's words, e.g. "3 targets cannot be
    /// reached") with the kept errors as its [`Error::related`] and, when
    /// some were not kept, a note counting them.
    pub fn into_error(self, summary: impl FnOnce(usize) -> Error) -> Option<Error> {
        if self.count <= 1 {
            return self.kept.into_iter().next();
        }
        let mut all = summary(self.count);
        if self.count > self.kept.len() {
            all = all.with_note(format!(
                "the first {} are listed, {} more are not",
                self.kept.len(),
                self.count - self.kept.len()
            ));
        }
        for e in self.kept {
            all = all.with_related(e);
        }
        Some(all)
    }
}

impl fmt::Display for Error {
    /// `file:line:col: error: message`, then the line and a caret under the
    /// column, then notes: the layout of rustc and most compilers, which
    /// editors turn into clickable locations.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(&Remedy::describe))
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
        assert_eq!(&*loc.line_text, "  ! été");
    }

    #[test]
    fn every_line_end_counts_once_and_keeps_offsets() {
        // The same three lines with each line end: `x` on line 3, column 3.
        for eol in ["\n", "\r\n", "\r"] {
            let src = format!("MODULE m{eol}  ! c{eol}  x := 1;{eol}");
            let b = src.as_bytes();
            let off = src.find('x').unwrap();
            let loc = Location::from_offset("a.mod", b, off);
            assert_eq!((loc.line, loc.col), (3, 3), "{eol:?}");
            assert_eq!(&*loc.line_text, "  x := 1;");
            assert_eq!(breaks_in(b, 0..b.len()), 3);
            let second = src.find('!').unwrap() - 2;
            assert_eq!(next_line_start(b, 0), Some(second));
            assert_eq!(line_start(b, off), src.find("  x").unwrap());
            assert_eq!(line_end(b, off), src.find(";").unwrap() + 1);
            assert_eq!(next_line_start(b, off), Some(b.len()));
            assert_eq!(line_break_of(b), eol);
        }
        // A `\r\n` cut between two ranges counts once; its `\n` is on the
        // line it ends.
        let b = b"a\r\nb";
        assert_eq!(breaks_in(b, 0..2) + breaks_in(b, 2..5), 1);
        assert_eq!(line_start(b, 2), 0);
        assert_eq!(line_start(b, 3), 3);
        assert_eq!(next_line_start(b"abc", 1), None);
        assert_eq!(line_break_of(b"abc"), "\n");
        assert_eq!(start_of_line(b"a\r\nb\rc", 3), 5);
        assert_eq!(start_of_line(b"a\r\nb\rc", 1), 0);
        assert_eq!(start_of_line(b"a\r\nb\rc", 9), 6);
        let lines: Vec<&str> = split_lines("a\r\nb\rc\n\nd").collect();
        assert_eq!(lines, ["a", "b", "c", "", "d"]);
        assert_eq!(split_lines("a\n").collect::<Vec<_>>(), ["a"]);
        assert_eq!(split_lines("").count(), 0);
    }

    #[test]
    fn a_remedy_completes_the_line_it_was_given_for() {
        let words = |r: Remedy| match r {
            Remedy::ChooseEntry => " (pick one with --entry)",
            _ => " (something else)",
        };
        let on_note = Error::input("no procedure `main`")
            .with_note("procedures: a, b")
            .with_remedy(Remedy::ChooseEntry)
            .with_note("a later note");
        assert_eq!(
            on_note.render(&words),
            "error: no procedure `main`\n  = procedures: a, b (pick one with --entry)\n  = a later note"
        );
        let on_message = Error::input("no time").with_remedy(Remedy::ChooseEntry);
        assert_eq!(
            on_message.render(&words),
            "error: no time (pick one with --entry)"
        );
        // The library's own words name no flag.
        assert_eq!(
            on_message.to_string(),
            "error: no time (choose the entry routine)"
        );
        assert!(!on_note.to_string().contains("--"));
    }

    #[test]
    fn a_long_line_is_cut_around_the_column_and_invisibles_are_shown() {
        let mut src = "x".repeat(1_000_000);
        src.insert_str(500_000, "\u{FEFF}\0bad");
        let e = Error::input("bad word").at(Location::from_offset("f", src.as_bytes(), 500_000));
        let shown = e.to_string();
        assert!(shown.len() < 400, "{} bytes shown", shown.len());
        let lines: Vec<&str> = shown.lines().collect();
        assert_eq!(
            lines[2],
            format!(
                "1 | …{}\\u{{FEFF}}\\0bad{}…",
                "x".repeat(80),
                "x".repeat(75)
            )
        );
        // The caret stands under the escaped BOM.
        assert_eq!(lines[3].find('^'), Some("1 | ".len() + 1 + 80));
    }

    #[test]
    fn quoted_input_is_bounded_and_says_its_length() {
        assert_eq!(quoted("p10"), "`p10`");
        assert_eq!(quoted(&"x".repeat(40)), format!("`{}`", "x".repeat(40)));
        let big = "1".repeat(10 << 20);
        let q = quoted(&big);
        assert_eq!(q, format!("`{}…` (10485760 characters)", "1".repeat(40)));
        assert_eq!(quoted("a\u{FEFF}b"), "`a\\u{FEFF}b`");
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

#[cfg(test)]
mod related_tests {
    use super::*;

    #[test]
    fn related_errors_render_as_blocks_of_their_own() {
        let src = b"p1\np2\n";
        let a = Error::input("bad p1").at(Location::from_offset("f", src, 0));
        let b = Error::input("bad p2").at(Location::from_offset("f", src, 3));
        let mut errors = Errors::default();
        errors.push(a);
        errors.push(b);
        let all = errors
            .into_error(|n| Error::input(format!("{n} bad targets")))
            .unwrap();
        assert_eq!(all.related().len(), 2);
        assert_eq!(
            all.to_string(),
            "error: 2 bad targets\nf:1:1: error: bad p1\n  |\n1 | p1\n  | ^\nf:2:1: error: bad p2\n  |\n2 | p2\n  | ^"
        );
        let mut one = Errors::default();
        one.push(Error::input("alone"));
        let one = one.into_error(|_| Error::input("x")).unwrap();
        assert_eq!(one.to_string(), "error: alone");
        assert!(Errors::default()
            .into_error(|_| Error::input("x"))
            .is_none());
        let mut many = Errors::default();
        for i in 0..25 {
            many.push(Error::input(format!("e{i}")));
        }
        assert_eq!(many.len(), 25);
        let all = many
            .into_error(|n| Error::input(format!("{n} errors")))
            .unwrap();
        assert_eq!(all.related().len(), MAX_RELATED);
        assert!(all.to_string().contains("5 more are not"));
    }

    /// Every `Result` of the library carries an `Error`: below clippy's
    /// `result_large_err` limit (128 bytes) on 64-bit targets.
    #[test]
    fn error_stays_small() {
        assert!(std::mem::size_of::<Error>() < 128);
    }
}

#[cfg(test)]
mod subject_tests {
    use super::*;

    #[test]
    fn an_error_about_a_target_says_it_before_its_cause() {
        let e = Error::input("unknown tool `t`").about(Subject::Target("p20".to_string()));
        assert_eq!(e.message, "unknown tool `t`");
        assert_eq!(e.headline(), "target p20: unknown tool `t`");
        assert_eq!(e.to_string(), "error: target p20: unknown tool `t`");
        let j = Error::input("x").about(Subject::JointTarget("j1".to_string()));
        assert_eq!(j.headline(), "jointtarget j1: x");
    }
}
