//! The generator of the widened evaluation: a seeded tracker session on
//! one of the arms, in one of the forms the world sends, with one library
//! effect (or none) withheld at a drawn size, and the truth recorded.
//!
//! The real arm is the library's own chain of the arm's URDF (the IRB 140's
//! OPW chain for it), perturbed by the library's effects: what is tested is
//! whether the diagnosis finds what is there, on arms and data it was not
//! tuned on, not the chain itself (`tests/diagnose/general.rs` checks the
//! chain of a URDF against its forward kinematics, `world.rs` the IRB 140
//! against an independent chain). The nuisance is a real session's: an
//! error of every joint origin (0.1 mm, 0.3 mrad) and zero (0.3 mrad), a
//! reflector 0.1 mm off the flange, 0.01-0.035 mm of noise per axis, and,
//! where the registration is unknown, a tracker metres away at any heading.
//!
//! The motor temperatures are the session's own (each axis warming to its
//! own level along its own time constant; an overnight session stops and
//! cools), never the IRB 140's heating profile: where they are not logged,
//! the diagnosis has no way to know them.

use super::arms::{random_pose, WideArm};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rapidtherm::diagnose::arm::Arm as DiagArm;
use rapidtherm::model::{predict, Base, Effect, EffectKind, LinkLags, Model, RowState};
use rapidtherm::robot::Joints;
use rapidtherm::thermal::{MotorTemps, TempHistory};

/// What is withheld: nothing, or one effect of the library.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    Nothing,
    Effect(EffectKind),
}

impl Class {
    /// Every class of the evaluation: nothing, and each library effect a
    /// real arm can have (the geometric calibration and the tracker frame
    /// are in every set, as nuisance).
    pub const ALL: [Class; 7] = [
        Class::Nothing,
        Class::Effect(EffectKind::ExpansionScale),
        Class::Effect(EffectKind::ThermalLag),
        Class::Effect(EffectKind::ArmBending),
        Class::Effect(EffectKind::JointOffsetDrift),
        Class::Effect(EffectKind::MountDrift),
        Class::Effect(EffectKind::GravitySag),
    ];

    pub fn name(self) -> &'static str {
        match self {
            Class::Nothing => "nothing",
            Class::Effect(k) => k.name(),
        }
    }
}

/// The form of a data set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Form {
    pub arm: WideArm,
    /// Motor temperature columns in the file.
    pub temps: bool,
    /// Poses measured again and again (else each pose once).
    pub repeats: bool,
    /// A clock (else `time_min` is only the rows' order).
    pub clock: bool,
    /// The data in the robot's base frame (else in a tracker's frame, and
    /// the diagnosis registers).
    pub registered: bool,
}

impl Form {
    /// The number of forms: 4 arms × 2⁴.
    pub const COUNT: usize = 64;

    /// Form `i` of [`Form::COUNT`].
    pub fn of_index(i: usize) -> Form {
        let i = i % Form::COUNT;
        Form {
            arm: WideArm::ALL[i % 4],
            temps: i & 4 == 0,
            repeats: i & 8 == 0,
            clock: i & 16 == 0,
            registered: i & 32 == 0,
        }
    }

    /// A short label, e.g. `ur5 temps repeats clock registered`.
    pub fn label(self) -> String {
        format!(
            "{} {} {} {} {}",
            self.arm.name(),
            if self.temps { "temps" } else { "no-temps" },
            if self.repeats {
                "repeats"
            } else {
                "no-repeats"
            },
            if self.clock { "clock" } else { "order" },
            if self.registered {
                "registered"
            } else {
                "unregistered"
            }
        )
    }
}

/// One set to make.
#[derive(Debug, Clone, Copy)]
pub struct Spec {
    pub class: Class,
    pub form: Form,
    pub seed: u64,
}

/// One measured row as the physics made it.
#[derive(Debug, Clone)]
pub struct TrueRow {
    /// The robot's joints, rad.
    pub q: Joints,
    /// The chain's angles of them.
    pub qc: Joints,
    /// Real minutes since the cold start.
    pub time_min: f64,
    pub temps: MotorTemps,
    pub pose: usize,
}

/// What was in a set.
#[derive(Debug, Clone)]
pub struct Truth {
    /// The withheld effect at the size drawn (library parameters).
    pub effect: Option<Effect>,
    /// Its RMS move of the measured point per axis over the rows, mm.
    pub size_mm: f64,
    /// The noise per axis, mm (never given to the diagnosis).
    pub noise_mm: f64,
    /// The effect's move of every row's measured point, base frame, mm.
    pub moved: Vec<Vector3<f64>>,
    /// Without temperature columns, everything thermal the session did
    /// (the arm's own expansion as the model says, with the session's
    /// temperatures, and a withheld thermal effect) against the arm kept
    /// cold: a drift in time nothing in the file explains. Zero with the
    /// columns (the model's expansion then follows them).
    pub drift: Vec<Vector3<f64>>,
    pub rows: Vec<TrueRow>,
    pub poses: usize,
}

