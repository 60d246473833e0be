//! Integration tests of the `robot` layer, one binary (one link) for all
//! of them: a test binary per file made the clean build minutes longer.

#[path = "../common/rng.rs"]
mod rng;

mod arms;
mod crosscheck;
mod encoding;
mod frames;
mod ik_chain;
mod ik_conf;
mod kinematics;
mod picks_back;
mod refusals;
mod robustness;
mod straight_down;
mod urdf;
mod urdf_rules;
