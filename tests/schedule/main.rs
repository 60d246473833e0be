//! Integration tests of the `schedule` layer, one binary (one link) for all
//! of them: a test binary per file made the clean build minutes longer.

mod cli;
mod cold_joints;
mod encoding;
mod estimate;
mod lanes;
mod props;
mod settled;
#[path = "../common/ways.rs"]
mod ways;
