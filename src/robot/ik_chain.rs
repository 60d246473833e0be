//! Numeric IK for arms without the OPW form (a UR5, ABB's GoFa: no
//! spherical wrist, so no closed form): Levenberg–Marquardt on the
//! flange's 6-D pose error with the chain's geometric Jacobian
//! ([`Chain::axes_scaled`]), from starting points the requested robconf
//! suggests, then the turn of each axis that gives that robconf.
//!
//! Each converged point is a physical solution (every angle modulo 2π).
//! The robconf picks its turns: axes 1, 4 and 6 the one in their
//! quadrant, axis 5 the one of the requested sign (but a turn within
//! [`CONF_TOLERANCE`] of 0 stays there: at the wrist singularity its sign
//! is rounding); axes 2 and 3, which the robconf leaves open, the one
//! nearest 0. When several physical solutions have the robconf (possible
//! without a spherical wrist, and for turns of axes 2 and 3 on an arm
//! whose limits allow them), the answer is the one nearest (Euclidean, in
//! joint space) to the reference point: the middles of the requested
//! quadrants for axes 1, 4 and 6, and 0 for axes 2, 3 and 5; an exact tie
//! goes to the smaller joint vector (axis 1 first). When none has it
//! exactly, the closest within [`CONF_TOLERANCE`] is taken, as the closed
//! form does. The starting points are fixed, so the same pose and robconf
//! always give the same answer.
//!
//! The search runs in rounds, each only when the ones before found no
//! solution with the robconf. The first starts from the quadrant middles
//! of axes 1, 4 and 6, axis 5 at 90° of the requested sign (and of the
//! other sign where a turn of it has the requested one within the
//! limits), and a 3 × 3 grid over axes 2 and 3, taking the starts whose
//! wrist centre lies on the requested sides of axis 1 and of the lower
//! arm (cfx): on a regular pose one of them lands on the requested
//! solution. The second takes the rest of that grid. The third starts
//! from every quarter turn of axis 1, both wrist flips and the whole grid,
//! to find every solution (the error lists their configurations). A start
//! that comes near a solution already found is stopped there.

use super::arm::Robot;
use super::chain::{conf_of_axes, Chain};
use super::conf::{quadrant, quadrant_distance, quadrant_range, CfxBits, RobConf};
use super::ik::{
    wrap, DroppedBranch, IkFailure, Limits, Solution, Solutions, Violation, CONF_TOLERANCE,
    LIMIT_EPS, MAX_SOLUTIONS,
};
use super::{Joints, LinkScales};
use crate::error::{Error, ErrorKind, Result};
use nalgebra::{Isometry3, Matrix6, UnitQuaternion, Vector3, Vector6};
use std::collections::BTreeSet;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// A start has converged when the flange is this close to the pose (mm)
/// and turned this little from it (rad).
const CONVERGED_MM: f64 = 1e-10;
const CONVERGED_RAD: f64 = 1e-13;
/// What an answer promises (mm, rad): a start whose steps no longer
/// improve the pose (rounding) counts as converged within these.
pub const TOLERANCE_MM: f64 = 1e-9;
pub const TOLERANCE_RAD: f64 = 1e-12;
/// Steps per start: a start that has not converged by then is given up.
const MAX_STEPS: usize = 60;
/// The largest change of any axis in one step (rad): a long step out of a
/// poorly conditioned start jumps into another solution's basin.
const MAX_STEP_RAD: f64 = 0.5;
/// Two converged points closer than this (rad, every axis, modulo 2π) are
/// one solution.
const SAME_RAD: f64 = 1e-6;
/// A start this close (rad, every axis) to a solution already found will
/// converge to it: it is stopped.
const MERGE_RAD: f64 = 0.01;
/// A start whose error has not fallen to this fraction in
/// [`STALL_STEPS`] steps is in a local minimum, not near a solution: it
/// is given up.
const STALL_FACTOR: f64 = 0.25;
const STALL_STEPS: usize = 10;
/// Below this weighted squared error (about 1e-6 mm or rad) a step tries
/// Newton's step from the Jacobian first.
const NEWTON_COST: f64 = 1e-12;

