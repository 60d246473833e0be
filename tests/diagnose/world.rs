//! A blind generator of laser-tracker data of a warming IRB 140, written
//! from the specification (`docs/model.md`, `docs/model.md`) and
//! physics, independently of the diagnosis: its own kinematic chain, its own
//! parameterisation of every effect, and the nuisance of real measurements
//! (a tracker metres away at any heading, the arm's own geometric error, a
//! reflector off the flange, 0.02 mm noise, temperatures logged or not).
//!
//! The only thing taken from the library is the embedded heating profile,
//! and only for sets without temperature columns: there the heating model
//! is the premise the diagnosis works from, so the truth follows it.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rapidtherm::thermal::{default_profile, HeatingProfile};

/// IRB 140 lengths, mm (`docs/model.md`, "Geometry").
const C1: f64 = 352.0;
const A1: f64 = 70.0;
const C2: f64 = 360.0;
const C3: f64 = 380.0;
const C4: f64 = 65.0;
/// A380 expansion coefficient and the calibrated default's scale
/// (`docs/model.md`, "Materials", "Calibrated default").
const ALPHA: f64 = 21.8e-6;
const K0: f64 = 0.33699;
/// Reference temperature of the taught targets, °C.
const T_REF: f64 = 7.0;
/// Table-1 maxima (`docs/model.md`), °C.
const T_MAX: [f64; 6] = [18.837, 21.596, 18.849, 21.665, 27.537, 30.705];

/// One physical departure of the real robot from the model in use.
#[derive(Debug, Clone)]
pub enum Effect {
    /// Each link expands `k` times what the model says (base, lower arm,
    /// upper arm, wrist).
    ExpansionScale([f64; 4]),
    /// The structure follows the motors through a first-order lag, min.
    ThermalLag(f64),
    /// Tip rotation per K of link rise, rad/K (lower arm, upper arm).
    ArmBending([f64; 2]),
    /// Zero drift per K of the axis's own motor rise, rad/K.
    JointOffsetDrift([f64; 6]),
    /// Base shift (mm/K) and tilt about x and y (rad/K) per K of the base
    /// motor's rise.
    MountDrift(Vector3<f64>, [f64; 2]),
    /// Gearbox compliance of axes 2 and 3, rad per N·m, under the weight of
    /// the arm (masses below).
    GravitySag([f64; 2]),
    /// Outside the library: the base knocked at `minute`, moved by `shift`
    /// (mm) for good.
    Knock(f64, Vector3<f64>),
    /// Outside the library: backlash of an axis (1-based), rad: the axis
    /// stops β/2 short on the side it came from.
    Backlash(usize, f64),
    /// Outside the library: a cyclic error of an axis's angle (1-based
    /// axis, cycles per turn, amplitude in rad, phase in rad), as a gear's
    /// or an encoder's: Δq = A·sin(n·q + φ).
    Cyclic(usize, f64, f64, f64),
    /// Outside the library: every link grows with the square of its
    /// temperature rise besides the model's linear growth, by β times the
    /// model's expansion at a rise of 10 K (none at the cold start, four
    /// times as much at 20 K).
    QuadraticExpansion(f64),
}

impl Effect {
    /// The library's name of the effect, `None` outside the library.
    pub fn name(&self) -> Option<&'static str> {
        Some(match self {
            Effect::ExpansionScale(_) => "expansion-scale",
            Effect::ThermalLag(_) => "thermal-lag",
            Effect::ArmBending(_) => "arm-bending",
            Effect::JointOffsetDrift(_) => "joint-offset-drift",
            Effect::MountDrift(..) => "mount-drift",
            Effect::GravitySag(_) => "gravity-sag",
            Effect::Knock(..)
            | Effect::Backlash(..)
            | Effect::Cyclic(..)
            | Effect::QuadraticExpansion(_) => return None,
        })
    }
}

/// Which robot the world holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Arm {
    Irb140,
    /// A UR5 (`world_ur5.rs`): no OPW form, the diagnosis works on its
    /// URDF chain.
    Ur5,
}

/// What makes a data set: the effects, the nuisance, and its form.
#[derive(Debug, Clone)]
pub struct SetSpec {
    pub arm: Arm,
    pub effects: Vec<Effect>,
    pub seed: u64,
    pub poses: usize,
    /// Measurement times (a sweep over all poses at each), minutes.
    pub times: Vec<f64>,
    /// Log motor temperatures in the file (else the heating model's).
    pub temps_logged: bool,
    pub noise_mm: f64,
    /// Geometric error of the arm: joint-origin translations (mm) and
    /// rotations (rad), one standard deviation per component.
    pub geometry_mm: f64,
    pub geometry_rad: f64,
    /// Tracker distance from the robot base, mm.
    pub tracker_mm: f64,
}

