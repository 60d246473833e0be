//! Closed-form inverse kinematics of arms with an offset shoulder and a
//! spherical wrist (OPW: Brandstötter, Angerer, Hofbaur 2014), with joint
//! limits, the ±360° turns of axes that allow them, robconf and defined
//! choices at the wrist and shoulder singularities. No heap allocation
//! (except for the error of a pose whose every solution violates a limit).

use super::conf::{quadrant, quadrant_range, CfxBits, RobConf};
use super::lanes::sin_cos6;
use super::{Joints, Opw};
use nalgebra::{Isometry3, Matrix3, Quaternion, Translation3, UnitQuaternion, Vector3};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// |sin θ5| below this is the wrist singularity: axes 4 and 6 in line, only
/// their sum (or difference) is defined, and the split between them is
/// chosen. Choosing it moves the flange by at most 2·c4·|sin θ5| (1.3e-10
/// mm on the IRB 140); above it θ4 and θ6 come from the pose, with the sum
/// taken from its well-conditioned form.
pub const WRIST_SINGULAR_EPS: f64 = 1e-12;
/// Wrist centre closer than this (mm) to axis 1 is the shoulder
/// singularity: axis 1 is free.
pub const SHOULDER_SINGULAR_EPS: f64 = 1e-9;
/// Joint values this close (rad) outside a limit count as on the limit
/// (rounding of a target taught exactly at the limit).
pub const LIMIT_EPS: f64 = 1e-9;
/// Room for all solutions. The IRB 140 has at most 48: per arm branch, a
/// wrist and its flip together have at most 8 turns of axes 4 (±200°) and 6
/// (±400°), and axis 1 at exactly ±180° doubles the two front (or back)
/// branches. With axes 4 and 6 both at ±400° (IRB 2600, 4600) a wrist and
/// its flip have at most 3·3 + 2·2 = 13 turns (the flip is 180° away, out
/// of the 80° where a third turn fits), 52 in all, and up to 78 with axis 1
/// at exactly ±180°. What does not fit is dropped from the list (a search
/// by robconf keeps only near matches and is not limited by it).
pub const MAX_SOLUTIONS: usize = 64;

/// Angle wrapped into [-π, π].
#[inline]
pub fn wrap(a: f64) -> f64 {
    // Most angles are already inside: there a/2π rounds to ±0 and the
    // result is a itself (+0 for −0), without the division and the libm
    // call of `round` (no SSE4.1 in the baseline target). 3 < π keeps
    // a/2π well away from the halves.
    if a.abs() < 3.0 {
        return a + 0.0;
    }
    a - TAU * (a / TAU).round()
}

/// How the wrist axes of one branch were resolved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wrist {
    /// θ4, θ6 determined.
    Regular,
    /// θ5 ≈ 0: θ4 + θ6 = the value; θ4 was set to 0.
    Sum(f64),
    /// θ5 ≈ ±π: θ4 − θ6 = the value; θ4 was set to 0.
    Diff(f64),
}

/// The eight OPW branches in OPW angles θ (no offsets, no signs), each in
/// [-π, π]. Order: front elbow-a (wrist, flipped), front elbow-b, back
/// elbow-a, back elbow-b.
#[derive(Debug, Clone, Copy)]
pub struct Branches {
    pub theta: [Joints; 8],
    pub valid: [bool; 8],
    pub wrist: [Wrist; 8],
    /// The wrist centre was on axis 1 (θ1 came from the hint).
    pub shoulder_singular: bool,
    /// Distances (mm) of the wrist centre from axis 2 for the front and
    /// the back arm solutions, and the arm's reach interval from axis 2.
    pub reach: Reach,
    /// Per branch: the wrist centre's forward distance from axis 1 and its
    /// side of the lower arm (as [`Opw::cfx_geometry`], from the triangle).
    pub forward: [f64; 8],
    pub side: [f64; 8],
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    pub front: f64,
    pub back: f64,
    pub min: f64,
    pub max: f64,
}

