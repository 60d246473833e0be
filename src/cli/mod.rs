//! Command-line layer: argument parsing (clap), reading inputs, writing
//! outputs, exit codes. Every computation is the library's.
//!
//! Exit codes: 0 success; 1 when `--check`/`--diff` finds changes or a gate
//! (`--fail-above`) fails; 2 for usage and input errors.
//!
//! Messages go through `messages` (`-q`, `-v`, `--color`), never straight
//! to standard error.
#![deny(clippy::print_stderr)]

mod arms;
mod ci_report;
mod ci_suite;
mod compare;
mod correct;
mod correct_report;
mod correct_runtime;
mod correct_words;
mod diagnose;
mod diagnose_args;
mod diagnose_chain;
mod events;
mod examples;
mod format;
mod gap;
mod generate;
mod heating;
mod io;
mod junit;
mod kinematics;
mod messages;
mod model;
mod output;
mod plot;
mod sarif;
mod schedule;
mod simulate;
mod targets;
mod tasks;
mod unified_diff;

pub use format::{Format, Status};
pub use io::{read_input, write_stdout, Inputs};
pub use output::write_output;

use clap::{CommandFactory, Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "rapidtherm",
    version,
    about = "Thermal drift correction for ABB RAPID programs, and sim-to-real diagnosis",
    propagate_version = true
)]
struct Cli {
    #[command(flatten)]
    messages: messages::MessageArgs,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List every target of RAPID programs (declared, array elements, record fields, inline).
    Targets(targets::TargetsArgs),
    /// Forward kinematics: flange pose for joint angles (degrees), optionally warm.
    Fk(kinematics::FkArgs),
    /// Inverse kinematics: joint solutions for a flange pose.
    Ik(kinematics::IkArgs),
    /// Heating curves: fit recordings, evaluate profiles.
    #[command(subcommand)]
    Heating(heating::HeatingArgs),
    /// Estimate when each target of a program is reached (CSV schedule).
    Schedule(schedule::ScheduleArgs),
    /// Rewrite a program's targets so that the warm robot reaches what the cold program meant.
    Correct(correct::CorrectArgs),
    /// Compare the targets of two programs.
    Diff(compare::DiffArgs),
    /// Show the model the simulation uses.
    #[command(subcommand)]
    Model(model::ModelArgs),
    /// Make simulated measurements ("real" data) with chosen effects and noise.
    Simulate(simulate::SimulateArgs),
    /// Diagnose the sim-to-real gap of measured positions.
    Diagnose(diagnose_args::DiagnoseArgs),
    /// RMS and max gap of a model on measured data.
    Gap(gap::GapArgs),
    /// List the ABB arms `--robot` takes by name (payload, reach, where the numbers come from).
    Arms(arms::ArmsArgs),
    /// Print the shell completion script for bash, zsh, fish, elvish or powershell.
    Completions(generate::CompletionsArgs),
    /// Print the man page (roff), or write one page per subcommand with --out-dir.
    Man(generate::ManArgs),
}

pub fn main() -> ExitCode {
    junit::start_clock();
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    // Before parsing: clap's own errors and help follow --color too.
    messages::set_color(messages::color_before_parsing(&args));
    // Every command's help ends with its examples and exit statuses.
    let cli = match examples::annotate(Cli::command())
        .try_get_matches_from(args)
        .and_then(|m| <Cli as clap::FromArgMatches>::from_arg_matches(&m))
    {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    // clap sees the conflict only when both flags are on the same side
    // of the subcommand.
    if cli.messages.quiet && cli.messages.verbose > 0 {
        Cli::command()
            .error(
                clap::error::ErrorKind::ArgumentConflict,
                "the argument '--quiet' cannot be used with '--verbose'",
            )
            .exit();
    }
    messages::init(&cli.messages);
    output::remove_temporaries_on_signals();
    let result = match cli.command {
        Command::Targets(a) => targets::plan(a).and_then(targets::run),
        Command::Fk(a) => kinematics::plan_fk(a).and_then(kinematics::run_fk),
        Command::Ik(a) => kinematics::plan_ik(a).and_then(kinematics::run_ik),
        Command::Heating(a) => heating::plan(a).and_then(heating::run),
        Command::Schedule(a) => schedule::plan(a).and_then(schedule::run),
        Command::Correct(a) => correct::plan(a).and_then(correct::run),
        Command::Diff(a) => compare::plan(a).and_then(compare::run),
        Command::Model(a) => model::plan(a).and_then(model::run),
        Command::Simulate(a) => simulate::plan(a).and_then(simulate::run),
        Command::Diagnose(a) => diagnose::plan(a).and_then(diagnose::run),
        Command::Gap(a) => gap::plan(a).and_then(gap::run),
        Command::Arms(a) => arms::plan(a).and_then(arms::run_arms),
        Command::Completions(a) => generate::plan_completions(a)
            .and_then(|plan| generate::run_completions(plan, Cli::command())),
        Command::Man(a) => {
            generate::plan_man(a).and_then(|plan| generate::run_man(plan, Cli::command()))
        }
    };
    match result {
        Ok(Status::Success) => ExitCode::SUCCESS,
        Ok(Status::Changes) => ExitCode::from(1),
        Err(e) => {
            messages::print_error(&e);
            ExitCode::from(2)
        }
    }
}
