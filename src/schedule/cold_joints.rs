//! The cold joints a walk found for the robtargets it moved to.
//!
//! A walk asks, on another core, whether the arm reaches each target it
//! moves to: an IK with the target's robconf. A correction of the same
//! program asks the very same IK of every target again (its cold joints)
//! on the cores it shares with nothing. Kept here, the answers spare it
//! that: a `--start` run of a million targets solved each twice.
//!
//! An answer is kept only for a literal's own pose and robconf, with the
//! tool and work object of the move; it is given back only for the same
//! program, target, tool and work object (compared to the bit), so it is
//! what the IK would give: the one computation, done once.

use crate::rapid::Program;
use crate::robot::frames::{ToolFrame, WobjFrames};
use crate::robot::Joints;
use nalgebra::Isometry3;

/// Each robtarget's cold joints, where the walk found them.
#[derive(Default)]
pub struct ColdJoints {
    /// The program it was found for (its address) and its count of
    /// robtargets: it fits only that program.
    program: usize,
    /// The tool and work object of each pair the walk moved in, by
    /// number from 1.
    pairs: Vec<(ToolFrame, WobjFrames)>,
    /// Per robtarget, by number: its joints and its pair's number (as a
    /// float; 0: none found). Zeros for every target at first, so that a
    /// program's targets the walk never reaches cost no memory.
    entries: Vec<Slot>,
}

/// Whether two pairs of tool and work object are the same to the bit: a
/// flange placed by one is the flange placed by the other. (`==` takes a
/// quaternion and its negative as equal, and costs more than the IK it
/// spares where a million targets ask.)
pub(crate) fn same_frames(
    a: &(ToolFrame, WobjFrames),
    (tool, wobj): (&ToolFrame, &WobjFrames),
) -> bool {
    let (t, w) = a;
    t.robhold == tool.robhold
        && same_pose(&t.tframe, &tool.tframe)
        && w.robhold == wobj.robhold
        && w.ufprog == wobj.ufprog
        && same_pose(&w.uframe, &wobj.uframe)
        && same_pose(&w.oframe, &wobj.oframe)
        && w.ufmec.as_bytes().iter().eq(wobj.ufmec.as_bytes())
}

fn same_pose(a: &Isometry3<f64>, b: &Isometry3<f64>) -> bool {
    let bits = |p: &Isometry3<f64>| {
        let (v, q) = (p.translation.vector, p.rotation.coords);
        [v.x, v.y, v.z, q.x, q.y, q.z, q.w].map(f64::to_bits)
    };
    bits(a) == bits(b)
}

/// One robtarget's joints and the number of the pair they were found in.
pub(crate) type Slot = [f64; 7];

impl ColdJoints {
    /// Room for each of `program`'s robtargets, none found yet.
    pub(crate) fn slots(program: &Program) -> Vec<Slot> {
        // `vec!` of zeros asks the allocator for zeroed pages: the pages
        // of targets never moved to are never touched.
        vec![[0.0; 7]; program.targets().len()]
    }

    /// Keep `q`, found for target `index` in pair `pair` (from 1), in
    /// `slots`.
    pub(crate) fn keep(slots: &mut [Slot], index: u32, pair: u32, q: &Joints) {
        if let Some(s) = slots.get_mut(index as usize) {
            s[..6].copy_from_slice(q);
            s[6] = f64::from(pair);
        }
    }

    pub(crate) fn new(
        program: &Program,
        pairs: Vec<(ToolFrame, WobjFrames)>,
        entries: Vec<Slot>,
    ) -> ColdJoints {
        ColdJoints {
            program: std::ptr::from_ref(program) as usize,
            pairs,
            entries,
        }
    }

    /// Whether it was found for `program` (the very one, not a copy).
    pub fn fits(&self, program: &Program) -> bool {
        self.program == std::ptr::from_ref(program) as usize
            && self.entries.len() == program.targets().len()
    }

    /// Target `index`'s cold joints with robconf of its literal, flange
    /// placed by `tool` and `wobj`, where the walk found them in that
    /// very pair.
    pub fn joints(&self, index: usize, tool: &ToolFrame, wobj: &WobjFrames) -> Option<Joints> {
        let s = self.entries.get(index)?;
        let pair = s[6] as usize;
        let found = self.pairs.get(pair.checked_sub(1)?)?;
        same_frames(found, (tool, wobj)).then(|| std::array::from_fn(|i| s[i]))
    }

    /// The same, each joint found turned by a thousandth of a radian:
    /// what a test gives a run to see that it takes them.
    #[cfg(test)]
    pub(crate) fn shifted(mut self) -> ColdJoints {
        for s in self.entries.iter_mut().filter(|s| s[6] != 0.0) {
            s[0] += 1e-3;
        }
        self
    }

    /// How many targets have joints.
    pub fn found(&self) -> usize {
        self.entries.iter().filter(|s| s[6] != 0.0).count()
    }
}