impl Robot {
    /// [`Robot::ik_conf`] for an arm without the OPW form (see the module
    /// documentation).
    pub(super) fn chain_solve_conf(
        &self,
        pose: &Isometry3<f64>,
        conf: &RobConf,
        scales: Option<&LinkScales>,
    ) -> Result<Joints> {
        check_finite(pose, scales)?;
        let mut search =
            Search::new(&self.chain, scales, pose).map_err(|how| self.out_of_reach(&how))?;
        let reference = reference(conf);
        if let Some(bits) = CfxBits::from_cfx(conf.cfx) {
            let (likely, rest) = search.first_round(&self.limits, &reference, bits);
            let mut rounds = [likely, rest, Vec::new()];
            for i in 0..rounds.len() {
                if i == 2 {
                    // Built only when needed: most poses end above.
                    let [likely, rest, _] = &rounds;
                    rounds[2] = full_round(&self.limits, &reference)
                        .into_iter()
                        .filter(|s| !likely.contains(s) && !rest.contains(s))
                        .collect();
                }
                search.run(&rounds[i]);
                if let Some(q) = search.pick(&self.limits, conf, &reference, false) {
                    return Ok(q);
                }
            }
            // As the closed form: a joint a little outside its quadrant,
            // or axis 5 a little on the other side of 0, when nothing has
            // the robconf exactly.
            if let Some(q) = search.pick(&self.limits, conf, &reference, true) {
                return Ok(q);
            }
        }
        let have = search.reachable_confs(&self.limits);
        if have.is_empty() {
            return Err(self.chain_failure(&search));
        }
        let list: Vec<String> = have.iter().map(RobConf::to_string).collect();
        Err(Error::new(
            ErrorKind::Unreachable,
            format!("no solution with robconf {conf} within the joint limits"),
        )
        .with_note(format!("reachable configurations: {}", list.join(" "))))
    }

    /// [`Robot::ik`] for an arm without the OPW form: every solution the
    /// full search finds, each physical solution with every turn of its
    /// axes within the limits (the turns nearest 0 of every solution
    /// first, so that a full buffer drops turns, not solutions).
    pub(super) fn chain_solve(
        &self,
        pose: &Isometry3<f64>,
        scales: Option<&LinkScales>,
    ) -> Result<Solutions> {
        check_finite(pose, scales)?;
        let mut search =
            Search::new(&self.chain, scales, pose).map_err(|how| self.out_of_reach(&how))?;
        let reference = [0.0; 6];
        search.run(&full_round(&self.limits, &reference));
        let mut physical: Vec<(RobConf, Joints)> =
            search.found.iter().map(|s| (search.conf(s), *s)).collect();
        physical.sort_by(|a, b| {
            (a.0.cfx, a.0.cf1, a.0.cf4, a.0.cf6)
                .cmp(&(b.0.cfx, b.0.cf1, b.0.cf4, b.0.cf6))
                .then_with(|| lexical(&a.1, &b.1))
        });
        let mut out = Solutions::default();
        let turns: Vec<[Vec<f64>; 6]> = physical
            .iter()
            .map(|(_, s)| std::array::from_fn(|j| turns(s[j], self.limits[j])))
            .collect();
        // The sides of axis 1 and the lower arm are the same in every turn.
        let with_conf = |arm: &RobConf, q: Joints| {
            let cfx = (arm.cfx & 6) | i32::from(q[4] < 0.0);
            let conf = RobConf::new(quadrant(q[0]), quadrant(q[3]), quadrant(q[5]), cfx);
            Solution { q, conf }
        };
        for ((arm, s), t) in physical.iter().zip(&turns) {
            if t.iter().any(Vec::is_empty) {
                if let Some(violation) = first_violation(s, t, &self.limits) {
                    out.push_dropped(DroppedBranch {
                        q: *s,
                        conf: *arm,
                        violation,
                    });
                }
                continue;
            }
            out.push(with_conf(arm, std::array::from_fn(|j| nearest(&t[j], 0.0))));
        }
        for ((arm, _), t) in physical.iter().zip(&turns) {
            if t.iter().any(Vec::is_empty) {
                continue;
            }
            let near: Joints = std::array::from_fn(|j| nearest(&t[j], 0.0));
            for_each_combination(t, |q| {
                if *q != near && out.len() < MAX_SOLUTIONS {
                    out.push(with_conf(arm, *q));
                }
            });
        }
        if out.is_empty() {
            return Err(self.chain_failure(&search));
        }
        Ok(out)
    }

