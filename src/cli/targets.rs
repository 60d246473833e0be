//! `rapidtherm targets FILE...`: every robtarget of RAPID programs. The
//! listing is the library's (`resolve::listing`); this reads the tasks
//! and writes it, as the plan of the arguments says.
use super::tasks::TaskPick;
use super::Format;
use super::{write_stdout, Status};
use rapidtherm::error::Result;
use rapidtherm::resolve::listing::{joints, listing, listing_parts, ListFormat};
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct TargetsArgs {
    /// RAPID files (.mod, .modx, .prg, .sys); `-` reads standard input.
    /// Several files are read as one run (identifiers unique across them).
    /// A program file (.pgf), a task folder or a controller backup: each
    /// task is one run.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub pick: super::tasks::TaskArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// List the jointtargets (MoveAbsJ positions, degrees) instead.
    #[arg(long)]
    pub joints: bool,
}

/// The library's name of a listing format.
fn list_format(f: Format) -> ListFormat {
    match f {
        Format::Table => ListFormat::Table,
        Format::Csv => ListFormat::Csv,
        Format::Json => ListFormat::Json,
    }
}

/// What `targets` lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Listed {
    Robtargets,
    /// `--joints`: the jointtargets.
    Jointtargets,
}

/// Everything `targets` does, read from its arguments once.
pub struct TargetsCommand {
    files: Vec<PathBuf>,
    pick: TaskPick,
    format: Format,
    listed: Listed,
}

/// The plan of `targets`' arguments (clap has refused every wrong one).
pub fn plan(args: TargetsArgs) -> Result<TargetsCommand> {
    Ok(TargetsCommand {
        files: args.files,
        pick: args.pick.into(),
        format: args.format,
        listed: if args.joints {
            Listed::Jointtargets
        } else {
            Listed::Robtargets
        },
    })
}

pub fn run(cmd: TargetsCommand) -> Result<Status> {
    let tasks = super::tasks::select(&cmd.files, &cmd.pick)?;
    let refs: Vec<&rapidtherm::rapid::task::Task> = tasks.iter().collect();
    let labels = super::tasks::labels(&refs);
    let format = list_format(cmd.format);
    // One task's listing is written as it is put together: a million
    // targets make 150 MB of text, which need not be held whole first.
    if let ([task], None, Listed::Robtargets) = (tasks.as_slice(), &labels, cmd.listed) {
        let (inputs, prog) = super::tasks::read(task)?;
        let (lister, parts) = listing_parts(format, inputs.len() > 1, &prog);
        let mut out = std::io::BufWriter::with_capacity(1 << 20, std::io::stdout().lock());
        let written = lister.finish(parts, &mut out).and_then(|_| out.flush());
        super::io::stdout_written(written)?;
        return Ok(Status::Success);
    }
    let mut texts = Vec::new();
    for task in &tasks {
        let (inputs, prog) = super::tasks::read(task)?;
        texts.push(match cmd.listed {
            Listed::Jointtargets => joints(&prog, format),
            Listed::Robtargets => listing(format, inputs.len() > 1, &prog),
        });
    }
    let out = super::tasks::join(cmd.format, labels.as_deref(), texts, &[])?;
    write_stdout(out.as_bytes())?;
    Ok(Status::Success)
}
