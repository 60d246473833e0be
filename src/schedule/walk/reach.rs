//! Whether the arm reaches each flange pose the walk meets, asked on
//! another core while the walk goes on. The walk runs on one core; the
//! question (an IK per pose) was asked of all poses after it, so a
//! program of a million targets waited for it. Now the poses go, a
//! chunk at a time, to a thread that answers them as they come, and what
//! is left when the walk ends is answered on every core.

use crate::robot::{RobConf, Robot};
use nalgebra::Isometry3;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex};

/// A flange pose and the robconf of its target.
type Pose = (Isometry3<f64>, RobConf);

/// Poses sent at a time: 72 kB, below the size the allocator maps fresh
/// from the system (128 kB, `src/main.rs`), so that an answered chunk's
/// memory holds the next one (chunks of 4,096 were a page fault every
/// 57 poses, a sixth of the walk's own time).
const CHUNK: usize = 1024;

/// The poses a walk leaves to another thread.
pub(crate) struct ReachAhead {
    chunk: Vec<Pose>,
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
    /// Chunks taken by the thread and not yet answered.
    checking: usize,
}

/// Whether the arm reaches `flange` (in the robconf `conf`, else in any).
pub(crate) fn reaches(robot: &Robot, (flange, conf): &Pose) -> bool {
    robot.reaches_with(flange, conf) || robot.ik(flange).is_ok_and(|s| !s.is_empty())
}

impl ReachAhead {
    /// Poses answered on a thread of `scope` as they are sent.
    pub(crate) fn start<'s, 'e>(
        scope: &'s std::thread::Scope<'s, 'e>,
        robot: &'e Robot,
    ) -> ReachAhead {
        let shared = Arc::new(Shared::default());
        let theirs = shared.clone();
        scope.spawn(move || answer_as_sent(&theirs, robot));
        ReachAhead {
            chunk: Vec::with_capacity(CHUNK),
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
    /// answered on every core, and the thread's last chunk awaited.
    /// `false` also where the answers were lost (the walk is then taken
    /// again asking at each move, which finds the same).
    pub(crate) fn finish(mut self, robot: &Robot) -> bool {
        let mut rest = vec![std::mem::take(&mut self.chunk)];
        match self.shared.state.lock() {
            Ok(mut st) => {
                st.done = true;
                rest.extend(st.chunks.drain(..));
            }
            Err(_) => return false,
        }
        self.shared.changed.notify_all();
        let ours = rest.par_iter().flatten().all(|p| reaches(robot, p));
        let Ok(mut st) = self.shared.state.lock() else {
            return false;
        };
        while st.checking > 0 {
            st = match self.shared.changed.wait(st) {
                Ok(st) => st,
                Err(_) => return false,
            };
        }
        ours && !st.unreachable
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

/// The thread: each chunk answered as it comes, until no more will.
fn answer_as_sent(shared: &Shared, robot: &Robot) {
    loop {
        let chunk = {
            let Ok(mut st) = shared.state.lock() else {
                return;
            };
            loop {
                if let Some(c) = st.chunks.pop_front() {
                    st.checking += 1;
                    break c;
                }
                if st.done {
                    return;
                }
                st = match shared.changed.wait(st) {
                    Ok(st) => st,
                    Err(_) => return,
                };
            }
        };
        let ok = chunk.iter().all(|p| reaches(robot, p));
        if let Ok(mut st) = shared.state.lock() {
            st.checking -= 1;
            st.unreachable |= !ok;
        }
        shared.changed.notify_all();
    }
}
