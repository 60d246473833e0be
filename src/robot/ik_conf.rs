//! IK for one robconf, the main job's call: the solution of the requested
//! arm branch and quadrants, or the nearest within
//! [`super::ik::CONF_TOLERANCE`] (a target taught on a quadrant boundary,
//! its axis a rounding error outside), computed directly, with the
//! enumeration of every solution ([`OpwArm::solve_conf_by_enumeration`])
//! as the fallback that decides everything the direct path does not (the
//! shoulder singularity's search, errors) and as the reference the direct
//! path is tested against (`tests/robot/ik_conf.rs`).

use super::conf::{quadrant, quadrant_distance, quadrant_range, CfxBits, RobConf};
use super::ik::{
    cfx_bits, pick_conf, ArmAngles, IkFailure, Limits, OpwArm, Solution, Solutions, CONF_TOLERANCE,
    LIMIT_EPS, MAX_SOLUTIONS,
};
use super::Joints;
use nalgebra::Isometry3;
use std::f64::consts::TAU;

impl OpwArm {
    /// The solution with robconf `want` (see [`pick_conf`]), or `Ok(None)`
    /// when none has it. The same solution as
    /// [`OpwArm::solve_conf_by_enumeration`], computed from the requested
    /// arm branch alone when one has it exactly.
    pub fn solve_conf(
        &self,
        pose: &Isometry3<f64>,
        limits: &Limits,
        want: &RobConf,
    ) -> Result<Option<Solution>, IkFailure> {
        if let Some(s) = self.solve_conf_direct(pose, limits, want) {
            return Ok(Some(s));
        }
        Ok(self.solve_conf_by_enumeration(pose, limits, want)?.0)
    }

    /// What the enumeration picks, computed from the arm branches with the
    /// requested cfx arm bits alone: the first solution with exactly
    /// robconf `want` (the first turn of each axis within the limits that
    /// lands in the requested quadrant, axes 1, 4, 6, or sign, axis 5);
    /// without one, the nearest within [`super::ik::CONF_TOLERANCE`]
    /// (the first of equals in the enumeration's order). None where the
    /// enumeration must decide: no solution near enough, the shoulder
    /// singularity (its search over cf1's quadrant), more near matches
    /// than its buffer holds, errors. So this never answers differently
    /// from [`OpwArm::solve_conf_by_enumeration`].
    #[doc(hidden)]
    pub fn solve_conf_direct(
        &self,
        pose: &Isometry3<f64>,
        limits: &Limits,
        want: &RobConf,
    ) -> Option<Solution> {
        let bits = CfxBits::from_cfx(want.cfx)?;
        // The same hint for θ1 at the shoulder singularity as the
        // enumeration's first pass, so the same solution where it has one.
        let (lo, hi) = quadrant_range(want.cf1);
        let q1_hint = 0.5 * (lo + hi);
        let rot = (pose.rotation * self.tip.inverse()).to_rotation_matrix();
        let r = rot.matrix();
        let p = pose.translation.vector;
        let theta1_hint = self.signs[0] * q1_hint + self.offsets[0];
        let (arms, _, singular) = self
            .geom
            .arm_angles(r, &p, theta1_hint, Some(bits.behind_axis1));
        let mut near = Near::default();
        for arm in arms.iter().filter(|a| a.valid()) {
            // Both branches of an arm solution share its cfx arm bits.
            let arm_bits = cfx_bits(arm.forward, arm.side, 0.0);
            if arm_bits.behind_axis1 != bits.behind_axis1
                || arm_bits.behind_lower_arm != bits.behind_lower_arm
            {
                continue;
            }
            let sc1 = arm.t1.sin_cos();
            for (theta, wrist) in self.geom.wrists(r, arm, sc1).into_iter().flatten() {
                let q = self.branch_q(&theta, wrist, Some(want));
                if let Some(q) = exact_turns(&q, limits, want, bits.axis5_negative) {
                    return Some(Solution { q, conf: *want });
                }
                if !singular {
                    near.consider(&q, limits, want, bits.axis5_negative, arm);
                }
            }
        }
        near.best.filter(|_| near.kept <= MAX_SOLUTIONS)
    }