impl Opw {
    /// Flange pose for OPW angles θ (θ3 = 0 with the forearm in line with
    /// the lower arm, all axes pointing up; no joint offsets).
    #[inline]
    pub fn fk_theta(&self, t: &Joints) -> Isometry3<f64> {
        // Half-angle sines and cosines build the quaternion directly; the
        // full angles for the position come from them (six sin/cos pairs,
        // in lanes).
        let t23 = t[1] + t[2];
        let ([sh1, sh23, sh4, sh5, s2, sh6], [ch1, ch23, ch4, ch5, c2, ch6]) = sin_cos6([
            0.5 * t[0],
            0.5 * t23,
            0.5 * t[3],
            0.5 * t[4],
            t[1],
            0.5 * t[5],
        ]);
        let (s1, c1) = (2.0 * sh1 * ch1, ch1 * ch1 - sh1 * sh1);
        let (s23, c23) = (2.0 * sh23 * ch23, ch23 * ch23 - sh23 * sh23);
        // k·sin(θ2+θ3+ψ3) = c3·sin θ23 + a2·cos θ23 (no atan2, no sqrt).
        let cx1 = self.c2 * s2 + self.c3 * s23 + self.a2 * c23 + self.a1;
        let cy1 = self.b;
        let cz1 = self.c2 * c2 + self.c3 * c23 - self.a2 * s23;
        let wrist = Vector3::new(cx1 * c1 - cy1 * s1, cx1 * s1 + cy1 * c1, cz1 + self.c1);
        // Rz(θ1)·Ry(θ23) and the wrist's Rz·Ry·Rz.
        let arm = Quaternion::new(ch1 * ch23, -sh1 * sh23, ch1 * sh23, sh1 * ch23);
        let zy = Quaternion::new(ch4 * ch5, -sh4 * sh5, ch4 * sh5, sh4 * ch5);
        let wrist_rot = zy * Quaternion::new(ch6, 0.0, 0.0, sh6);
        let rot = UnitQuaternion::new_unchecked(arm * wrist_rot);
        let flange = wrist + rot * Vector3::new(0.0, 0.0, self.c4);
        Isometry3::from_parts(Translation3::from(flange), rot)
    }

    /// Forward coordinate of the wrist centre in the arm plane (from axis
    /// 1) and its side of the lower-arm line (positive = in front), mm.
    pub fn cfx_geometry(&self, t: &Joints) -> (f64, f64) {
        let (s23, c23) = (t[1] + t[2]).sin_cos();
        let (s3, c3) = t[2].sin_cos();
        let forward = self.c2 * t[1].sin() + self.c3 * s23 + self.a2 * c23 + self.a1;
        // (wrist − axis 2) · (forward normal of the lower arm) = k·sin(θ3+ψ3).
        let side = self.c3 * s3 + self.a2 * c3;
        (forward, side)
    }

    /// All eight OPW solutions for a flange pose (rotation `r`, position
    /// `p`, mm). `theta1_hint` is used for θ1 at the shoulder singularity.
    pub fn ik_theta(&self, r: &Matrix3<f64>, p: &Vector3<f64>, theta1_hint: f64) -> Branches {
        let (arms, reach, shoulder_singular) = self.arm_angles(r, p, theta1_hint, None);
        let mut out = Branches {
            theta: [[0.0; 6]; 8],
            valid: [false; 8],
            wrist: [Wrist::Regular; 8],
            shoulder_singular,
            reach,
            forward: [0.0; 8],
            side: [0.0; 8],
        };
        // The two elbows of a shoulder share θ1 and so its sine and cosine.
        let mut trig: Option<(f64, (f64, f64))> = None;
        for (j, arm) in arms.iter().enumerate() {
            if !arm.valid() {
                continue;
            }
            let sc1 = match trig {
                Some((t1, sc1)) if t1.to_bits() == arm.t1.to_bits() => sc1,
                _ => {
                    let sc1 = arm.t1.sin_cos();
                    trig = Some((arm.t1, sc1));
                    sc1
                }
            };
            for (h, branch) in self.wrists(r, arm, sc1).iter().enumerate() {
                let i = 2 * j + h;
                out.forward[i] = arm.forward;
                out.side[i] = arm.side;
                if let Some((theta, wrist)) = *branch {
                    out.theta[i] = theta;
                    out.valid[i] = true;
                    out.wrist[i] = wrist;
                }
            }
        }
        out
    }