impl SetSpec {
    pub fn new(effects: Vec<Effect>, seed: u64) -> SetSpec {
        SetSpec {
            arm: Arm::Irb140,
            effects,
            seed,
            poses: 15,
            times: (0..=30).map(|i| 6.0 * i as f64).collect(),
            temps_logged: true,
            noise_mm: 0.02,
            geometry_mm: 0.1,
            geometry_rad: 0.3e-3,
            tracker_mm: 3000.0,
        }
    }
}

/// A generated set: the CSV a tracker session would leave, and what was in
/// it.
pub struct DataSet {
    pub csv: String,
    pub rows: usize,
}

/// The real robot's fixed departures from nominal.
pub(super) struct Geometry {
    /// A small transform after each joint's rotation.
    pub(super) origin: [Isometry3<f64>; 6],
    /// Zero offsets, rad.
    pub(super) zero: [f64; 6],
    /// Reflector position in the last frame (x along the flange normal).
    pub(super) reflector: Vector3<f64>,
    /// Robot base in the tracker's frame.
    pub(super) tracker: Isometry3<f64>,
}

pub(super) fn rx(a: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), a)
}
pub(super) fn ry(a: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), a)
}
pub(super) fn rz(a: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), a)
}
pub(super) fn rot(r: UnitQuaternion<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::identity(), r)
}
pub(super) fn tr(x: f64, y: f64, z: f64) -> Isometry3<f64> {
    Isometry3::translation(x, y, z)
}

/// Everything a pose's position depends on at one moment.
pub(super) struct State {
    /// Link lengths as they are (expanded): c1, a1, c2, c3, c4.
    len: [f64; 5],
    /// Each link's length factor (base, lower arm, upper arm, wrist).
    pub(super) grow: [f64; 4],
    /// Extra joint angles, rad.
    pub(super) dq: [f64; 6],
    /// Curvature tip rotations of the lower and upper arm, rad.
    pub(super) bend: [f64; 2],
    /// Where the base really is.
    pub(super) base: Isometry3<f64>,
}

/// The position of the reflector in the tracker frame. Written from the
/// ABB convention: calibration pose with the lower arm vertical and the
/// upper arm horizontal, axis 4 and 6 along the forearm and flange normal.
fn position(g: &Geometry, s: &State, q: &[f64; 6]) -> Vector3<f64> {
    let [c1, a1, c2, c3, c4] = s.len;
    let a = |i: usize| q[i] + g.zero[i] + s.dq[i];
    let lower = {
        let t = s.bend[0];
        // Bent about y: the tip goes forward by θL/2 and turns by θ.
        tr(t * c2 / 2.0, 0.0, c2) * rot(ry(t))
    };
    let upper = {
        let t = s.bend[1];
        tr(c3, 0.0, -t * c3 / 2.0) * rot(ry(t))
    };
    let chain = s.base
        * rot(rz(a(0)))
        * g.origin[0]
        * tr(a1, 0.0, c1)
        * rot(ry(a(1)))
        * g.origin[1]
        * lower
        * rot(ry(a(2)))
        * g.origin[2]
        * upper
        * rot(rx(a(3)))
        * g.origin[3]
        * rot(ry(a(4)))
        * g.origin[4]
        * tr(c4, 0.0, 0.0)
        * rot(rx(a(5)))
        * g.origin[5];
    (g.tracker * chain)
        .transform_point(&g.reflector.into())
        .coords
}

/// Motor temperatures: logged sets warm along saturating curves of their
/// own (time constants 40-80 min per axis, a slow room drift, a 0.1 K
/// logger); unlogged sets follow the heating model.
struct Heat {
    tau: [f64; 6],
    tmax: [f64; 6],
}

impl Heat {
    fn new(rng: &mut ChaCha8Rng) -> Heat {
        Heat {
            tau: std::array::from_fn(|_| rng.random_range(40.0..80.0)),
            tmax: std::array::from_fn(|i| T_MAX[i] + rng.random_range(-1.5..1.5)),
        }
    }
    fn at(&self, t: f64, logged: bool) -> [f64; 6] {
        if logged {
            std::array::from_fn(|i| {
                T_REF + (self.tmax[i] - T_REF) * (1.0 - (-t / self.tau[i]).exp())
            })
        } else {
            default_profile().temps_at(t).expect("in range")
        }
    }
}