    /// The error when no solution is within the limits: out of reach when
    /// the search found none at all, else the first axis outside its
    /// limits of each solution found.
    fn chain_failure(&self, search: &Search) -> Error {
        if search.found.is_empty() {
            return self.out_of_reach(&format!(
                "no joint values put the flange at this pose (the numeric IK converged from none of its {} starting points); the arm reaches at most {:.3} mm from its base",
                search.starts, search.reach
            ));
        }
        let mut violations: [Option<Violation>; 8] = [None; 8];
        for (slot, s) in violations.iter_mut().zip(&search.found) {
            let t: [Vec<f64>; 6] = std::array::from_fn(|j| turns(s[j], self.limits[j]));
            *slot = first_violation(s, &t, &self.limits);
        }
        self.failure(IkFailure::JointLimits(Box::new(violations)))
    }
}

/// Refuse non-finite input, as the closed form does.
fn check_finite(pose: &Isometry3<f64>, scales: Option<&LinkScales>) -> Result<()> {
    let numbers = pose
        .translation
        .vector
        .iter()
        .chain(pose.rotation.coords.iter());
    if !numbers.copied().all(f64::is_finite) {
        return Err(Error::input("pose is not finite"));
    }
    match scales {
        Some(s) if s.iter().any(|v| !v.is_finite()) => {
            Err(Error::input("motor temperatures are not finite"))
        }
        _ => Ok(()),
    }
}

/// The point the pick measures from: the middles of the requested
/// quadrants of axes 1, 4 and 6, and 0 for the others.
fn reference(conf: &RobConf) -> Joints {
    let mid = |cf: i32| {
        let (lo, hi) = quadrant_range(cf);
        0.5 * (lo + hi)
    };
    [mid(conf.cf1), 0.0, 0.0, mid(conf.cf4), 0.0, mid(conf.cf6)]
}

/// Three values across an axis's limits, within one turn (rad).
fn grid(limits: (f64, f64)) -> [f64; 3] {
    let (lo, hi) = (limits.0.max(-PI), limits.1.min(PI));
    let (lo, hi) = if lo < hi { (lo, hi) } else { limits };
    std::array::from_fn(|k| lo + (hi - lo) * (k as f64 + 0.5) / 3.0)
}

/// The full search's starts: axis 1 at its reference and every quarter
/// turn from it, axis 4 at its reference and the wrist flip, axis 5 at
/// ±90°, axes 2 and 3 over their grids.
fn full_round(limits: &Limits, reference: &Joints) -> Vec<Joints> {
    let mut out = Vec::with_capacity(144);
    for k1 in [0.0, 1.0, 2.0, -1.0] {
        for q2 in grid(limits[1]) {
            for q3 in grid(limits[2]) {
                for k4 in [0.0, 1.0] {
                    for q5 in [FRAC_PI_2, -FRAC_PI_2] {
                        out.push([
                            wrap(reference[0] + k1 * FRAC_PI_2),
                            q2,
                            q3,
                            wrap(reference[3] + k4 * PI),
                            q5,
                            reference[5],
                        ]);
                    }
                }
            }
        }
    }
    out
}

/// The turns q + 2πk (k = −2..2) of an angle within limits (within
/// [`LIMIT_EPS`], clamped onto them), ascending: as the closed form's.
fn turns(q: f64, (lo, hi): (f64, f64)) -> Vec<f64> {
    (-2..=2)
        .map(|k| q + TAU * f64::from(k))
        .filter(|v| *v >= lo - LIMIT_EPS && *v <= hi + LIMIT_EPS)
        .map(|v| v.clamp(lo, hi))
        .collect()
}

/// The value nearest `to` (the first of a tie); NaN when there is none.
fn nearest(values: &[f64], to: f64) -> f64 {
    values
        .iter()
        .copied()
        .fold(None, |best: Option<f64>, v| match best {
            Some(b) if (b - to).abs() <= (v - to).abs() => Some(b),
            _ => Some(v),
        })
        .unwrap_or(f64::NAN)
}

/// The first axis of a solution with no turn within the limits.
fn first_violation(s: &Joints, turns: &[Vec<f64>; 6], limits: &Limits) -> Option<Violation> {
    (0..6)
        .find(|&j| turns[j].is_empty())
        .map(|j| (j, s[j], limits[j]))
}

/// Every combination of the turns, axis 1 fastest.
fn for_each_combination(turns: &[Vec<f64>; 6], mut f: impl FnMut(&Joints)) {
    let mut idx = [0usize; 6];
    loop {
        let q: Joints = std::array::from_fn(|j| turns[j][idx[j]]);
        f(&q);
        let mut j = 0;
        loop {
            if j == 6 {
                return;
            }
            idx[j] += 1;
            if idx[j] < turns[j].len() {
                break;
            }
            idx[j] = 0;
            j += 1;
        }
    }
}

