//! Everything the command line says on standard error, in one place (as
//! ripgrep's `messages` module): the remedies in the CLI's words (so that a
//! renamed flag is renamed in every message), how much is said (`-q`,
//! `-v`), and in what colours (`--color`, `NO_COLOR`, `CLICOLOR_FORCE`).
//!
//! Levels, each a macro that takes `format!` arguments and ends the line:
//! - [`error!`]: `error:` and the message; always shown.
//! - [`warning!`], [`note!`]: `warning:`/`note:`; hidden by `-q`.
//! - [`status!`]: a summary line without a label (targets corrected, files
//!   written); hidden by `-q`.
//! - [`outcome!`]: what a gate or a check found when it goes to standard
//!   error (the failing targets); shown even with `-q`, as the exit code 1
//!   that goes with it.
//! - [`info!`]: `-v`, what a user debugging a run wants (which arm and
//!   model, from where; which files); [`took`] adds timings at `-vv`, so
//!   that `-v`'s output is the same on every run.
//!
//! Standard output is data and never depends on these flags. Only the
//! labels are coloured; `anstream` decides whether the terminal gets
//! colour, and clap (which uses it too) follows the same choice.

use anstyle::{AnsiColor, Effects, Style};
use rapidtherm::error::{Error, Remedy};
use std::ffi::OsString;
use std::io::Write;
use std::sync::atomic::{AtomicI8, Ordering};

/// `-q`, `-v`, `--color`: valid before or after the subcommand.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct MessageArgs {
    /// Print only errors and what a check or gate found: no warnings,
    /// notes, summaries or progress bar (standard output is unchanged).
    // Repeated, as an alias may add it, it is still one -q.
    #[arg(
        short,
        long,
        global = true,
        conflicts_with = "verbose",
        overrides_with = "quiet"
    )]
    pub quiet: bool,
    /// Say on standard error which arm, model and files each task uses;
    /// -vv adds timings.
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    pub verbose: u8,
    /// When to colour the labels of messages: auto colours a terminal
    /// only, and follows NO_COLOR and CLICOLOR_FORCE.
    #[arg(
        long,
        global = true,
        value_enum,
        value_name = "WHEN",
        default_value_t = ColorWhen::Auto
    )]
    pub color: ColorWhen,
}

/// `--color`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ColorWhen {
    #[default]
    Auto,
    Always,
    Never,
}

impl From<ColorWhen> for anstream::ColorChoice {
    fn from(c: ColorWhen) -> Self {
        match c {
            ColorWhen::Auto => anstream::ColorChoice::Auto,
            ColorWhen::Always => anstream::ColorChoice::Always,
            ColorWhen::Never => anstream::ColorChoice::Never,
        }
    }
}

/// -1 quiet, 0 normal, 1 and more: `-v`, `-vv`.
static VERBOSITY: AtomicI8 = AtomicI8::new(0);

/// The colour choice of `args` as given on the command line, before clap
/// has parsed it, so that clap's own errors and help (for an invalid
/// command line too) follow `--color`. The last `--color` before `--`
/// wins, as clap reads it; an invalid value is left for clap to report.
pub fn color_before_parsing(args: &[OsString]) -> ColorWhen {
    let mut choice = ColorWhen::Auto;
    let mut it = args.iter().skip(1).filter_map(|a| a.to_str());
    while let Some(arg) = it.next() {
        if arg == "--" {
            break;
        }
        let value = match arg.strip_prefix("--color") {
            Some("") => it.next(),
            Some(v) => v.strip_prefix('='),
            None => None,
        };
        if let Some(c) = value.and_then(|v| clap::ValueEnum::from_str(v, true).ok()) {
            choice = c;
        }
    }
    choice
}

/// Set the colour choice for everything written to the terminal from now
/// on (clap's output included).
pub fn set_color(when: ColorWhen) {
    anstream::ColorChoice::write_global(when.into());
}

/// Apply the parsed flags.
pub fn init(args: &MessageArgs) {
    set_color(args.color);
    let level = if args.quiet {
        -1
    } else {
        i8::try_from(args.verbose).unwrap_or(i8::MAX)
    };
    VERBOSITY.store(level, Ordering::Relaxed);
}

