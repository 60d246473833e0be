//! Diagnosis of the sim-to-real gap: where the gap between the model and
//! measured flange positions lies, which physical effect causes it, and how
//! far it shrinks once that effect is in the model.

pub mod chain;
pub mod effects;
pub mod measurements;
pub mod fit;
