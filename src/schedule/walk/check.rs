//! Whether a move's target can be reached at all, checked before the move
//! is timed: a target that is not finite, out of reach, or (a jointtarget)
//! outside the joint limits would be timed as NaN or nonsense. Each such
//! target is recorded once ([`Walker::errors`]) and its move skipped, so
//! that the walk finds them all and the estimate lists them together.
//! Reach is the costly question (an IK per pose): a first walk defers it
//! ([`Walker::deferred`]) to be asked on another core as it goes, and only when
//! a pose is out of reach is the walk taken again asking at each move.

use super::value::Rob;
use super::walker::{Frame, Walker};
use crate::error::{Error, ErrorKind};
use crate::rapid::{Call, Statement};
use crate::robot::describe_violation;
use crate::robot::{Joints, ToolFrame, WobjFrames};
use crate::schedule::cold_joints::same_frames;
use nalgebra::Isometry3;
use std::rc::Rc;

/// Flange poses remembered as reachable (a target in a loop is checked
/// once); beyond this many, each further pose is checked at every move
/// (about 1 µs) rather than held in memory.
const REACHABLE_CACHE: usize = 65_536;

/// Pairs of tool and work object whose poses' joints are kept: each move
/// looks its pair up among them.
const PAIRS: usize = 64;

impl<'p> Walker<'p> {
    /// Record a target that cannot be timed (once per place).
    pub(super) fn fail_target(&mut self, e: Error) {
        let key = e
            .location
            .as_ref()
            .map(|l| format!("{}:{}:{}", l.file, l.line, l.col))
            .unwrap_or_else(|| e.message.clone());
        if self.failed.insert(key) {
            self.errors.push(e);
        }
    }

    /// A robtarget the robot can reach (its pose finite, its flange pose
    /// with a solution within the joint limits; `frames`: the tool and
    /// work object that placed the flange); otherwise recorded, and
    /// `false`. A MoveJ's configuration is chosen later ([`Walker::joint_goal`]).
    pub(super) fn check_rob(
        &mut self,
        rob: &Rob,
        (flange, frames): (&Isometry3<f64>, &Rc<(ToolFrame, WobjFrames)>),
        call: &Call,
        frame: &Frame,
        s: &Statement,
    ) -> bool {
        let t = rob.pose.translation.vector;
        let q = rob.pose.rotation.coords;
        if !(t.iter().chain(q.iter()).all(|v| v.is_finite())) {
            let e = self.target_error(
                rob,
                call,
                frame,
                s,
                ErrorKind::Input,
                format!(
                    "not a finite pose: [[{},{},{}],[{},{},{},{}]]",
                    t.x, t.y, t.z, q.w, q.x, q.y, q.z
                ),
            );
            self.fail_target(e);
            return false;
        }
        let key: [u64; 7] = {
            let v = flange.translation.vector;
            let r = flange.rotation.coords;
            [v.x, v.y, v.z, r.w, r.x, r.y, r.z].map(f64::to_bits)
        };
        // A walk that defers the question keeps no answers: nothing to
        // hash the pose for.
        if !self.reachable.is_empty() && self.reachable.contains(&key) {
            return true;
        }
        if let Some(keeps) = self.deferred.as_ref().map(|d| d.keeps) {
            let (index, pair) = if keeps {
                self.literal_pair(rob, frames)
            } else {
                (0, 0)
            };
            if let Some(poses) = &mut self.deferred {
                poses.push((*flange, rob.conf, index, pair));
            }
            return true;
        }
        // Most targets are reached with their own robconf: found so, a
        // solution is found at a third of the cost of them all.
        if self.robot.reaches_with(flange, &rob.conf) {
            if self.reachable.len() < REACHABLE_CACHE {
                self.reachable.insert(key);
            }
            return true;
        }
        let why = match self.robot.ik(flange) {
            Ok(sols) if !sols.is_empty() => {
                if self.reachable.len() < REACHABLE_CACHE {
                    self.reachable.insert(key);
                }
                return true;
            }
            Ok(_) => Error::new(
                ErrorKind::Unreachable,
                "no solution within the joint limits",
            ),
            Err(e) => e,
        };
        let e = self.unreachable(rob, call, frame, s, why);
        self.fail_target(e);
        false
    }

    /// For a literal's own pose and robconf, its number and the number
    /// (from 1) of the pair `frames` among those the walk moved in: what
    /// the joints found for it are kept under ([`crate::schedule::ColdJoints`]).
    /// `(0, 0)` for any other pose (derived, assigned, read at the move).
    fn literal_pair(&mut self, rob: &Rob, frames: &Rc<(ToolFrame, WobjFrames)>) -> (u32, u32) {
        // A value with a literal's number is that literal's pose and
        // robconf, as read (values are never changed in place).
        let literal = rob
            .id
            .filter(|_| rob.derived.is_none() && rob.bases.is_empty());
        let Some(index) = literal.and_then(|i| u32::try_from(i).ok()) else {
            return (0, 0);
        };
        // Mostly the very frames of the last move (a loop's move keeps
        // them): known by address, with no comparison of their values
        // (which cost what the joints kept saved).
        if let Some((last, pair)) = &self.last_pair {
            if Rc::ptr_eq(last, frames) {
                return (index, *pair);
            }
        }
        // A program moves in few pairs; one that moves in more than
        // [`PAIRS`] keeps the joints of the first ones only (the rest
        // are solved again, as before).
        let k = match self
            .pairs
            .iter()
            .position(|p| same_frames(p, (&frames.0, &frames.1)))
        {
            Some(k) => k,
            None if self.pairs.len() < PAIRS => {
                self.pairs.push((**frames).clone());
                self.pairs.len() - 1
            }
            None => return (0, 0),
        };
        // Below [`PAIRS`]: a number from 1 that fits.
        let pair = k as u32 + 1;
        self.last_pair = Some((frames.clone(), pair));
        (index, pair)
    }

    /// A jointtarget within the joint limits (taken literally, as the
    /// controller takes them); otherwise recorded, and `false`.
    pub(super) fn check_joints(
        &mut self,
        q: &Joints,
        id: Option<usize>,
        call: &Call,
        frame: &Frame,
        s: &Statement,
    ) -> bool {
        let outside = self.robot.outside_limits(q);
        if outside.is_empty() {
            return true;
        }
        let jt = id.and_then(|i| self.program.jointtargets().get(i));
        let name = jt.map_or("(computed)", |j| j.id.as_str());
        let words: Vec<String> = outside.iter().map(describe_violation).collect();
        let e = Error::new(
            ErrorKind::Unreachable,
            format!(
                "jointtarget {name} ({} at line {}): {}",
                call.name,
                s.pos.line,
                words.join("; ")
            ),
        );
        let e = match jt {
            Some(j) => e.at(self.program.location(&j.origin)),
            None => e.at(self.location(frame, s)),
        };
        self.fail_target(e);
        false
    }

    /// An error about a robtarget, at its declaration (or the statement,
    /// for a computed one).
    fn target_error(
        &self,
        rob: &Rob,
        call: &Call,
        frame: &Frame,
        s: &Statement,
        kind: ErrorKind,
        what: String,
    ) -> Error {
        let mut e = self.unreachable(rob, call, frame, s, Error::new(kind, what));
        e.kind = kind;
        e
    }
}
