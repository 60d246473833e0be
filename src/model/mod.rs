//! The warm robot both jobs share: what the simulation says a robot does at
//! a moment of its warm-up. `correct` asks it where targets go; `diagnose`
//! fits its effects to measurements and writes it back as a model file.
//!
//! Owns: the model file ([`mod@file`], its embedded default), the base
//! thermal expansion ([`expansion`]), the effect library of
//! `docs/model.md` ("The effect library") ([`effects`]), the perturbed kinematic chain
//! ([`chain`], [`perturb`]), the bounds of a plausible model
//! ([`plausible`]) and [`warm::WarmRobot`].
//!
//! May import: `robot` (geometry), `thermal` (temperatures over time) and
//! the shared `error`. Never `resolve`, `schedule`, `correct` or
//! `diagnose`.

pub mod chain;
pub mod effects;
pub mod expansion;
pub mod file;
pub mod file_place;
pub mod general;
pub mod perturb;
pub mod plausible;
pub mod warm;

pub use effects::{Effect, EffectKind};
pub use expansion::{LinkThermal, ThermalExpansion};
pub use file::{
    EffectEntry, HeatingSection, InstrumentSection, JointConvention, Model, ModelArm, RobotSection,
    FORMAT,
};
pub use perturb::{
    fk_perturbed, lag_taus, perturbation, perturbation_with, predict, predict_with, Base, Geometry,
    LinkLags, RowFree, RowState, Warm,
};
pub use warm::{Moment, State, States, WarmRobot};
