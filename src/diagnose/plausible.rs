//! The largest magnitude each effect parameter can take on a real arm: the
//! model's bounds (`data/plausible_effects.toml`, read by
//! [`crate::model::plausible`]), which every model file read is checked
//! against. A fitted value beyond its bound is the fit wandering along a
//! direction the data hardly constrain, and the parameter is declared not
//! identifiable instead of reported.

pub use crate::model::plausible::{bound, PLAUSIBLE_EFFECTS_TOML};