    /// The four arm solutions (θ1, θ2, θ3, before the wrist) in the order
    /// of [`Branches`], the reach, and whether the wrist centre is on
    /// axis 1. Split from the wrist so that a search for one robconf
    /// solves the wrist of its own arm only; with `behind_axis1`, only the
    /// arm solutions on that side of axis 1 (as [`cfx_bits`] reads it) are
    /// solved, the others are left invalid (the same numbers either way).
    pub(super) fn arm_angles(
        &self,
        r: &Matrix3<f64>,
        p: &Vector3<f64>,
        theta1_hint: f64,
        behind_axis1: Option<bool>,
    ) -> ([ArmAngles; 4], Reach, bool) {
        let zc = r.column(2);
        let c = p - self.c4 * zc;
        let (cx, cy, cz) = (c.x, c.y, c.z);
        let rho2 = cx * cx + cy * cy;
        let lateral = (rho2 - self.b * self.b).sqrt();
        let nx1 = lateral - self.a1;
        let czp = cz - self.c1;
        let s1_2 = nx1 * nx1 + czp * czp;
        let s2_2 = (nx1 + 2.0 * self.a1).powi(2) + czp * czp;
        let k2 = self.a2 * self.a2 + self.c3 * self.c3;
        let k = k2.sqrt();
        let (s1, s2) = (s1_2.sqrt(), s2_2.sqrt());
        let shoulder_singular = self.b == 0.0 && rho2.sqrt() < SHOULDER_SINGULAR_EPS;
        let base = if shoulder_singular {
            theta1_hint
        } else {
            cy.atan2(cx)
        };
        let off = atan2_of_offset(self.b, nx1 + self.a1);
        let c2sq = self.c2 * self.c2;
        let psi3 = atan2_of_offset(self.a2, self.c3);
        // The front arms face the wrist centre (forward = its lateral
        // distance from axis 1), the back arms turn away from it; elbow
        // sign decides the side of the lower arm. `tmp`: the angle of the
        // line from axis 2 to the wrist centre, signed for the side.
        let arms_of = |t1: f64, s: f64, s_2: f64, tmp: f64, forward: f64| {
            let arg2 = (s_2 + c2sq - k2) / (2.0 * s * self.c2);
            let arg3 = (s_2 - c2sq - k2) / (2.0 * self.c2 * k);
            let ok = in_acos_domain(arg2) && in_acos_domain(arg3);
            // The triangle's angles by atan2 with Heron's area: acos
            // loses half the digits near full stretch and full fold.
            let (a2, a3, side) = self.triangle(s, s_2, k2, k);
            let arm = |t2: f64, t3: f64, side: f64| ArmAngles {
                t1,
                t2,
                t3,
                ok,
                forward,
                side,
            };
            [
                arm(-a2 + tmp, a3 - psi3, side),
                arm(a2 + tmp, -a3 - psi3, -side),
            ]
        };
        let wanted = |forward: f64| {
            behind_axis1.is_none_or(|b| cfx_bits(forward, 0.0, 0.0).behind_axis1 == b)
        };
        let [a, b] = if wanted(lateral) {
            arms_of(base - off, s1, s1_2, nx1.atan2(czp), lateral)
        } else {
            [ArmAngles::NONE; 2]
        };
        let [c, d] = if wanted(-lateral) {
            let tmp2 = (nx1 + 2.0 * self.a1).atan2(czp);
            arms_of(base + off - PI, s2, s2_2, -tmp2, -lateral)
        } else {
            [ArmAngles::NONE; 2]
        };
        let reach = Reach {
            front: s1,
            back: s2,
            min: (self.c2 - k).abs(),
            max: self.c2 + k,
        };
        ([a, b, c, d], reach, shoulder_singular)
    }

