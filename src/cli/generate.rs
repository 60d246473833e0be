//! `completions` and `man`: shell completion scripts and man pages made
//! from the clap definitions at run time, so that they always describe the
//! binary that prints them (`cargo install` installs a binary and nothing
//! else; a build-time generation would leave them in the target folder).

use super::{write_stdout, Status};
use rapidtherm::error::{Error, Result};
use rapidtherm::writes::{Made, Plan, Role};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    shell: clap_complete::Shell,
}

#[derive(clap::Args)]
pub struct ManArgs {
    /// Write one page per command and subcommand (rapidtherm.1,
    /// rapidtherm-correct.1, ...) into this folder instead of printing the
    /// main page.
    #[arg(long, value_name = "DIR")]
    out_dir: Option<PathBuf>,
    /// Replace a file in the folder even where it is not a man page
    /// (docs/limits.md); without it such a file is refused.
    #[arg(long, requires = "out_dir")]
    force: bool,
}

/// `completions`, read from its arguments once.
pub struct CompletionsCommand {
    shell: clap_complete::Shell,
}

/// The plan of `completions`' arguments (clap has refused every wrong
/// one).
pub fn plan_completions(args: CompletionsArgs) -> Result<CompletionsCommand> {
    Ok(CompletionsCommand { shell: args.shell })
}

/// `man`, read from its arguments once.
pub enum ManCommand {
    /// The main page on standard output.
    Print,
    /// A page per command into `dir`.
    Pages { dir: PathBuf, force: bool },
}

/// The plan of `man`'s arguments: the folder checked before anything is
/// written.
pub fn plan_man(args: ManArgs) -> Result<ManCommand> {
    let Some(dir) = args.out_dir else {
        return Ok(ManCommand::Print);
    };
    super::output::check_folder("--out-dir", &dir)?;
    Ok(ManCommand::Pages {
        dir,
        force: args.force,
    })
}

/// `cli`: the command line's own definition, which the script completes.
pub fn run_completions(plan: CompletionsCommand, mut cli: clap::Command) -> Result<Status> {
    let mut script = Vec::new();
    clap_complete::generate(plan.shell, &mut cli, "rapidtherm", &mut script);
    write_stdout(&script)?;
    Ok(Status::Success)
}

/// `cli`: the command line's own definition, which the pages describe.
pub fn run_man(plan: ManCommand, cli: clap::Command) -> Result<Status> {
    // As clap_mangen::generate_to prepares it: subcommands named
    // `rapidtherm-correct`, no `help` subcommand page.
    let mut cmd = cli.disable_help_subcommand(true);
    cmd.build();
    let (dir, force) = match plan {
        ManCommand::Print => {
            write_stdout(&page(&cmd, "")?)?;
            return Ok(Status::Success);
        }
        ManCommand::Pages { dir, force } => (dir, force),
    };
    let mut pages = Vec::new();
    collect(&cmd, "", &mut pages)?;
    let mut writes = Plan::new(force);
    let flag = format!("--out-dir {}", dir.display());
    for (name, _) in &pages {
        writes.output(&flag, &dir.join(name), Role::Made(Made::ManPage));
    }
    let checked = super::output::check(&writes)?;
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, &e))?;
    for (name, roff) in pages {
        let path = dir.join(name);
        super::output::write_atomic(&checked, &path, &roff, None)?;
    }
    Ok(Status::Success)
}

/// One command's page, in roff: clap's sections, then its EXIT STATUS and
/// EXAMPLES (`path`: the command below `rapidtherm`, empty for the top).
fn page(cmd: &clap::Command, path: &str) -> Result<Vec<u8>> {
    let mut roff = Vec::new();
    clap_mangen::Man::new(cmd.clone())
        .render(&mut roff)
        .map_err(|e| Error::io(std::path::Path::new("<man page>"), &e))?;
    roff.extend(super::examples::man_sections(path).into_bytes());
    Ok(roff)
}

/// The page of `cmd` and of every visible subcommand below it, with their
/// file names.
fn collect(cmd: &clap::Command, path: &str, out: &mut Vec<(String, Vec<u8>)>) -> Result<()> {
    let name = cmd.get_display_name().unwrap_or_else(|| cmd.get_name());
    out.push((format!("{name}.1"), page(cmd, path)?));
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        let below = if path.is_empty() {
            sub.get_name().to_string()
        } else {
            format!("{path} {}", sub.get_name())
        };
        collect(sub, &below, out)?;
    }
    Ok(())
}
