//! Diagnosis of the sim-to-real gap: where the gap between the model and
//! measured flange positions lies, which physical effect causes it, and how
//! far it shrinks once that effect is in the model.
//!
//! This module owns the measurements file, the fit of candidate effects,
//! their held-out selection, the verdict and its wording, the simulated
//! "real" data used to test all of it, and plots of the gap (as SVG text).
//! It builds on [`crate::model`] (the warm robot and its effects),
//! [`crate::robot`], [`crate::thermal`], [`crate::resolve`] and
//! [`crate::rapid`] (poses of a program's targets), and the shared
//! [`crate::error`] and [`crate::csv_table`]; never on `correct` or the
//! command line. It names no command-line flag: where a remedy needs one,
//! the result is typed ([`RegisterFailure`], [`Advice`]) or the wording is
//! the caller's ([`prose::Remedies`]).
//!
//! Pipeline: [`prepare()`] (resolve temperatures, pose identities, optional
//! registration of a tracker frame) → [`gap()`] (RMS/max of the current
//! model) or [`diagnose()`] (noise level, localisation, candidate fits with
//! held-out scores, forward selection, [`Verdict`]) → [`prose::words`].
//!
//! Files: [`mod@prepare`] (measurements + model → fit problem, instrument
//! frame), [`mod@gap`] (gap statistics, noise level), [`fit`] (the fit of
//! effects; what it is fitted to in `fit_problem`, what it gives in
//! `fitted`), [`select`] (folds, candidate scores), [`locate`] (where a gap
//! lies, as typed [`finding`]s, each worded in one place), [`pipeline`]
//! (the diagnosis and its verdict), `stages` (its stages and what they
//! share), [`verdict`] (the result as data),
//! [`prose`] (the result in sentences), [`instrument`] (noise levels and
//! the ISO cube from `data/instrument.toml`), [`sanity`] (sets a diagnosis
//! cannot mean anything on), [`arm`],
//! [`measurements`], [`simulate`], [`plot`].

pub mod arm;
pub mod chain_calib;
pub mod chain_diagnose;
pub mod chain_finding;
pub mod chain_residual;
pub mod detect;
pub mod drift;
pub mod finding;
pub mod fit;
mod fit_key;
mod fit_problem;
mod fit_steps;
mod fitted;
pub mod forward;
pub mod gap;
pub mod instrument;
pub mod job;
pub mod joint_signature;
mod judge;
pub mod knock;
mod listed;
pub mod locate;
pub mod measurements;
pub mod memo;
mod options;
pub mod pipeline;
pub mod plan;
pub mod plausible;
pub mod plot;
pub mod prepare;
pub mod prose;
pub mod sanity;
pub mod saved;
pub mod select;
pub mod separation;
pub mod signature;
pub mod simulate;
pub mod square;
pub mod stability;
mod stages;
pub mod stats;
mod step;
pub mod temps;
pub mod test_noise;
pub mod unidentified;
pub mod verdict;

pub use gap::{estimate_noise, gap, gap_stats, orientation_gap, GapStats, Noise, NoiseSource};
pub use pipeline::{diagnose, diagnosed_model, DiagnoseOptions};
pub use prepare::{
    place_in_base, prepare, prepare_arm, problem_of, register_instrument, Prepared, PreparedFrom,
    RegisterFailure, Registration,
};
pub use verdict::{
    Advice, Ambiguity, CandidateOut, Diagnosis, NotNamed, NotNamedWhy, ParamOut, ScoredIn,
    StageSummary, StepOut, Verdict,
};