/// Link temperature rises above the reference (`docs/model.md`: base T1, lower
/// (T2+T3)/2, upper (T4+T5+T6)/3, wrist (T5+T6)/2).
fn link_rise(t: &[f64; 6]) -> [f64; 4] {
    [
        t[0] - T_REF,
        (t[1] + t[2]) / 2.0 - T_REF,
        (t[3] + t[4] + t[5]) / 3.0 - T_REF,
        (t[4] + t[5]) / 2.0 - T_REF,
    ]
}

/// Gravity torques on axes 2 and 3, N·m: lower arm 8 kg at mid-length,
/// upper arm and wrist 10 kg at 40 % of the forearm, a 2 kg payload at the
/// flange. Angles from the vertical.
fn gravity_torque(q: &[f64; 6]) -> [f64; 2] {
    let g = 9.81e-3; // N per kg, lengths in mm → N·m
    let lower = q[1].sin();
    let fore = (q[1] + q[2]).cos();
    let upper_moment = 10.0 * 0.4 * C3 * fore + 2.0 * (C3 + C4) * fore;
    let t2 = g * (8.0 * C2 / 2.0 * lower + 12.0 * C2 * lower + upper_moment);
    let t3 = g * upper_moment;
    [t2, t3]
}

fn random_pose(rng: &mut ChaCha8Rng) -> [f64; 6] {
    let deg = |rng: &mut ChaCha8Rng, lo: f64, hi: f64| rng.random_range(lo..hi).to_radians();
    let q5 = loop {
        let v = rng.random_range(-100.0..100.0);
        if f64::abs(v) > 15.0 {
            break v;
        }
    };
    [
        deg(rng, -150.0, 150.0),
        deg(rng, -50.0, 80.0),
        deg(rng, -120.0, 30.0),
        deg(rng, -150.0, 150.0),
        q5.to_radians(),
        deg(rng, -180.0, 180.0),
    ]
}

/// A first-order lag of the link rises, integrated exactly between steps.
fn lagged_rises(heat: &Heat, logged: bool, times: &[f64], tau: f64) -> Vec<[f64; 4]> {
    let end = times.iter().cloned().fold(0.0, f64::max);
    let dt = 0.25;
    let mut state = [0.0; 4];
    let mut t = 0.0;
    let mut sorted: Vec<(usize, f64)> = times.iter().cloned().enumerate().collect();
    sorted.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut result = vec![[0.0; 4]; times.len()];
    let mut k = 0;
    while t <= end + dt {
        while k < sorted.len() && sorted[k].1 <= t + 1e-9 {
            result[sorted[k].0] = state;
            k += 1;
        }
        let drive = link_rise(&heat.at(t + dt / 2.0, logged));
        let f = (-dt / tau).exp();
        for i in 0..4 {
            state[i] = drive[i] + (state[i] - drive[i]) * f;
        }
        t += dt;
    }
    result
}

/// What a set's seed draws before its effects act: the real robot's fixed
/// departures, its warm-up and its poses, and the generator's state after
/// them (the noise and the visiting order come from it).
struct World {
    rng: ChaCha8Rng,
    geometry: Geometry,
    heat: Heat,
    poses: Vec<[f64; 6]>,
}

fn draw_world(spec: &SetSpec) -> World {
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let n = |rng: &mut ChaCha8Rng, s: f64| Normal::new(0.0, s).unwrap().sample(rng);
    let small = |rng: &mut ChaCha8Rng| {
        Isometry3::from_parts(
            Translation3::new(
                n(rng, spec.geometry_mm),
                n(rng, spec.geometry_mm),
                n(rng, spec.geometry_mm),
            ),
            UnitQuaternion::from_scaled_axis(Vector3::new(
                n(rng, spec.geometry_rad),
                n(rng, spec.geometry_rad),
                n(rng, spec.geometry_rad),
            )),
        )
    };
    let heading = rng.random_range(0.0..std::f64::consts::TAU);
    let tracker_pos = Vector3::new(
        spec.tracker_mm * heading.cos(),
        spec.tracker_mm * heading.sin(),
        rng.random_range(-300.0..500.0),
    );
    // The tracker's own axes: any heading, levelled to within a degree.
    let tracker_rot = rz(rng.random_range(0.0..std::f64::consts::TAU))
        * rx(rng.random_range(-1.0f64..1.0).to_radians())
        * ry(rng.random_range(-1.0f64..1.0).to_radians());
    let tracker = Isometry3::from_parts(Translation3::from(tracker_pos), tracker_rot).inverse();
    let geometry = Geometry {
        origin: std::array::from_fn(|_| small(&mut rng)),
        zero: std::array::from_fn(|_| n(&mut rng, spec.geometry_rad)),
        // A reflector on the flange as the nominal tool0 point says, off by
        // what mounting it leaves.
        reflector: Vector3::new(n(&mut rng, 0.1), n(&mut rng, 0.1), n(&mut rng, 0.1)),
        tracker,
    };
    let heat = Heat::new(&mut rng);
    let poses: Vec<[f64; 6]> = (0..spec.poses)
        .map(|_| match spec.arm {
            Arm::Irb140 => random_pose(&mut rng),
            Arm::Ur5 => super::world_ur5::random_pose(&mut rng),
        })
        .collect();
    World {
        rng,
        geometry,
        heat,
        poses,
    }
}