    /// The wrist of one arm solution: the wrist and its flip, each with its
    /// OPW angles (θ1..θ3 wrapped) and how the wrist was resolved; at the
    /// wrist singularity only the first. `(st1, ct1)`: θ1's sine and cosine.
    #[inline]
    pub(super) fn wrists(
        &self,
        r: &Matrix3<f64>,
        arm: &ArmAngles,
        (st1, ct1): (f64, f64),
    ) -> [Option<(Joints, Wrist)>; 2] {
        let (t1, t2, t3) = (arm.t1, arm.t2, arm.t3);
        let (sa, ca) = (t2 + t3).sin_cos();
        // Rows of R03ᵀ with R03 = Rz(θ1)·Ry(θ2+θ3).
        let x = Vector3::new(ct1 * ca, st1 * ca, -sa);
        let y = Vector3::new(-st1, ct1, 0.0);
        let z = Vector3::new(ct1 * sa, st1 * sa, ca);
        let (r0, r1, r2) = (r.column(0), r.column(1), r.column(2));
        let m13 = x.dot(&r2);
        let m23 = y.dot(&r2);
        let m33 = z.dot(&r2);
        let sb = (m13 * m13 + m23 * m23).sqrt();
        let t5 = sb.atan2(m33);
        let (t1w, t2w, t3w) = (wrap(t1), wrap(t2), wrap(t3));
        let m11 = x.dot(&r0);
        let m21 = y.dot(&r0);
        // θ4 + θ6 from the upper-left block, (1 + cos θ5)·(cos, sin) of
        // the sum: well conditioned for θ5 < 90°, where the separate
        // atan2s of θ4 and θ6 lose precision as θ5 → 0.
        let sum = if m33 > 0.0 {
            let m12 = x.dot(&r1);
            let m22 = y.dot(&r1);
            Some((m21 - m12).atan2(m11 + m22))
        } else {
            None
        };
        if sb < WRIST_SINGULAR_EPS {
            let (t6, kind) = match sum {
                Some(sum) => (sum, Wrist::Sum(sum)),
                None => {
                    let diff = (-m21).atan2(-m11);
                    (-diff, Wrist::Diff(diff))
                }
            };
            [Some(([t1w, t2w, t3w, 0.0, t5, wrap(t6)], kind)), None]
        } else {
            let mut t4 = m23.atan2(m13);
            let mut t6 = z.dot(&r1).atan2(-z.dot(&r0));
            if let Some(sum) = sum {
                // Keep θ4 − θ6 from the atan2s (its error only matters
                // in proportion to sin θ5) and the sum from above.
                let diff = t4 - t6;
                let half = 0.5 * (sum + diff);
                // (sum + diff)/2 is θ4 up to π: take the one nearer θ4.
                let refined = if wrap(half - t4).abs() <= FRAC_PI_2 {
                    half
                } else {
                    half + PI
                };
                t4 = wrap(refined);
                t6 = wrap(sum - refined);
            }
            [
                Some(([t1w, t2w, t3w, t4, t5, t6], Wrist::Regular)),
                Some((
                    [t1w, t2w, t3w, wrap(t4 + PI), -t5, wrap(t6 + PI)],
                    Wrist::Regular,
                )),
            ]
        }
    }
}

/// One arm solution before the wrist: OPW angles θ1..θ3 (unwrapped),
/// whether the triangle closes, and the wrist centre's forward distance
/// from axis 1 and side of the lower arm (mm).
#[derive(Debug, Clone, Copy)]
pub(super) struct ArmAngles {
    pub t1: f64,
    pub t2: f64,
    pub t3: f64,
    pub ok: bool,
    pub forward: f64,
    pub side: f64,
}

impl ArmAngles {
    /// An arm solution not solved for.
    const NONE: ArmAngles = ArmAngles {
        t1: f64::NAN,
        t2: f64::NAN,
        t3: f64::NAN,
        ok: false,
        forward: f64::NAN,
        side: f64::NAN,
    };

    pub(super) fn valid(&self) -> bool {
        self.ok && self.t1.is_finite() && self.t2.is_finite() && self.t3.is_finite()
    }
}

impl Opw {
    /// Angles at axis 2 (between the lower arm and the line to the wrist
    /// centre) and at axis 3 (θ3 + ψ3) of the triangle with sides c2, k, s.
    /// Also k·sin(θ3+ψ3) = 2·area/c2 (≥ 0), the wrist centre's distance
    /// from the lower-arm line.
    fn triangle(&self, s: f64, s_2: f64, k2: f64, k: f64) -> (f64, f64, f64) {
        let c2 = self.c2;
        // 4·area² = ((c2+k)² − s²)(s² − (c2−k)²), factored for accuracy.
        let p = ((c2 + k - s) * (c2 + k + s) * (s - c2 + k) * (s + c2 - k)).max(0.0);
        let root = p.sqrt();
        let at2 = root.atan2(s_2 + c2 * c2 - k2);
        let at3 = root.atan2(s_2 - c2 * c2 - k2);
        (at2, at3, 0.5 * root / c2)
    }
}