/// A generated set: the CSV the session leaves and what was in it.
pub struct Set {
    pub csv: String,
    pub truth: Truth,
    /// The arm as the diagnosis models it, and its base model.
    pub arm: DiagArm,
    pub base: Base,
    /// The session's temperatures as the library's lag integrates them.
    pub history: TempHistory,
}

/// Each axis warms to its own level along its own time constant; an
/// overnight session stops once and cools.
struct Heat {
    t_ref: f64,
    rise: [f64; 6],
    tau: [f64; 6],
    stop: Option<f64>,
}

impl Heat {
    fn at(&self, t: f64) -> MotorTemps {
        std::array::from_fn(|i| {
            let warm = |t: f64| self.rise[i] * (1.0 - (-t / self.tau[i]).exp());
            let rise = match self.stop {
                Some(s) if t > s => warm(s) * (-(t - s) / (1.5 * self.tau[i])).exp(),
                _ => warm(t),
            };
            self.t_ref + rise
        })
    }
}

fn normal(rng: &mut ChaCha8Rng, sd: f64) -> f64 {
    Normal::new(0.0, sd).unwrap().sample(rng)
}

/// The arm's fixed departures from nominal as the library's geometric
/// calibration writes them: every joint zero, every joint origin, the
/// reflector on the flange.
fn geometry(rng: &mut ChaCha8Rng) -> Effect {
    let mut e = Effect::zero(EffectKind::GeometryOffset);
    let set = |e: &mut Effect, name: String, v: f64| {
        e.set(&name, &format!("{v:.9}"))
            .unwrap_or_else(|err| panic!("{name}: {}", err.message));
    };
    for j in 1..=6 {
        set(&mut e, format!("dq{j}_mrad"), normal(rng, 0.3));
    }
    for j in 1..=6 {
        for a in ["x", "y", "z"] {
            set(&mut e, format!("j{j}_{a}_mm"), normal(rng, 0.1));
        }
        for a in ["rx", "ry", "rz"] {
            set(&mut e, format!("j{j}_{a}_mrad"), normal(rng, 0.3));
        }
    }
    for a in ["x", "y", "z"] {
        set(&mut e, format!("point_{a}_mm"), normal(rng, 0.1));
    }
    e
}

/// The measured point of every row with `effects` on the real arm (base
/// frame).
pub fn points(
    base: &Base,
    history: &TempHistory,
    rows: &[TrueRow],
    effects: &[Effect],
) -> Vec<Vector3<f64>> {
    let lags = LinkLags::new(history, effects);
    rows.iter()
        .map(|r| {
            let state = RowState {
                q: r.qc,
                temps: r.temps,
                lagged: lags.as_ref().map(|l| l.at(r.time_min)),
            };
            predict(base, effects, &state).translation.vector
        })
        .collect()
}

fn rms_per_axis(v: &[Vector3<f64>]) -> f64 {
    (v.iter().map(|d| d.norm_squared()).sum::<f64>() / (3.0 * v.len().max(1) as f64)).sqrt()
}

/// The move of `effect` on top of the arm's own geometry.
fn moved(
    base: &Base,
    history: &TempHistory,
    rows: &[TrueRow],
    geom: &Effect,
    effect: &Effect,
) -> Vec<Vector3<f64>> {
    let without = points(base, history, rows, std::slice::from_ref(geom));
    let with = points(base, history, rows, &[geom.clone(), effect.clone()]);
    with.iter().zip(&without).map(|(a, b)| a - b).collect()
}