/// The amplitude (rad) of a cyclic error of `axis` (1-based), `cycles` per
/// turn at `phase`, that moves the measured point over the poses of `spec`
/// by `ratio` times the set's noise per axis, RMS: computed from the
/// generator's own chain (the real robot's geometry, cold), so that the
/// error is in the data by a known margin whatever the axis's lever on
/// these poses. The displacement is linear in the amplitude at these sizes
/// (a microradian's move, scaled).
pub fn cyclic_amplitude(spec: &SetSpec, axis: usize, cycles: f64, phase: f64, ratio: f64) -> f64 {
    let world = draw_world(spec);
    let i = axis - 1;
    let eps = 1e-6;
    let at = |q: &[f64; 6], dq: f64| {
        let mut s = State::cold();
        s.dq[i] = dq;
        match spec.arm {
            Arm::Irb140 => position(&world.geometry, &s, q),
            Arm::Ur5 => super::world_ur5::position(&world.geometry, &s, q),
        }
    };
    let sum: f64 = world
        .poses
        .iter()
        .map(|q| (at(q, eps * (cycles * q[i] + phase).sin()) - at(q, 0.0)).norm_squared())
        .sum();
    // Per axis: the squared move shared among the three axes.
    let per_axis = (sum / (3.0 * world.poses.len().max(1) as f64)).sqrt() / eps;
    ratio * spec.noise_mm / per_axis.max(1e-9)
}

