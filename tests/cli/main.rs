//! The command line as a user meets it: transcripts of every case in
//! `tests/cmd/` (regenerate with `TRYCMD=overwrite cargo test --test cli`),
//! the CI report formats against their specifications, and the pre-commit
//! hook as pre-commit runs it. One binary, one link.

mod announced;
mod backinfo;
mod bare_names;
mod ci_report;
mod ci_snippets;
mod conventions;
mod docs_commands;
mod gate;
mod help_examples;
mod hostile;
mod json_schemas;
mod outputs;
mod plain_task_folder;
mod plans;
mod pre_commit_hook;
mod readme_tour;
mod runtime_gate;
mod transcripts;
mod writes;