/// `y.atan2(x)`, without the call for an offset of zero in front (b = 0 on
/// every catalogue arm, a2 = 0 on the IRB 140): atan2(±0, x > 0) is ±0
/// exactly, so the result is the same to the bit.
#[inline]
fn atan2_of_offset(y: f64, x: f64) -> f64 {
    if y == 0.0 && x > 0.0 {
        y
    } else {
        y.atan2(x)
    }
}

fn in_acos_domain(x: f64) -> bool {
    // Targets exactly at full stretch land a rounding error outside.
    x.abs() <= 1.0 + 1e-12
}

/// An OPW arm in the robot's own joint convention: θ_i = sign_i·s_i +
/// offset_i with s the serial angles of the controller's joints `q`
/// ([`serial_angles`]: s = q, except s3 = q3 + coupling·q2), and the
/// flange frame (tool0) is the OPW flange frame turned by the fixed
/// rotation `tip`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpwArm {
    pub geom: Opw,
    /// +1 or −1 per axis.
    pub signs: [f64; 6],
    /// rad.
    pub offsets: [f64; 6],
    /// 0 on a serial arm; −1 where the controller reads axis 3 against the
    /// horizontal rather than against the lower arm (ABB's parallel-arm
    /// robots, IRB 2400: `data/arms/README.md`).
    pub coupling: f64,
    pub tip: UnitQuaternion<f64>,
}

/// The serial joint angles (each axis relative to the link before it) of
/// the controller's joints: axis 3 of a parallel-arm robot is driven
/// through a parallelogram, so the controller's q3 is the upper arm's angle
/// to the horizontal and the serial angle is q3 + coupling·q2 (coupling
/// −1; 0 leaves `q` as it is).
pub fn serial_angles(q: &Joints, coupling: f64) -> Joints {
    let mut s = *q;
    s[2] += coupling * q[1];
    s
}

/// The controller's joints of serial angles: [`serial_angles`] undone.
pub fn controller_angles(s: &Joints, coupling: f64) -> Joints {
    let mut q = *s;
    q[2] -= coupling * s[1];
    q
}

/// One IK solution: joint angles (rad) and their robconf.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solution {
    pub q: Joints,
    pub conf: RobConf,
}

/// All IK solutions of a pose (at most [`MAX_SOLUTIONS`]), and the arm
/// branches left out because a joint is outside its limits in every turn
/// ([`Solutions::dropped`]). The solutions live on the heap: a 4 kB
/// buffer in the struct was cleared and copied on every call, a tenth of
/// IK's time, where one small allocation is not.
#[derive(Clone)]
pub struct Solutions {
    items: Vec<Solution>,
    len: usize,
    /// In branch order; empty (no allocation) in the common case.
    dropped: Vec<DroppedBranch>,
}

/// An arm branch of a pose that no turn of its axes brings within the
/// joint limits: its joints (each wrapped into [-180°, 180°]), its
/// robconf, and the first axis outside its limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DroppedBranch {
    pub q: Joints,
    pub conf: RobConf,
    pub violation: Violation,
}

impl Default for Solutions {
    fn default() -> Self {
        Solutions {
            items: Vec::with_capacity(16),
            len: 0,
            dropped: Vec::new(),
        }
    }
}

impl std::fmt::Debug for Solutions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl Solutions {
    pub fn as_slice(&self) -> &[Solution] {
        &self.items[..self.len]
    }
    pub fn len(&self) -> usize {
        self.len
    }
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    pub fn iter(&self) -> std::slice::Iter<'_, Solution> {
        self.as_slice().iter()
    }
    /// The arm branches left out: a joint outside its limits in every turn
    /// (set by a search for all solutions, not by one for a robconf).
    pub fn dropped(&self) -> impl Iterator<Item = &DroppedBranch> {
        self.dropped.iter()
    }
    pub(super) fn clear(&mut self) {
        self.items.clear();
        self.len = 0;
        self.dropped.clear();
    }
    pub(super) fn push(&mut self, s: Solution) {
        if self.len < MAX_SOLUTIONS {
            self.items.push(s);
            self.len += 1;
        }
    }
    /// Record a branch left out (the numeric IK's; the closed form fills
    /// the slot of its branch).
    pub(super) fn push_dropped(&mut self, d: DroppedBranch) {
        // One per arm branch at most, as the closed form has eight.
        if self.dropped.len() < 8 {
            self.dropped.push(d);
        }
    }
}