/// Generate one data set.
pub fn generate(spec: &SetSpec) -> DataSet {
    let World {
        mut rng,
        geometry,
        heat,
        poses,
    } = draw_world(spec);
    let lag_tau = spec.effects.iter().find_map(|e| match e {
        Effect::ThermalLag(t) => Some(*t),
        _ => None,
    });
    let lagged = lag_tau.map(|tau| lagged_rises(&heat, spec.temps_logged, &spec.times, tau));
    let noise = Normal::new(0.0, spec.noise_mm).unwrap();
    let mut csv = String::from("time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm");
    if spec.temps_logged {
        csv.push_str(",t1_c,t2_c,t3_c,t4_c,t5_c,t6_c");
    }
    csv.push_str(",pose\n");
    let mut rows = 0;
    // The measurement program visits the poses in one fixed order each
    // sweep, a minute apart at most.
    let mut order: Vec<usize> = (0..spec.poses).collect();
    order.shuffle(&mut rng);
    let mut last_q = poses[order[spec.poses - 1]];
    for (ti, &t0) in spec.times.iter().enumerate() {
        for (k, &pi) in order.iter().enumerate() {
            let t = t0 + 0.05 * k as f64;
            let q = poses[pi];
            let temps = heat.at(t, spec.temps_logged);
            let motor = link_rise(&temps);
            let structure = match &lagged {
                Some(l) => l[ti],
                None => motor,
            };
            let mut scale = [1.0; 4];
            let mut state = State {
                len: [C1, A1, C2, C3, C4],
                grow: [1.0; 4],
                dq: [0.0; 6],
                bend: [0.0; 2],
                base: Isometry3::identity(),
            };
            for e in &spec.effects {
                match e {
                    Effect::ExpansionScale(k) => scale = *k,
                    Effect::ThermalLag(_) => {}
                    Effect::ArmBending(b) => {
                        state.bend = [b[0] * structure[1], b[1] * structure[2]];
                    }
                    Effect::JointOffsetDrift(c) => {
                        for i in 0..6 {
                            state.dq[i] += c[i] * (temps[i] - T_REF);
                        }
                    }
                    Effect::MountDrift(shift, tilt) => {
                        let rise = temps[0] - T_REF;
                        state.base = Isometry3::from_parts(
                            Translation3::from(shift * rise),
                            UnitQuaternion::from_scaled_axis(Vector3::new(
                                tilt[0] * rise,
                                tilt[1] * rise,
                                0.0,
                            )),
                        ) * state.base;
                    }
                    Effect::GravitySag(_) if spec.arm != Arm::Irb140 => {
                        panic!("the world's gravity torques are the IRB 140's")
                    }
                    Effect::GravitySag(c) => {
                        let tq = gravity_torque(&q);
                        state.dq[1] += c[0] * tq[0];
                        state.dq[2] += c[1] * tq[1];
                    }
                    Effect::Knock(at, shift) => {
                        if t > *at {
                            state.base = Isometry3::from_parts(
                                Translation3::from(*shift),
                                UnitQuaternion::identity(),
                            ) * state.base;
                        }
                    }
                    Effect::Backlash(axis, beta) => {
                        let i = axis - 1;
                        let came_up = q[i] > last_q[i];
                        state.dq[i] += if came_up { -beta / 2.0 } else { beta / 2.0 };
                    }
                    Effect::Cyclic(axis, cycles, amp, phase) => {
                        let i = axis - 1;
                        state.dq[i] += amp * (cycles * q[i] + phase).sin();
                    }
                    Effect::QuadraticExpansion(_) => {}
                }
            }
            let quadratic = spec.effects.iter().find_map(|e| match e {
                Effect::QuadraticExpansion(beta) => Some(*beta),
                _ => None,
            });
            state.grow = std::array::from_fn(|link| {
                let r = structure[link];
                1.0 + K0 * ALPHA * (scale[link] * r + quadratic.map_or(0.0, |b| b * r * r / 10.0))
            });
            let g = state.grow;
            state.len = [C1 * g[0], A1 * g[0], C2 * g[1], C3 * g[2], C4 * g[3]];
            let p = match spec.arm {
                Arm::Irb140 => position(&geometry, &state, &q),
                Arm::Ur5 => super::world_ur5::position(&geometry, &state, &q),
            };
            let p = p + Vector3::new(
                noise.sample(&mut rng),
                noise.sample(&mut rng),
                noise.sample(&mut rng),
            );
            last_q = q;
            let deg = q.map(|a| format!("{:.5}", a.to_degrees()));
            csv.push_str(&format!(
                "{t:.2},{},{:.4},{:.4},{:.4}",
                deg.join(","),
                p.x,
                p.y,
                p.z
            ));
            if spec.temps_logged {
                // A logger with 0.1 K resolution.
                let logged = temps.map(|c| format!("{:.1}", c));
                csv.push_str(&format!(",{}", logged.join(",")));
            }
            csv.push_str(&format!(",P{}\n", pi + 1));
            rows += 1;
        }
    }
    DataSet { csv, rows }
}

/// The nominal flange position (no error, no warmth, base frame): the
/// check values of `docs/model.md` pin this chain to the ABB convention.
pub fn nominal_flange(q: &[f64; 6]) -> Vector3<f64> {
    position(&Geometry::exact(), &State::cold(), q)
}

impl Geometry {
    /// No error, measured at the flange, in the base frame.
    pub(super) fn exact() -> Geometry {
        Geometry {
            origin: [Isometry3::identity(); 6],
            zero: [0.0; 6],
            reflector: Vector3::zeros(),
            tracker: Isometry3::identity(),
        }
    }
}

impl State {
    /// The cold, nominal arm.
    pub(super) fn cold() -> State {
        State {
            len: [C1, A1, C2, C3, C4],
            grow: [1.0; 4],
            dq: [0.0; 6],
            bend: [0.0; 2],
            base: Isometry3::identity(),
        }
    }
}

#[test]
fn the_generators_chain_meets_the_spec_check_values() {
    for (q, p) in [
        ([0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [515.0, 0.0, 712.0]),
        ([0.0, 0.0, 0.0, 0.0, 90.0, 0.0], [450.0, 0.0, 647.0]),
        ([90.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 515.0, 712.0]),
        (
            [30.0, 20.0, -40.0, 50.0, 60.0, 70.0],
            [492.1012, 333.9077, 797.3712],
        ),
    ] {
        let q = q.map(f64::to_radians);
        let got = nominal_flange(&q);
        assert!(
            (got - Vector3::from(p)).norm() < 1e-3,
            "{q:?}: {got:?} against {p:?}"
        );
    }
}
