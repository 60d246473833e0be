//! Diagnosis of the sim-to-real gap.