impl<'a> IntoIterator for &'a Solutions {
    type Item = &'a Solution;
    type IntoIter = std::slice::Iter<'a, Solution>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// Joint limits, rad, inclusive.
pub type Limits = [(f64, f64); 6];

/// A joint outside its limits in every turn: axis (0-based), angle (rad),
/// limits (rad).
pub type Violation = (usize, f64, (f64, f64));

/// Why a pose has no solution.
#[derive(Debug, Clone, PartialEq)]
pub enum IkFailure {
    /// The wrist centre is out of the arm's reach (all branches).
    OutOfReach(Reach),
    /// Arm solutions exist but each violates a joint limit: the first
    /// violation of each branch (boxed: only this failure allocates).
    JointLimits(Box<[Option<Violation>; 8]>),
}

impl OpwArm {
    /// A serial ABB arm in the controller's joint convention (all signs
    /// +1, θ3 = q3 + 90°, tool0 z out of the flange and x down at the zero
    /// pose), as the IRB 140.
    pub fn abb(geom: Opw) -> OpwArm {
        OpwArm {
            geom,
            signs: [1.0; 6],
            offsets: [0.0, 0.0, super::OPW_OFFSET_Q3, 0.0, 0.0, 0.0],
            coupling: 0.0,
            tip: UnitQuaternion::identity(),
        }
    }

    #[inline]
    pub fn theta_of(&self, q: &Joints) -> Joints {
        let s = serial_angles(q, self.coupling);
        std::array::from_fn(|i| self.signs[i] * s[i] + self.offsets[i])
    }

    pub fn q_of(&self, t: &Joints) -> Joints {
        let s: Joints = std::array::from_fn(|i| wrap((t[i] - self.offsets[i]) * self.signs[i]));
        if self.coupling == 0.0 {
            return s;
        }
        let mut q = controller_angles(&s, self.coupling);
        q[2] = wrap(q[2]);
        q
    }

    /// Flange (tool0) pose in the base frame.
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        let mut pose = self.geom.fk_theta(&self.theta_of(q));
        pose.rotation *= self.tip;
        pose
    }

    /// robconf of joint angles on this arm.
    pub fn conf_of(&self, q: &Joints) -> RobConf {
        let (forward, side) = self.geom.cfx_geometry(&self.theta_of(q));
        RobConf::from_parts(q, cfx_bits(forward, side, q[4]))
    }

    /// All solutions within `limits`. With `want`, the free angles at
    /// singularities are chosen to give that robconf where possible: θ1 at
    /// the shoulder singularity from the middle of the cf1 quadrant, and
    /// q4 at the wrist singularity as close to 0 as the cf4 and cf6
    /// quadrants allow. Without it, q1 = 0 and q4 = 0 there.
    pub fn solve(
        &self,
        pose: &Isometry3<f64>,
        limits: &Limits,
        want: Option<&RobConf>,
    ) -> Result<Solutions, IkFailure> {
        // Built in the place it is returned from: the buffer is 4 kB, and
        // moving it into the result took a sixth of the time.
        let mut out = Ok(Solutions::default());
        if let Ok(sols) = &mut out {
            if let Err(f) = self.solve_in(pose, limits, want, sols) {
                out = Err(f);
            }
        }
        out
    }

    /// [`OpwArm::solve`] into an empty buffer.
    pub(super) fn solve_in(
        &self,
        pose: &Isometry3<f64>,
        limits: &Limits,
        want: Option<&RobConf>,
        out: &mut Solutions,
    ) -> Result<(), IkFailure> {
        let q1_hint = want.map_or(0.0, |c| {
            let (lo, hi) = quadrant_range(c.cf1);
            0.5 * (lo + hi)
        });
        self.solve_hinted(pose, limits, want, q1_hint, out, false)
            .map(|_| ())
    }

