//! What a chain calibration's diagnosis found, typed, and the one place
//! each is put in words: the stages of increasing scope, what the held-out
//! evidence names, and what it says of temperatures. The report's
//! sentences and the JSON strings are rendered from these.

use crate::model::EffectKind;
use serde::{Serialize, Serializer};
use std::fmt;

/// A model of increasing scope.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChainStage {
    /// The nominal chain, positions as measured.
    AsMeasured,
    /// The nominal chain in a rigid instrument frame.
    RigidFrame,
    /// The instrument frame and the measured point fitted.
    FrameAndPoint,
    /// Joint offsets and origins too: the full geometry.
    FullGeometry,
}

impl ChainStage {
    pub fn words(self) -> &'static str {
        match self {
            ChainStage::AsMeasured => "nominal, as measured",
            ChainStage::RigidFrame => "nominal, rigid instrument frame",
            ChainStage::FrameAndPoint => "instrument frame + measured point",
            ChainStage::FullGeometry => "+ joint offsets and origins (full geometry)",
        }
    }
}

impl fmt::Display for ChainStage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.words())
    }
}

impl Serialize for ChainStage {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.words())
    }
}

/// What the chain calibration says of temperatures: it tries no thermal
/// effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChainThermal {
    /// Temperatures in the data, but only the geometry calibrated here.
    NotTried,
    /// No temperatures: time is only an order.
    NoTemperatures,
}

impl ChainThermal {
    pub fn words(self) -> &'static str {
        match self {
            ChainThermal::NotTried => "The data have temperatures, but this is the geometric calibration only: no thermal effect was tried here (the effect diagnosis tries every effect on this chain).",
            ChainThermal::NoTemperatures => "The data have no temperatures (time is only an order): no thermal effect can be named.",
        }
    }
}

impl Serialize for ChainThermal {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.words())
    }
}

/// The sentence naming what the held-out evidence names.
pub fn named_words(named: &[EffectKind]) -> String {
    if named.is_empty() {
        "Named: nothing (the calibration does not beat the rigid frame on held-out poses).".into()
    } else {
        let names: Vec<&str> = named.iter().map(|k| k.name()).collect();
        format!("Named: {}.", names.join(", "))
    }
}
