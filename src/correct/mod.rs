//! Correcting a program for thermal drift: for each target, the
//! coordinates that make the warm robot reach what the cold program meant;
//! and the target-by-target comparison of two programs.

pub mod diff;
pub mod frames;