    pub(super) fn solve_hinted(
        &self,
        pose: &Isometry3<f64>,
        limits: &Limits,
        want: Option<&RobConf>,
        q1_hint: f64,
        out: &mut Solutions,
        only_near_want: bool,
    ) -> Result<bool, IkFailure> {
        let rot = (pose.rotation * self.tip.inverse()).to_rotation_matrix();
        let p = pose.translation.vector;
        let theta1_hint = self.signs[0] * q1_hint + self.offsets[0];
        let br = self.geom.ik_theta(rot.matrix(), &p, theta1_hint);
        let mut violations: [Option<Violation>; 8] = [None; 8];
        let mut any = false;
        let mut in_limits = false;
        let keep = if only_near_want { want } else { None };
        for (i, violation) in violations.iter_mut().enumerate() {
            if !br.valid[i] {
                continue;
            }
            any = true;
            let q = self.branch_q(&br.theta[i], br.wrist[i], want);
            let (forward, side) = (br.forward[i], br.side[i]);
            let conf = |qq: &Joints| RobConf::from_parts(qq, cfx_bits(forward, side, qq[4]));
            if push_turns(&q, limits, out, &conf, keep) {
                in_limits = true;
            } else {
                *violation = first_violation(&q, limits);
                if let (Some(v), None) = (*violation, keep) {
                    out.push_dropped(DroppedBranch {
                        q,
                        conf: conf(&q),
                        violation: v,
                    });
                }
            }
        }
        if !any {
            return Err(IkFailure::OutOfReach(br.reach));
        }
        if !in_limits {
            return Err(IkFailure::JointLimits(Box::new(violations)));
        }
        Ok(br.shoulder_singular)
    }

    /// The controller's joints of one branch's OPW angles, the free split
    /// of a singular wrist chosen for `want` ([`OpwArm::split_wrist`]).
    #[inline]
    pub(super) fn branch_q(&self, theta: &Joints, wrist: Wrist, want: Option<&RobConf>) -> Joints {
        let mut q = self.q_of(theta);
        match wrist {
            Wrist::Regular => {}
            Wrist::Sum(v) => self.split_wrist(
                &mut q,
                v - self.offsets[3] - self.offsets[5],
                self.signs[5],
                want,
            ),
            Wrist::Diff(v) => self.split_wrist(
                &mut q,
                v - self.offsets[3] + self.offsets[5],
                -self.signs[5],
                want,
            ),
        }
        q
    }

    /// At the wrist singularity only s4·q4 + e·q6 ≡ t (mod 2π) is fixed.
    /// Choose q4 as close to 0 as keeps q4 in quadrant cf4 and q6 in cf6;
    /// without a wanted robconf (or if none fits), q4 = 0.
    fn split_wrist(&self, q: &mut Joints, t: f64, e: f64, want: Option<&RobConf>) {
        let s4 = self.signs[3];
        // q6 = e·(t − s4·q4) = c + m·q4
        let m = -e * s4;
        let mut best: Option<f64> = None;
        if let Some(conf) = want {
            let (a_lo, a_hi) = quadrant_range(conf.cf4);
            let (b_lo, b_hi) = quadrant_range(conf.cf6);
            for k in -3..=3 {
                let c = e * (t + TAU * f64::from(k));
                // q4 range putting q6 in [b_lo, b_hi); (value, closed?).
                let (lo2, hi2) = if m > 0.0 {
                    ((b_lo - c, true), (b_hi - c, false))
                } else {
                    ((c - b_hi, false), (c - b_lo, true))
                };
                let lo = if lo2.0 > a_lo { lo2 } else { (a_lo, true) };
                let hi = if hi2.0 < a_hi { hi2 } else { (a_hi, false) };
                if lo.0 > hi.0 {
                    continue;
                }
                let margin = 1e-9;
                let q4 = if 0.0 < lo.0 {
                    lo.0 + if lo.1 { 0.0 } else { margin }
                } else if 0.0 > hi.0 {
                    hi.0 - if hi.1 { 0.0 } else { margin }
                } else {
                    0.0
                };
                let q6 = c + m * q4;
                if quadrant(q4) == conf.cf4
                    && quadrant(q6) == conf.cf6
                    && best.is_none_or(|b| q4.abs() < b.abs())
                {
                    best = Some(q4);
                    q[3] = q4;
                    q[5] = q6;
                }
            }
        }
        if best.is_none() {
            q[3] = 0.0;
            q[5] = wrap(e * t);
        }
    }
}

