//! The examples and exit statuses of every command
//! (`data/help/examples.toml`): the end of each `--help`, and the man
//! pages' EXAMPLES and EXIT STATUS. One file for both, run by
//! tests/cli/help_examples.rs, so that neither can drift from what the
//! commands do.

use serde::Deserialize;
use std::sync::OnceLock;

/// The embedded file.
pub const EXAMPLES_TOML: &str = include_str!("../../data/help/examples.toml");

#[derive(Deserialize)]
struct File {
    command: Vec<CommandHelp>,
}

/// One command's examples and exit statuses.
#[derive(Debug, Deserialize)]
pub struct CommandHelp {
    /// The command's path below `rapidtherm` (`heating fit`).
    pub path: String,
    /// Each exit status and what it means.
    pub exit: Vec<(i32, String)>,
    pub examples: Vec<Example>,
}

/// One example: the command line as typed, what it does, and the exit
/// status it ends with.
#[derive(Debug, Deserialize)]
pub struct Example {
    pub run: String,
    pub does: String,
    #[serde(default)]
    pub exit: i32,
}

/// Every command's help, as the embedded file gives it.
pub fn all() -> &'static [CommandHelp] {
    static ALL: OnceLock<Vec<CommandHelp>> = OnceLock::new();
    ALL.get_or_init(|| {
        toml::from_str::<File>(EXAMPLES_TOML)
            .expect("the embedded data/help/examples.toml reads (tests/cli/help_examples.rs)")
            .command
    })
}

fn of(path: &str) -> Option<&'static CommandHelp> {
    all().iter().find(|c| c.path == path)
}

/// `cmd` (the command line's definition) with every subcommand's help
/// ending in its examples and exit statuses.
pub fn annotate(cmd: clap::Command) -> clap::Command {
    let cmd = annotate_below(cmd, "");
    match of("") {
        Some(help) => cmd.after_help(help_text(help)),
        None => cmd,
    }
}

fn annotate_below(mut cmd: clap::Command, path: &str) -> clap::Command {
    let names: Vec<String> = cmd
        .get_subcommands()
        .map(|s| s.get_name().to_string())
        .collect();
    for name in names {
        let sub_path = if path.is_empty() {
            name.clone()
        } else {
            format!("{path} {name}")
        };
        cmd = cmd.mut_subcommand(&name, |sub| {
            let sub = annotate_below(sub, &sub_path);
            match of(&sub_path) {
                Some(help) => sub.after_help(help_text(help)),
                None => sub,
            }
        });
    }
    cmd
}

/// The text `--help` ends with.
fn help_text(help: &CommandHelp) -> String {
    let mut s = String::from("Examples:\n");
    for e in &help.examples {
        s.push_str(&format!("  $ {}\n      {}{}\n", e.run, e.does, ends(e)));
    }
    s.push_str("\nExit status:\n");
    for (code, what) in &help.exit {
        s.push_str(&format!("  {code}  {what}\n"));
    }
    s
}

/// What an example's exit status is, where it is not 0.
fn ends(e: &Example) -> String {
    if e.exit == 0 {
        String::new()
    } else {
        format!(" (exits {})", e.exit)
    }
}

/// The man page sections of the command at `path`: EXIT STATUS and
/// EXAMPLES, in roff.
pub fn man_sections(path: &str) -> String {
    let Some(help) = of(path) else {
        return String::new();
    };
    let mut s = String::from(".SH \"EXIT STATUS\"\n");
    for (code, what) in &help.exit {
        s.push_str(&format!(".TP\n\\fB{code}\\fR\n{}\n", roff(what)));
    }
    s.push_str(".SH EXAMPLES\n");
    for e in &help.examples {
        let does = format!("{}{}", e.does, ends(e));
        s.push_str(&format!(".TP\n\\fB{}\\fR\n{}\n", roff(&e.run), roff(&does)));
    }
    s
}

/// Text as roff reads it: a backslash and a minus escaped, no line
/// starting with a control character.
fn roff(text: &str) -> String {
    let t = text.replace('\\', "\\e").replace('-', "\\-");
    if t.starts_with('.') || t.starts_with('\'') {
        format!("\\&{t}")
    } else {
        t
    }
}
