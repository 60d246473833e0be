//! What every command shares of its output: the data format `--format`
//! chooses, and how a run that did not fail ended (its exit code).

/// Output format chosen with `--format`: the library renders tables, CSV
/// and JSON; which one a run prints is the command line's choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Format {
    #[default]
    Table,
    Csv,
    Json,
}

/// How a command that ran without error ended.
pub enum Status {
    /// Exit 0.
    Success,
    /// Exit 1: `--check`/`--diff` found changes, or a gate failed.
    Changes,
}