/// The withheld effect of `kind` whose move is `size` mm RMS per axis:
/// the default parameters scaled (every effect but the lag is linear in
/// them at these sizes); a lag's common time constant found by bisection
/// (its move grows with it), at most 600 min.
fn sized(
    kind: EffectKind,
    size: f64,
    base: &Base,
    history: &TempHistory,
    rows: &[TrueRow],
    geom: &Effect,
) -> Effect {
    if kind == EffectKind::ThermalLag {
        let lag = |tau: f64| Effect {
            kind,
            params: vec![tau; 4],
        };
        let of = |tau: f64| rms_per_axis(&moved(base, history, rows, geom, &lag(tau)));
        let (mut lo, mut hi) = (0.0, 600.0);
        if of(hi) <= size {
            return lag(hi);
        }
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if of(mid) < size {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        return lag(0.5 * (lo + hi));
    }
    let shape = Effect::with_defaults(kind);
    let unit = rms_per_axis(&moved(base, history, rows, geom, &shape));
    let m = if unit > 0.0 { size / unit } else { 0.0 };
    Effect {
        kind,
        params: shape.params.iter().map(|p| p * m).collect(),
    }
}

/// Make the set of `spec`.
pub fn generate(spec: &Spec) -> Set {
    let form = spec.form;
    let robot = form.arm.robot();
    let arm = form.arm.diag_arm(&robot);
    let model = Model::default();
    let base = arm.base(&model);
    let t_ref = base.thermal.t_ref;
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let noise_mm = rng.random_range(0.01..0.035);
    // A 3-hour warm-up, or a 12-hour overnight session.
    let overnight = rng.random_bool(0.5);
    let end = if overnight { 720.0 } else { 180.0 };
    let heat = Heat {
        t_ref,
        rise: std::array::from_fn(|_| rng.random_range(8.0..25.0)),
        tau: std::array::from_fn(|_| rng.random_range(30.0..90.0)),
        stop: overnight.then(|| end * rng.random_range(0.5..0.8)),
    };
    let geom = geometry(&mut rng);
    // The tracker: any heading, levelled within a degree, metres away.
    let tracker = if form.registered {
        Isometry3::identity()
    } else {
        let (lo, hi) = form.arm.tracker_range_mm();
        let d = rng.random_range(lo..hi);
        let heading = rng.random_range(0.0..std::f64::consts::TAU);
        let at = Vector3::new(
            d * heading.cos(),
            d * heading.sin(),
            rng.random_range(-300.0..500.0),
        );
        let turn = UnitQuaternion::from_axis_angle(
            &Vector3::z_axis(),
            rng.random_range(0.0..std::f64::consts::TAU),
        ) * UnitQuaternion::from_axis_angle(
            &Vector3::x_axis(),
            rng.random_range(-1.0f64..1.0).to_radians(),
        ) * UnitQuaternion::from_axis_angle(
            &Vector3::y_axis(),
            rng.random_range(-1.0f64..1.0).to_radians(),
        );
        Isometry3::from_parts(Translation3::from(at), turn).inverse()
    };
    // The measurement program: a few poses swept again and again (a sweep
    // every 6-10 min of a warm-up, every 30-45 min overnight), or many
    // poses each measured once, evenly over the session.
    let limits = robot.limits;
    let mut plan: Vec<(usize, f64)> = Vec::new();
    let poses: Vec<Joints> = if form.repeats {
        let n = rng.random_range(12..=20usize);
        let poses: Vec<Joints> = (0..n).map(|_| random_pose(&mut rng, &limits)).collect();
        let step = if overnight {
            rng.random_range(30.0..45.0)
        } else {
            rng.random_range(6.0..10.0)
        };
        let mut order: Vec<usize> = (0..n).collect();
        order.shuffle(&mut rng);
        let mut t0 = 0.0;
        while t0 <= end {
            for (k, &p) in order.iter().enumerate() {
                plan.push((p, t0 + 0.25 * k as f64));
            }
            t0 += step;
        }
        poses
    } else {
        let n = rng.random_range(60..=120usize);
        let poses: Vec<Joints> = (0..n).map(|_| random_pose(&mut rng, &limits)).collect();
        for p in 0..n {
            plan.push((p, end * p as f64 / (n - 1) as f64));
        }
        poses
    };
    let rows: Vec<TrueRow> = plan
        .iter()
        .map(|&(p, t)| TrueRow {
            q: poses[p],
            qc: arm.map.to_chain(&poses[p]),
            time_min: t,
            temps: heat.at(t),
            pose: p,
        })
        .collect();
    // The session's temperatures minute by minute, as the lag integrates
    // them.
    let last = rows.iter().map(|r| r.time_min).fold(0.0, f64::max);
    let records: Vec<(f64, MotorTemps)> = (0..=(last.ceil() as usize + 1))
        .map(|m| (m as f64, heat.at(m as f64)))
        .collect();
    let history = TempHistory::from_records(&records, t_ref);
    // The size: from zero to four times the noise, as u² (half the sets
    // below the noise, so that the detection limit falls inside the range
    // on every arm and form).
    let u: f64 = rng.random_range(0.0..1.0);
    let effect = match spec.class {
        Class::Nothing => None,
        Class::Effect(kind) => Some(sized(
            kind,
            4.0 * noise_mm * u * u,
            &base,
            &history,
            &rows,
            &geom,
        )),
    };
    let moved_by = match &effect {
        Some(e) => moved(&base, &history, &rows, &geom, e),
        None => vec![Vector3::zeros(); rows.len()],
    };
    let mut all = vec![geom];
    all.extend(effect.iter().cloned());
    let real = points(&base, &history, &rows, &all);
    let noise = Normal::new(0.0, noise_mm).unwrap();
    let mut csv = String::from("time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm");
    if form.temps {
        csv.push_str(",t1_c,t2_c,t3_c,t4_c,t5_c,t6_c");
    }
    if form.repeats {
        csv.push_str(",pose");
    }
    csv.push('\n');
    for (k, (r, p)) in rows.iter().zip(&real).enumerate() {
        let m = tracker.transform_point(&(*p).into()).coords
            + Vector3::new(
                noise.sample(&mut rng),
                noise.sample(&mut rng),
                noise.sample(&mut rng),
            );
        // Without a clock the file's time is only the rows' order.
        let t = if form.clock {
            r.time_min
        } else {
            0.1 * k as f64
        };
        let deg = r.q.map(|a| format!("{:.6}", a.to_degrees()));
        csv.push_str(&format!(
            "{t:.3},{},{:.4},{:.4},{:.4}",
            deg.join(","),
            m.x,
            m.y,
            m.z
        ));
        if form.temps {
            // A logger of 0.1 K.
            csv.push_str(&format!(
                ",{}",
                r.temps.map(|c| format!("{c:.1}")).join(",")
            ));
        }
        if form.repeats {
            csv.push_str(&format!(",P{}", r.pose + 1));
        }
        csv.push('\n');
    }
    let drift = if form.temps {
        vec![Vector3::zeros(); rows.len()]
    } else {
        let mut thermal = vec![all[0].clone()];
        thermal.extend(effect.iter().filter(|e| e.kind.is_thermal()).cloned());
        let warm = points(&base, &history, &rows, &thermal);
        let cold_rows: Vec<TrueRow> = rows
            .iter()
            .map(|r| TrueRow {
                temps: [t_ref; 6],
                ..r.clone()
            })
            .collect();
        let cold = points(&base, &history, &cold_rows, &all[..1]);
        warm.iter().zip(&cold).map(|(a, b)| a - b).collect()
    };
    let size_mm = rms_per_axis(&moved_by);
    Set {
        csv,
        truth: Truth {
            effect,
            size_mm,
            noise_mm,
            moved: moved_by,
            drift,
            rows,
            poses: poses.len(),
        },
        arm,
        base,
        history,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rapidtherm::diagnose::measurements::Measurements;

    /// A set's file says what its form says and no more (temperature
    /// columns, pose labels, a clock, the frame), parses with the arm's
    /// limits, and its withheld effect moves the measured point by at most
    /// four times the noise (the draw's range), nothing where nothing is
    /// withheld.
    #[test]
    fn a_set_is_its_form() {
        for (c, class) in Class::ALL.into_iter().enumerate() {
            for f in [0, 27, 38, 53] {
                let form = Form::of_index(f + c);
                let set = generate(&Spec {
                    class,
                    form,
                    seed: 900 + c as u64,
                });
                let header = set.csv.lines().next().unwrap();
                assert_eq!(header.contains("t1_c"), form.temps, "{header}");
                assert_eq!(header.ends_with(",pose"), form.repeats, "{header}");
                let meas = Measurements::parse("set.csv", set.csv.as_bytes(), &set.arm.limits_deg)
                    .unwrap();
                assert_eq!(meas.rows.len(), set.truth.rows.len());
                if !form.clock {
                    for (k, r) in meas.rows.iter().enumerate() {
                        assert!((r.time_min - 0.1 * k as f64).abs() < 1e-9);
                    }
                }
                // The base frame (within the arm's reach of the base's
                // origin: at most 1.2 m, 3.4 m for the KR 210), or a
                // tracker at least 2 m (4 m) away.
                let norms: Vec<f64> = meas.rows.iter().map(|r| r.position.norm()).collect();
                let reach = if form.arm == WideArm::Kr210 {
                    3400.0
                } else {
                    1250.0
                };
                if form.registered {
                    assert!(norms.iter().all(|&n| n < reach), "{}", form.label());
                } else {
                    assert!(norms.iter().all(|&n| n > 600.0), "{}", form.label());
                }
                let t = &set.truth;
                match class {
                    Class::Nothing => assert_eq!(t.size_mm, 0.0),
                    Class::Effect(_) => assert!(
                        t.size_mm <= 4.0 * t.noise_mm * (1.0 + 1e-3),
                        "{}: {} mm at noise {}",
                        class.name(),
                        t.size_mm,
                        t.noise_mm
                    ),
                }
                assert_eq!(t.drift.iter().any(|d| d.norm() > 0.0), !form.temps);
            }
        }
    }
}