/// Whether `-q` was given: no warnings, notes, summaries or progress bar.
pub fn quiet() -> bool {
    VERBOSITY.load(Ordering::Relaxed) < 0
}

/// Whether a progress bar may be drawn: to a person (standard error a
/// terminal), and not with `-q`.
pub fn progress_shown() -> bool {
    use std::io::IsTerminal;
    !quiet() && std::io::stderr().is_terminal()
}

const ERROR: Style = AnsiColor::Red.on_default().effects(Effects::BOLD);
const WARNING: Style = AnsiColor::Yellow.on_default().effects(Effects::BOLD);
const NOTE: Style = AnsiColor::Cyan.on_default().effects(Effects::BOLD);

/// The label of a level, as it starts a line: `error:`, `warning:`,
/// `note:`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    Error,
    Warning,
    Note,
}

impl Level {
    fn word(self) -> &'static str {
        match self {
            Level::Error => "error:",
            Level::Warning => "warning:",
            Level::Note => "note:",
        }
    }

    fn style(self) -> Style {
        match self {
            Level::Error => ERROR,
            Level::Warning => WARNING,
            Level::Note => NOTE,
        }
    }

    fn shown(self) -> bool {
        self == Level::Error || !quiet()
    }
}

/// `text` coloured as `style` (the escape codes are dropped by `anstream`
/// where colour is off).
fn paint(style: Style, text: &str) -> String {
    format!("{style}{text}{style:#}")
}

/// Write one or more whole lines to standard error. A closed standard
/// error is not worth a panic: there is no one left to tell.
fn write_stderr(text: &str) {
    let mut err = anstream::stderr().lock();
    let _ = err.write_all(text.as_bytes());
    let _ = err.flush();
}

/// A message at `level`: `label message`, or `location: label message`
/// (the compilers' `file:line:col: warning: …`, which editors follow).
pub fn emit(level: Level, location: Option<&str>, message: std::fmt::Arguments) {
    if !level.shown() {
        return;
    }
    let label = paint(level.style(), level.word());
    match location {
        Some(at) => write_stderr(&format!("{at}: {label} {message}\n")),
        None => write_stderr(&format!("{label} {message}\n")),
    }
}

/// A line without a label at the given verbosity: -1 for what even `-q`
/// shows, 0 for summaries, 1 for `-v`, 2 for `-vv`.
pub fn emit_plain(level: i8, message: std::fmt::Arguments) {
    if VERBOSITY.load(Ordering::Relaxed) >= level {
        write_stderr(&format!("{message}\n"));
    }
}

/// `error:` and the message: always shown.
macro_rules! error {
    ($($arg:tt)*) => {
        $crate::cli::messages::emit($crate::cli::messages::Level::Error, None, format_args!($($arg)*))
    };
}

/// `warning:` and the message; hidden by `-q`.
macro_rules! warning {
    ($($arg:tt)*) => {
        $crate::cli::messages::emit($crate::cli::messages::Level::Warning, None, format_args!($($arg)*))
    };
}

/// `note:` and the message; hidden by `-q`.
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::cli::messages::emit($crate::cli::messages::Level::Note, None, format_args!($($arg)*))
    };
}

/// A summary line (no label); hidden by `-q`.
macro_rules! status {
    ($($arg:tt)*) => {
        $crate::cli::messages::emit_plain(0, format_args!($($arg)*))
    };
}

/// What a gate or check found, on standard error; shown even with `-q`.
macro_rules! outcome {
    ($($arg:tt)*) => {
        $crate::cli::messages::emit_plain(-1, format_args!($($arg)*))
    };
}

/// `-v`: what a user debugging a run wants to know.
macro_rules! info {
    ($($arg:tt)*) => {
        $crate::cli::messages::emit_plain(1, format_args!("info: {}", format_args!($($arg)*)))
    };
}

pub(crate) use {error, info, note, outcome, status, warning};

/// Text made of whole lines, each said at the level its label gives
/// (`error:`, `warning:`, `note:`; a line without one is a summary, as
/// [`status!`]): the reports the CLI composes as one text (a run's summary
/// and its left-alone targets) keep their levels line by line.
pub fn lines(text: &str) {
    said(text, 0);
}