fn lexical(a: &Joints, b: &Joints) -> std::cmp::Ordering {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        .unwrap_or(std::cmp::Ordering::Equal)
}

/// Whether every axis of `a` is within `tol` of `b`'s, modulo 2π.
fn near(a: &Joints, b: &Joints, tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| wrap(x - y).abs() <= tol)
}

/// The rotation vector (axis × angle, rad) of a unit quaternion, precise
/// for tiny angles (nalgebra's goes through acos of the scalar part, which
/// cannot tell angles below 1e-8 from 0).
fn rotation_vector(r: &UnitQuaternion<f64>) -> Vector3<f64> {
    let (w, v) = (r.w, r.imag());
    let (w, v) = if w < 0.0 { (-w, -v) } else { (w, v) };
    let n = v.norm();
    if n == 0.0 {
        return v;
    }
    v * (2.0 * n.atan2(w) / n)
}

/// One pose's search: the chain (scaled), the pose, the solutions found.
struct Search<'a> {
    chain: &'a Chain,
    scale: LinkScales,
    target: Isometry3<f64>,
    /// How far the flange can be from the base (mm): the sum of the
    /// chain's offsets.
    reach: f64,
    /// Position errors are divided by it (mm) so that a millimetre and a
    /// radian weigh alike at the arm's size.
    length: f64,
    /// Distinct physical solutions, each angle wrapped into [−π, π], in
    /// the order found.
    found: Vec<Joints>,
    /// Starts run so far.
    starts: usize,
}

