//! Whether the arm reaches each flange pose the walk meets, asked on
//! another core while the walk goes on. The walk runs on one core; the
//! question (an IK per pose) was asked of all poses after it, so a
//! program of a million targets waited for it. Now the poses go, a
//! chunk at a time, to a thread that answers them as they come, and what
//! is left when the walk ends is answered on every core.
//!
//! The joints each answer finds for a literal's own pose are kept
//! ([`ColdJoints`]): a correction of the program asks the same IK.

use crate::robot::{Joints, RobConf, Robot};
use crate::schedule::cold_joints::{ColdJoints, Slot};
use nalgebra::Isometry3;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex};

/// A flange pose, the robconf of its target and, for a literal's own
/// pose, the target's number and the number of the pair of tool and work
/// object it was moved in (from 1; 0: not a literal's own pose).
pub(crate) type Pose = (Isometry3<f64>, RobConf, u32, u32);

/// Poses sent at a time: 80 kB, below the size the allocator maps fresh
/// from the system (128 kB, `src/main.rs`), so that an answered chunk's
/// memory holds the next one (chunks of 4,096 were a page fault every
/// 57 poses, a sixth of the walk's own time).
const CHUNK: usize = 1024;

/// The poses a walk leaves to another thread.
pub(crate) struct ReachAhead {
    chunk: Vec<Pose>,
    /// Whether the joints found are kept (the thread was given a slot
    /// per robtarget).
    pub(crate) keeps: bool,
    shared: Arc<Shared>,
}

#[derive(Default)]
struct Shared {
    state: Mutex<State>,
    changed: Condvar,
}

#[derive(Default)]
struct State {
    chunks: VecDeque<Vec<Pose>>,
    /// No chunk will come.
    done: bool,
    /// A pose was found out of reach.
    unreachable: bool,
    /// The joints the thread found, given back when it ends.
    found: Option<Vec<Slot>>,
}

/// Whether the arm reaches `flange` (in the robconf `conf`, else in any),
/// and the joints with `conf` where found so.
fn answer(robot: &Robot, (flange, conf, ..): &Pose) -> (bool, Option<Joints>) {
    match robot.joints_with(flange, conf) {
        Some(q) => (true, Some(q)),
        None => (robot.ik(flange).is_ok_and(|s| !s.is_empty()), None),
    }
}

/// [`answer`], its joints kept in `found` where the pose is a literal's.
fn answer_keeping(robot: &Robot, pose: &Pose, found: &mut [Slot]) -> bool {
    let (ok, q) = answer(robot, pose);
    keep(found, pose, q.as_ref());
    ok
}

/// `q`, found for `pose`, kept in `found` where the pose is a literal's.
fn keep(found: &mut [Slot], (_, _, index, pair): &Pose, q: Option<&Joints>) {
    if let (Some(q), 1..) = (q, pair) {
        ColdJoints::keep(found, *index, *pair, q);
    }
}

impl ReachAhead {
    /// Poses answered on a thread of `scope` as they are sent, the joints
    /// found for literals kept in `found` (one slot per robtarget).
    pub(crate) fn start<'s, 'e>(
        scope: &'s std::thread::Scope<'s, 'e>,
        robot: &'e Robot,
        found: Vec<Slot>,
    ) -> ReachAhead {
        let shared = Arc::new(Shared::default());
        let theirs = shared.clone();
        let keeps = !found.is_empty();
        scope.spawn(move || answer_as_sent(&theirs, robot, found));
        ReachAhead {
            chunk: Vec::with_capacity(CHUNK),
            keeps,
            shared,
        }
    }

    pub(crate) fn push(&mut self, pose: Pose) {
        self.chunk.push(pose);
        if self.chunk.len() == CHUNK {
            let full = std::mem::replace(&mut self.chunk, Vec::with_capacity(CHUNK));
            if let Ok(mut st) = self.shared.state.lock() {
                st.chunks.push_back(full);
            }
            self.shared.changed.notify_all();
        }
    }

    /// Whether every pose pushed is reached: those not yet answered are
    /// answered on every core, and the thread's end awaited. `false` also
    /// where the answers were lost (the walk is then taken again asking
    /// at each move, which finds the same). With it, the joints found
    /// (`None` where lost).
    pub(crate) fn finish(mut self, robot: &Robot) -> (bool, Option<Vec<Slot>>) {
        let mut rest = vec![std::mem::take(&mut self.chunk)];
        match self.shared.state.lock() {
            Ok(mut st) => {
                st.done = true;
                rest.extend(st.chunks.drain(..));
            }
            Err(_) => return (false, None),
        }
        self.shared.changed.notify_all();
        let answers: Vec<(bool, Option<Joints>)> = rest
            .par_iter()
            .flatten()
            .map(|p| answer(robot, p))
            .collect();
        let Ok(mut st) = self.shared.state.lock() else {
            return (false, None);
        };
        while st.found.is_none() {
            st = match self.shared.changed.wait(st) {
                Ok(st) => st,
                Err(_) => return (false, None),
            };
        }
        let mut found = st.found.take();
        if let Some(slots) = &mut found {
            for (pose, (_, q)) in rest.iter().flatten().zip(&answers) {
                keep(slots, pose, q.as_ref());
            }
        }
        (answers.iter().all(|a| a.0) && !st.unreachable, found)
    }
}

/// A walk that ends early (an error) ends the thread too.
impl Drop for ReachAhead {
    fn drop(&mut self) {
        if let Ok(mut st) = self.shared.state.lock() {
            st.done = true;
        }
        self.shared.changed.notify_all();
    }
}

/// The thread: each chunk answered as it comes, until no more will; then
/// the joints found given back.
fn answer_as_sent(shared: &Shared, robot: &Robot, mut found: Vec<Slot>) {
    loop {
        let chunk = {
            let Ok(mut st) = shared.state.lock() else {
                return;
            };
            loop {
                if let Some(c) = st.chunks.pop_front() {
                    break c;
                }
                if st.done {
                    st.found = Some(std::mem::take(&mut found));
                    drop(st);
                    shared.changed.notify_all();
                    return;
                }
                st = match shared.changed.wait(st) {
                    Ok(st) => st,
                    Err(_) => return,
                };
            }
        };
        let ok = chunk.iter().all(|p| answer_keeping(robot, p, &mut found));
        if let Ok(mut st) = shared.state.lock() {
            st.unreachable |= !ok;
        }
    }
}