/// cfx bits from the wrist centre's forward distance from axis 1 and its
/// side of the lower arm (mm). On the line within rounding (the shoulder or
/// elbow singularity) counts as in front, as the manual's zero does.
pub(super) fn cfx_bits(forward: f64, side: f64, q5: f64) -> CfxBits {
    CfxBits {
        behind_axis1: forward < -SHOULDER_SINGULAR_EPS,
        behind_lower_arm: side < -SHOULDER_SINGULAR_EPS,
        axis5_negative: q5 < 0.0,
    }
}

/// Push every combination of 2π turns of the joints that stays within the
/// limits.
/// Returns whether any combination was within the limits (kept or not).
fn push_turns(
    q: &Joints,
    limits: &Limits,
    out: &mut Solutions,
    conf: &impl Fn(&Joints) -> RobConf,
    keep: Option<&RobConf>,
) -> bool {
    let mut reps = [[0.0f64; 5]; 6];
    let mut counts = [0usize; 6];
    for j in 0..6 {
        let (lo, hi) = limits[j];
        for k in -2..=2 {
            let v = q[j] + TAU * f64::from(k);
            if v >= lo - LIMIT_EPS && v <= hi + LIMIT_EPS {
                reps[j][counts[j]] = v.clamp(lo, hi);
                counts[j] += 1;
            }
        }
        if counts[j] == 0 {
            return false;
        }
    }
    let mut idx = [0usize; 6];
    loop {
        let qq: Joints = std::array::from_fn(|j| reps[j][idx[j]]);
        let s = Solution {
            q: qq,
            conf: conf(&qq),
        };
        if keep.is_none_or(|want| conf_mismatch(&s, want).is_some()) {
            out.push(s);
        }
        // Odometer over the representations.
        let mut j = 0;
        loop {
            if j == 6 {
                return true;
            }
            idx[j] += 1;
            if idx[j] < counts[j] {
                break;
            }
            idx[j] = 0;
            j += 1;
        }
    }
}

fn first_violation(q: &Joints, limits: &Limits) -> Option<Violation> {
    (0..6).find_map(|j| {
        let (lo, hi) = limits[j];
        let inside = (-2..=2).any(|k| {
            let v = q[j] + TAU * f64::from(k);
            v >= lo - LIMIT_EPS && v <= hi + LIMIT_EPS
        });
        (!inside).then_some((j, q[j], (lo, hi)))
    })
}

/// Tolerance for matching a robconf when no solution matches it exactly: a
/// joint this close (rad) outside its requested quadrant, or axis 5 this
/// close to 0 with the other sign, still counts. Thermal corrections move
/// joints by hundredths of a degree; a target taught on a quadrant boundary
/// must not become unreachable because of that.
pub const CONF_TOLERANCE: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The solution that has robconf `want`: an exact match, else the closest
/// one within [`CONF_TOLERANCE`] (cfx's arm bits must match exactly).
pub fn pick_conf(solutions: &Solutions, want: &RobConf) -> Option<Solution> {
    let mut best: Option<(f64, Solution)> = None;
    for s in solutions {
        if let Some(d) = conf_mismatch(s, want) {
            if d == 0.0 && s.conf == *want {
                return Some(*s);
            }
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, *s));
            }
        }
    }
    best.map(|(_, s)| s)
}

/// How far (rad) a solution is from having robconf `want`: 0 for an exact
/// match, up to [`CONF_TOLERANCE`] for a near one, None beyond or when
/// cfx's arm bits differ.
fn conf_mismatch(s: &Solution, want: &RobConf) -> Option<f64> {
    if s.conf == *want {
        return Some(0.0);
    }
    let want_bits = CfxBits::from_cfx(want.cfx)?;
    let bits = CfxBits::from_cfx(s.conf.cfx)?;
    if bits.behind_axis1 != want_bits.behind_axis1
        || bits.behind_lower_arm != want_bits.behind_lower_arm
    {
        return None;
    }
    let mut d = super::conf::quadrant_distance(s.q[0], want.cf1)
        .max(super::conf::quadrant_distance(s.q[3], want.cf4))
        .max(super::conf::quadrant_distance(s.q[5], want.cf6));
    if bits.axis5_negative != want_bits.axis5_negative {
        d = d.max(s.q[4].abs());
    }
    // A mismatch of exactly 0 is impossible here (the confs differ), so a
    // near match never passes for an exact one.
    (d <= CONF_TOLERANCE).then_some(d.max(f64::MIN_POSITIVE))
}