    /// The enumerate-and-pick search: every solution near `want` (all
    /// branches, all turns within the limits), then [`pick_conf`]; at the
    /// shoulder singularity q1 is free: the middle of the cf1 quadrant
    /// first, then points across the quadrant until the wrist quadrants
    /// match too. Without a match, `Ok(None)` with all solutions (for the
    /// error's list of configurations). The reference of
    /// [`OpwArm::solve_conf`], and its fallback.
    #[doc(hidden)]
    pub fn solve_conf_by_enumeration(
        &self,
        pose: &Isometry3<f64>,
        limits: &Limits,
        want: &RobConf,
    ) -> Result<(Option<Solution>, Solutions), IkFailure> {
        // Only near matches are kept while searching: an arm with wide
        // limits has more turns than the buffer holds.
        let (lo, hi) = quadrant_range(want.cf1);
        let mid = 0.5 * (lo + hi);
        let mut sols = Solutions::default();
        let singular = self.solve_hinted(pose, limits, Some(want), mid, &mut sols, true)?;
        let first = pick_conf(&sols, want);
        if let Some(s) = first {
            if s.conf == *want || !singular {
                return Ok((Some(s), sols));
            }
        }
        if singular {
            const STEPS: i32 = 18;
            for i in 0..STEPS {
                let hint = lo + (hi - lo) * (f64::from(i) + 0.5) / f64::from(STEPS);
                sols.clear();
                if self
                    .solve_hinted(pose, limits, Some(want), hint, &mut sols, true)
                    .is_ok()
                {
                    if let Some(s) = sols.iter().find(|s| s.conf == *want) {
                        return Ok((Some(*s), sols));
                    }
                }
            }
        }
        if first.is_some() {
            return Ok((first, sols));
        }
        // None: all solutions, for the message.
        sols.clear();
        self.solve_hinted(pose, limits, Some(want), mid, &mut sols, false)?;
        Ok((None, sols))
    }
}

/// Clearances under which [`OpwArm::picks_back`] answers without solving:
/// a thousand times and more what a round trip through FK and IK loses
/// (1e-12 mm, 1e-13 rad), and small enough that a taught target almost
/// never comes as near to a boundary.
const CLEAR_RAD: f64 = 1e-7;
const CLEAR_MM: f64 = 1e-2;
/// |sin θ5| below which the wrist is left to the solve: the split of q4
/// and q6 loses digits as 1/sin θ5.
const CLEAR_WRIST: f64 = 1e-3;
/// How far from a quadrant boundary an axis counts as on it: far below
/// [`CONF_TOLERANCE`], far above a round trip's error.
const ON_BOUNDARY_RAD: f64 = 1e-10;

impl OpwArm {
    /// Whether [`OpwArm::solve_conf`] of this arm's own flange pose of `q`
    /// with robconf `want` certainly gives `q` back (to well below 1e-9
    /// rad), told without solving: `q` has robconf `want` (axes 1, 4 and 6
    /// in its quadrants, or a rounding error off one of their boundaries),
    /// and lies clear of everything that could make the pick go elsewhere (the
    /// quadrant boundaries of axes 1, 4 and 6, axis 5's sign and the wrist
    /// singularity, the shoulder and elbow singularities where two arm
    /// branches meet, the joint limits and another turn of an axis within
    /// them). `false` says nothing: solve to know. The main job checks
    /// every corrected target this way before solving it again
    /// (`tests/robot/picks_back.rs` holds `true` to the solve).
    pub fn picks_back(&self, q: &Joints, limits: &Limits, want: &RobConf) -> bool {
        use std::f64::consts::PI;
        let Some(bits) = CfxBits::from_cfx(want.cfx) else {
            return false;
        };
        let t = self.theta_of(q);
        let (forward, side) = self.geom.cfx_geometry(&t);
        if forward.abs() < CLEAR_MM || side.abs() < CLEAR_MM || t[4].sin().abs() < CLEAR_WRIST {
            return false;
        }
        if cfx_bits(forward, side, q[4]) != bits || q[4].abs() < CLEAR_RAD {
            return false;
        }
        // Clear inside the wanted quadrant, or a rounding error from one of
        // its boundaries (a target taught with the axis at 0°): either side
        // of it, the solve answers with this branch (an exact or a near
        // match), as no other branch has the same arm bits and axis 5's
        // sign.
        let fits = |v: f64, cf: i32| {
            let (lo, hi) = quadrant_range(cf);
            (v > lo + CLEAR_RAD && v < hi - CLEAR_RAD)
                || (v - lo).abs() <= ON_BOUNDARY_RAD
                || (v - hi).abs() <= ON_BOUNDARY_RAD
        };
        if !(fits(q[0], want.cf1) && fits(q[3], want.cf4) && fits(q[5], want.cf6)) {
            return false;
        }
        q.iter()
            .zip(limits)
            .enumerate()
            .all(|(j, (&v, &(lo, hi)))| {
                // The solve finds an axis within ±2 turns of its wrapped angle;
                // axes 2, 3 and 5 take their first turn within the limits
                // (axes 1, 4 and 6 their first in the quadrant, which is q's).
                let first_turn = matches!(j, 0 | 3 | 5) || v - TAU < lo - LIMIT_EPS - CLEAR_RAD;
                v.abs() < 4.9 * PI && v > lo + CLEAR_RAD && v < hi - CLEAR_RAD && first_turn
            })
    }
}

