//! Each robtarget's pose and robconf, read before the walk on every core.

use crate::rapid::Program;
use crate::resolve::robconf_of;
use crate::robot::frames::pose_from_rapid;
use crate::robot::RobConf;
use nalgebra::Isometry3;

/// The pose and robconf of each of a program's robtargets, by number:
/// `None` where it has no numbers or they do not make a pose (the walk
/// reads those itself, and says what is wrong where a move reaches one).
/// A walk read each literal as it met it, on one core: a tenth of timing
/// a program of a million targets.
#[derive(Default)]
pub struct TargetPoses(Vec<Option<(Isometry3<f64>, RobConf)>>);

impl TargetPoses {
    /// Every robtarget of `program` read, a chunk at a time on every core:
    /// its numbers alone, made into a pose and robconf as
    /// [`crate::resolve::target_pose`] makes them (making each whole
    /// target, identifier and place, for this was a third of the read).
    pub fn read(program: &Program) -> TargetPoses {
        use rayon::prelude::*;
        let targets = program.targets();
        let poses = (0..targets.len())
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| {
                let v = targets.pose(i)?;
                let pose = pose_from_rapid(v.trans, v.rot).ok()?;
                let conf = robconf_of(v.robconf).ok()?;
                Some((pose, conf))
            })
            .collect();
        TargetPoses(poses)
    }

    /// Target `i`'s pose and robconf, where read.
    pub(super) fn get(&self, i: usize) -> Option<(Isometry3<f64>, RobConf)> {
        self.0.get(i).copied().flatten()
    }
}