/// As [`lines`], the unlabelled lines being what a gate or check found
/// ([`outcome!`]): shown even with `-q`.
pub fn outcome_lines(text: &str) {
    said(text, -1);
}

fn said(text: &str, plain: i8) {
    for line in text.lines() {
        let labelled = [Level::Error, Level::Warning, Level::Note]
            .into_iter()
            .find_map(|l| line.strip_prefix(l.word()).map(|rest| (l, rest)));
        match labelled {
            Some((level, rest)) => emit(level, None, format_args!("{}", rest.trim_start())),
            None => emit_plain(plain, format_args!("{line}")),
        }
    }
}

/// A RAPID reader's warning, at its place in the file.
pub fn warning_at(w: &rapidtherm::rapid::Warning) {
    let l = &w.location;
    let at = format!("{}:{}:{}", l.file, l.line, l.col);
    emit(Level::Warning, Some(&at), format_args!("{}", w.message));
}

/// At `-vv`, how long `what` took since `start`.
pub fn took(what: &str, start: std::time::Instant) {
    took_for(what, start.elapsed());
}

/// At `-vv`, that `what` took `elapsed`.
pub fn took_for(what: &str, elapsed: std::time::Duration) {
    emit_plain(
        2,
        format_args!("info: {what}: {:.1} ms", elapsed.as_secs_f64() * 1e3),
    );
}

/// A remedy in the command line's terms.
pub fn remedy(r: Remedy) -> &'static str {
    match r {
        Remedy::ChooseEntry => " (choose one with --entry)",
        Remedy::GiveSchedule => ": give the schedule with --schedule instead",
        Remedy::GiveDefaultTime => " (add it, or give a default time with --default-time)",
        Remedy::GiveMinute => ": give a time with --at MIN",
        Remedy::FitSaturatingOrGiveMinute => {
            ": fit a saturating model (first-order, two-tau) or give a time with --at MIN"
        }
        Remedy::FitBeyondRecording => {
            "; fit a saturating model (`heating fit --model first-order`) to predict beyond it, or hold the end values explicitly"
        }
        Remedy::ListArms => " (`rapidtherm arms` lists every name)",
        Remedy::NameTheArm => "; give the arm with --robot TASK=NAME|FILE.urdf",
        Remedy::AnotherArm => {
            "; a program for another arm: name it with --robot (`rapidtherm arms` lists them)"
        }
        Remedy::ModelOfTheArm => {
            "give a model file of this arm with --model FILE.toml (its heating measured, or a heating recording in it), or use the IRB 140's defaults on this arm's lengths with --irb140-thermal"
        }
        Remedy::ArmOfTheModel => {
            "give a model diagnosed on this arm, or leave out --robot to use the model's"
        }
        Remedy::OneTaskAtATime => " with --task",
        Remedy::AcceptDefaultPlacement => {
            "; mend the backup, or put the robot at the world origin with --accept-default-placement"
        }
        Remedy::Force => ": move it away, or give --force to replace it",
    }
}

/// An error as the CLI prints it, its `error:` labels coloured.
pub fn render_error(e: &Error) -> String {
    e.render_styled(&remedy, &|label| paint(ERROR, label))
}

/// Print an error (always shown).
pub fn print_error(e: &Error) {
    write_stderr(&format!("{}\n", render_error(e)));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn os(args: &[&str]) -> Vec<OsString> {
        args.iter().map(OsString::from).collect()
    }

    #[test]
    fn color_is_read_before_parsing_as_clap_reads_it() {
        let c = |a: &[&str]| color_before_parsing(&os(a));
        assert_eq!(c(&["rt", "targets", "x.mod"]), ColorWhen::Auto);
        assert_eq!(
            c(&["rt", "--color", "always", "targets"]),
            ColorWhen::Always
        );
        assert_eq!(c(&["rt", "targets", "--color=never"]), ColorWhen::Never);
        assert_eq!(
            c(&["rt", "--color=always", "x", "--color", "never"]),
            ColorWhen::Never,
            "the last one wins"
        );
        assert_eq!(c(&["rt", "--color", "bogus"]), ColorWhen::Auto);
        assert_eq!(c(&["rt", "--", "--color=always"]), ColorWhen::Auto);
        assert_eq!(c(&["rt", "--colors=always"]), ColorWhen::Auto);
    }
}