/// The turn of each axis the enumeration would give first for an exact
/// match: the first of q + 2πk (k = −2..2) within the limits (clamped onto
/// them, as the enumeration does) that is in the requested quadrant (axes
/// 1, 4, 6) or has the requested sign (axis 5); axes 2 and 3 take their
/// first turn within the limits. The enumeration's order runs axis 1
/// fastest, so its first exact match is the first such turn of every axis.
#[inline]
fn exact_turns(q: &Joints, limits: &Limits, want: &RobConf, q5_negative: bool) -> Option<Joints> {
    // One call per axis with its own test, each inlined: a closure
    // matching on the axis inside the loop was a twentieth of a streamed
    // correction's time.
    Some([
        first_turn(q[0], limits[0], |v| quadrant(v) == want.cf1)?,
        first_turn(q[1], limits[1], |_| true)?,
        first_turn(q[2], limits[2], |_| true)?,
        first_turn(q[3], limits[3], |v| quadrant(v) == want.cf4)?,
        first_turn(q[4], limits[4], |v| (v < 0.0) == q5_negative)?,
        first_turn(q[5], limits[5], |v| quadrant(v) == want.cf6)?,
    ])
}

/// The first of `v + 2πk` (k = −2..2) within `(lo, hi)` (give or take
/// [`LIMIT_EPS`], clamped onto them) that `fits`.
#[inline(always)]
fn first_turn(v: f64, (lo, hi): (f64, f64), fits: impl Fn(f64) -> bool) -> Option<f64> {
    for k in -2..=2 {
        let t = v + TAU * f64::from(k);
        if t >= lo - LIMIT_EPS && t <= hi + LIMIT_EPS {
            let t = t.clamp(lo, hi);
            if fits(t) {
                return Some(t);
            }
        }
    }
    None
}

/// The nearest of the near matches (no exact one) over the branches seen so
/// far, as [`pick_conf`] finds it among the enumeration's solutions: the
/// mismatch of a combination of turns is the largest of its axes'
/// (quadrant distance of axes 1, 4, 6; |q5| on the wrong side of 0), so
/// the least over a branch's combinations is the largest of each axis's
/// least, and the first combination in the enumeration's order to reach
/// it takes the first turn of each axis within it. `kept`: how many
/// solutions the enumeration keeps (its buffer drops those beyond
/// [`MAX_SOLUTIONS`]).
#[derive(Default)]
struct Near {
    best: Option<Solution>,
    best_d: f64,
    kept: usize,
}

impl Near {
    fn consider(
        &mut self,
        q: &Joints,
        limits: &Limits,
        want: &RobConf,
        q5_negative: bool,
        arm: &ArmAngles,
    ) {
        let mismatch = |j: usize, v: f64| match j {
            0 => quadrant_distance(v, want.cf1),
            3 => quadrant_distance(v, want.cf4),
            4 if (v < 0.0) != q5_negative => v.abs(),
            5 => quadrant_distance(v, want.cf6),
            _ => 0.0,
        };
        // Each axis's turns within the limits (clamped onto them), in the
        // enumeration's order, and their mismatches.
        let mut turns = [[(0.0f64, 0.0f64); 5]; 6];
        let mut counts = [0usize; 6];
        let mut least = 0.0f64;
        let mut kept = 1usize;
        for j in 0..6 {
            let (lo, hi) = limits[j];
            let mut axis_least = f64::INFINITY;
            let mut within = 0;
            for k in -2..=2 {
                let v = q[j] + TAU * f64::from(k);
                if v >= lo - LIMIT_EPS && v <= hi + LIMIT_EPS {
                    let v = v.clamp(lo, hi);
                    let d = mismatch(j, v);
                    turns[j][counts[j]] = (v, d);
                    counts[j] += 1;
                    axis_least = axis_least.min(d);
                    within += usize::from(d <= CONF_TOLERANCE);
                }
            }
            if counts[j] == 0 || within == 0 {
                // Outside the limits in every turn, or no turn near the
                // wanted quadrant: the enumeration keeps nothing of this
                // branch (the flipped wrist of a near match ends here).
                return;
            }
            least = least.max(axis_least);
            kept *= within;
        }
        self.kept += kept;
        // As conf_mismatch: never 0 for a near match.
        let d = least.max(f64::MIN_POSITIVE);
        if d > CONF_TOLERANCE || self.best.is_some_and(|_| d >= self.best_d) {
            return;
        }
        let mut out = [0.0; 6];
        for j in 0..6 {
            out[j] = turns[j][..counts[j]]
                .iter()
                .find(|t| t.1 <= least)
                .map_or(f64::NAN, |t| t.0);
        }
        self.best = Some(Solution {
            q: out,
            conf: RobConf::from_parts(&out, cfx_bits(arm.forward, arm.side, out[4])),
        });
        self.best_d = d;
    }
}