impl<'a> Search<'a> {
    /// The search, or why the pose is out of reach when it is farther from
    /// the base than the arm stretches.
    fn new(
        chain: &'a Chain,
        scales: Option<&LinkScales>,
        target: &Isometry3<f64>,
    ) -> Result<Search<'a>, String> {
        let scale = scales.copied().unwrap_or([1.0; 4]);
        let (frames, flange) = chain.frames_scaled(&[0.0; 6], &scale);
        // The offset from each frame to the next, scaled, whatever the
        // angles: their sum bounds the reach.
        let mut reach = frames[0].translation.vector.norm();
        for w in frames.windows(2) {
            reach += (w[1].translation.vector - w[0].translation.vector).norm();
        }
        reach += (flange.translation.vector - frames[5].translation.vector).norm();
        let distance = target.translation.vector.norm();
        // Written so that a distance that is not a number is outside.
        let within = distance <= reach * (1.0 + 1e-9) + 1e-6;
        if !within {
            let how = if distance.is_finite() {
                format!("the flange is {distance:.3} mm from the base")
            } else {
                "the flange is too far from the base to measure (a coordinate of astronomic size?)"
                    .to_string()
            };
            return Err(format!("{how}; the arm reaches at most {reach:.3} mm"));
        }
        Ok(Search {
            chain,
            scale,
            target: *target,
            reach,
            length: reach.max(1.0),
            found: Vec::with_capacity(16),
            starts: 0,
        })
    }

    /// robconf of joint angles on this (scaled) chain.
    fn conf(&self, q: &Joints) -> RobConf {
        conf_of_axes(q, &self.chain.axes_scaled(q, &self.scale).0)
    }

    /// The first two rounds' starts (module documentation): those whose wrist
    /// centre is on the requested sides, and the rest of the grid.
    fn first_round(
        &self,
        limits: &Limits,
        reference: &Joints,
        bits: CfxBits,
    ) -> (Vec<Joints>, Vec<Joints>) {
        let sign = if bits.axis5_negative { -1.0 } else { 1.0 };
        // Axis 5 at 90° of the requested sign; and of the other sign too
        // where a turn of it has the requested sign within the limits (an
        // axis 5 of ±360°: its sign then does not tell the wrist flip).
        let (lo, hi) = limits[4];
        let turned = -sign * FRAC_PI_2 + sign * TAU;
        let flips: &[f64] = if turned >= lo && turned <= hi {
            &[1.0, -1.0]
        } else {
            &[1.0]
        };
        let (mut likely, mut rest) = (Vec::with_capacity(18), Vec::with_capacity(18));
        for flip in flips {
            for q2 in grid(limits[1]) {
                for q3 in grid(limits[2]) {
                    let q5 = flip * sign * FRAC_PI_2;
                    let s = [reference[0], q2, q3, reference[3], q5, reference[5]];
                    let got = CfxBits::from_cfx(self.conf(&s).cfx);
                    if got.is_some_and(|g| {
                        g.behind_axis1 == bits.behind_axis1
                            && g.behind_lower_arm == bits.behind_lower_arm
                    }) {
                        likely.push(s);
                    } else {
                        rest.push(s);
                    }
                }
            }
        }
        (likely, rest)
    }

    /// Run every start.
    fn run(&mut self, starts: &[Joints]) {
        for s in starts {
            self.starts += 1;
            if let Some(q) = self.descend(*s) {
                let q = q.map(wrap);
                if !self.found.iter().any(|f| near(f, &q, SAME_RAD)) {
                    self.found.push(q);
                }
            }
        }
    }

    /// The weighted pose error at `q` and the Jacobian of the flange pose.
    fn linearise(&self, q: &Joints) -> (Vector6<f64>, Matrix6<f64>) {
        let (axes, flange) = self.chain.axes_scaled(q, &self.scale);
        let tip = flange.translation.vector;
        let dp = (self.target.translation.vector - tip) / self.length;
        let dr = rotation_vector(&(self.target.rotation * flange.rotation.inverse()));
        let e = Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z);
        let mut jac = Matrix6::zeros();
        for (i, (p, d)) in axes.iter().enumerate() {
            let v = d.cross(&(tip - p)) / self.length;
            jac.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
            jac.fixed_view_mut::<3, 1>(3, i).copy_from(d);
        }
        // The controller's q2 also turns the serial axis 3 on a
        // parallel-arm robot (Chain::coupling).
        let c = self.chain.coupling;
        if c != 0.0 {
            let col3 = jac.column(2).clone_owned();
            jac.column_mut(1).axpy(c, &col3, 1.0);
        }
        (e, jac)
    }

    fn within(&self, e: &Vector6<f64>, mm: f64, rad: f64) -> bool {
        e.fixed_rows::<3>(0).norm() * self.length <= mm && e.fixed_rows::<3>(3).norm() <= rad
    }

    /// Levenberg–Marquardt from `start`: the joints reaching the pose, or
    /// None when it does not converge or comes near a solution already
    /// found. The damping is λ·|e|² (Yamashita and Fukushima): it vanishes
    /// with the error, so the last steps are Gauss–Newton steps and
    /// converge fast even near a singularity, where the Jacobian's
    /// smallest singular value is tiny (a wrist at 1e-9 rad from it).
    fn descend(&self, start: Joints) -> Option<Joints> {
        let mut q = start;
        let (mut e, mut jac) = self.linearise(&q);
        let mut cost = e.norm_squared();
        let mut lambda = 1e-2;
        let mut checkpoint = cost;
        for step in 1..=MAX_STEPS {
            if step % STALL_STEPS == 0 {
                if cost > STALL_FACTOR * checkpoint {
                    break;
                }
                checkpoint = cost;
            }
            if !cost.is_finite() {
                return None;
            }
            if self.within(&e, CONVERGED_MM, CONVERGED_RAD) {
                return Some(q);
            }
            if self.found.iter().any(|f| near(f, &q, MERGE_RAD)) {
                return None;
            }
            let a = jac.tr_mul(&jac);
            let g = jac.tr_mul(&e);
            // Keeps the factorisation defined where A is singular.
            let floor = 1e-20 * (0..6).map(|k| a[(k, k)]).fold(0.0, f64::max);
            let mut improved = false;
            // Close to a solution, the Newton step from J itself first: the
            // normal equations square J's condition, and near a
            // singularity that loses the step's small directions.
            let newton = if cost < NEWTON_COST {
                jac.lu().solve(&e)
            } else {
                None
            };
            // Raise the damping until a step lowers the error.
            for attempt in 0..13 {
                let step = match (attempt, newton) {
                    (0, Some(dq)) => Some(dq),
                    (0, None) => continue,
                    _ => {
                        let mut m = a;
                        let mu = (lambda * cost).max(floor);
                        for k in 0..6 {
                            m[(k, k)] += mu;
                        }
                        m.cholesky().map(|c| c.solve(&g))
                    }
                };
                let Some(mut dq) = step else {
                    lambda *= 100.0;
                    continue;
                };
                let big = dq.amax();
                if big > MAX_STEP_RAD {
                    dq *= MAX_STEP_RAD / big;
                }
                let next: Joints = std::array::from_fn(|k| q[k] + dq[k]);
                let (e2, jac2) = self.linearise(&next);
                let cost2 = e2.norm_squared();
                if cost2 < cost {
                    (q, e, jac, cost) = (next, e2, jac2, cost2);
                    lambda = (lambda / 5.0).max(1e-9);
                    improved = true;
                    break;
                }
                lambda *= 4.0;
            }
            if !improved {
                break;
            }
        }
        // Out of steps, or stuck at rounding: what the answer promises.
        self.within(&e, TOLERANCE_MM, TOLERANCE_RAD).then_some(q)
    }

    /// The joints with robconf `want` (module documentation: the turns,
    /// and the pick among several); with `near`, the closest within
    /// [`CONF_TOLERANCE`] when none has it exactly.
    fn pick(
        &self,
        limits: &Limits,
        want: &RobConf,
        reference: &Joints,
        near: bool,
    ) -> Option<Joints> {
        let bits = CfxBits::from_cfx(want.cfx)?;
        let quadrants = [
            Some(want.cf1),
            None,
            None,
            Some(want.cf4),
            None,
            Some(want.cf6),
        ];
        // (mismatch, distance from the reference, joints)
        let mut best: Option<(f64, f64, Joints)> = None;
        for s in &self.found {
            let got = CfxBits::from_cfx(self.conf(s).cfx)?;
            if got.behind_axis1 != bits.behind_axis1
                || got.behind_lower_arm != bits.behind_lower_arm
            {
                continue;
            }
            let mut q = [0.0; 6];
            let mut mismatch = 0.0f64;
            for j in 0..6 {
                let t = turns(s[j], limits[j]);
                // How far a turn is from the requested quadrant or sign.
                let off = |v: f64| match quadrants[j] {
                    Some(cf) => quadrant_distance(v, cf),
                    None if j == 4 && (v < 0.0) != bits.axis5_negative => v.abs(),
                    None => 0.0,
                };
                // Axis 5 within the tolerance of 0 stays there rather than
                // turn by 360° for its sign: at the wrist singularity the
                // sign is rounding.
                let zero = t.iter().copied().filter(|v| v.abs() <= CONF_TOLERANCE);
                let pick = if j == 4 {
                    zero.min_by(|a, b| a.abs().total_cmp(&b.abs()))
                } else {
                    None
                };
                let v = pick.or_else(|| {
                    t.iter().copied().min_by(|a, b| {
                        off(*a).total_cmp(&off(*b)).then(
                            (a - reference[j])
                                .abs()
                                .total_cmp(&(b - reference[j]).abs()),
                        )
                    })
                });
                let Some(v) = v else {
                    mismatch = f64::INFINITY;
                    break;
                };
                q[j] = v;
                mismatch = mismatch.max(off(v));
            }
            let exact = mismatch == 0.0 && self.conf(&q) == *want;
            if !(exact || near && mismatch <= CONF_TOLERANCE) {
                continue;
            }
            let mismatch = if exact {
                0.0
            } else {
                mismatch.max(f64::MIN_POSITIVE)
            };
            let d: f64 = q.iter().zip(reference).map(|(a, b)| (a - b).powi(2)).sum();
            let better = match &best {
                None => true,
                Some((bm, bd, bq)) => (mismatch, d)
                    .partial_cmp(&(*bm, *bd))
                    .is_some_and(|o| o.is_lt() || o.is_eq() && lexical(&q, bq).is_lt()),
            };
            if better {
                best = Some((mismatch, d, q));
            }
        }
        best.map(|(_, _, q)| q)
    }

    /// The robconfs of every solution found with every turn within the
    /// limits, sorted by cfx, then cf1, cf4, cf6.
    fn reachable_confs(&self, limits: &Limits) -> Vec<RobConf> {
        let mut set = BTreeSet::new();
        for s in &self.found {
            let t: [Vec<f64>; 6] = std::array::from_fn(|j| turns(s[j], limits[j]));
            if t.iter().any(Vec::is_empty) {
                continue;
            }
            let cfx = self.conf(s).cfx & 6;
            for &q1 in &t[0] {
                for &q4 in &t[3] {
                    for &q5 in &t[4] {
                        for &q6 in &t[5] {
                            set.insert((
                                cfx | i32::from(q5 < 0.0),
                                quadrant(q1),
                                quadrant(q4),
                                quadrant(q6),
                            ));
                        }
                    }
                }
            }
        }
        set.into_iter()
            .map(|(cfx, cf1, cf4, cf6)| RobConf::new(cf1, cf4, cf6, cfx))
            .collect()
    }
}
