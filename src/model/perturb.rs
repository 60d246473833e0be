//! The perturbed chain of one row: the base model's expanded geometry and
//! what each effect adds to it, and the flange pose that results.

use super::chain::Perturbation;
use super::effects::{Effect, EffectKind};
use super::expansion::ThermalExpansion;
use super::general::{fk_general, gravity_levers, link_lengths};
use crate::robot::chain::Chain;
use crate::robot::{Joints, LinkScales, Opw};
use crate::thermal::{Lagged, MotorTemps, TempHistory};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::sync::Arc;

/// The nominal geometry of the arm: OPW lengths (the ABB arms, in ABB's
/// joint convention) or any serial chain read from a URDF (in the URDF's
/// own joint convention).
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    Opw(Opw),
    Chain(Arc<Chain>),
}

impl Geometry {
    /// Flange pose of the cold, nominal arm.
    pub fn fk(&self, q: &Joints) -> Isometry3<f64> {
        match self {
            Geometry::Opw(o) => o.fk(q),
            Geometry::Chain(c) => c.fk(q),
        }
    }

    /// Flange pose of the arm with its links scaled (base, lower arm,
    /// upper arm, wrist) and nothing else.
    pub fn fk_scaled(&self, q: &Joints, scales: &LinkScales) -> Isometry3<f64> {
        match self {
            Geometry::Opw(o) => {
                super::chain::fk_chain(&o.scaled(scales), q, &Perturbation::default())
            }
            Geometry::Chain(c) => c.fk_scaled(q, scales),
        }
    }

    /// The OPW lengths, when the arm is written by them.
    pub fn opw(&self) -> Option<&Opw> {
        match self {
            Geometry::Opw(o) => Some(o),
            Geometry::Chain(_) => None,
        }
    }

    /// Whether parameter `idx` of `kind` has a place on this arm: a general
    /// chain has no OPW lengths (its joint origins take their role), and
    /// with the links' masses gravity sag has two compliances, not three
    /// levers. Parameters without a place are held at zero, never fitted.
    pub fn has_param(&self, kind: EffectKind, idx: usize) -> bool {
        match self {
            Geometry::Opw(_) => true,
            Geometry::Chain(c) => match kind {
                EffectKind::GeometryOffset => !super::effects::GEOMETRY_OPW_LENGTHS.contains(&idx),
                EffectKind::GravitySag => c.masses.is_empty() || idx != 1,
                _ => true,
            },
        }
    }

    /// Lengths of the lower and upper arm, mm (what bending curves).
    pub fn arm_lengths(&self) -> [f64; 2] {
        match self {
            Geometry::Opw(o) => [o.c2, o.c3],
            Geometry::Chain(c) => link_lengths(c),
        }
    }
}

/// The simulation the diagnosis starts from: nominal geometry and the base
/// thermal-expansion model.
#[derive(Debug, Clone, PartialEq)]
pub struct Base {
    pub nominal: Geometry,
    pub thermal: ThermalExpansion,
    /// The measured point (a tracker's reflector) in the chain's flange
    /// frame, mm; zero measures the flange itself.
    pub point: Vector3<f64>,
}

impl Default for Base {
    fn default() -> Self {
        Base {
            nominal: Geometry::Opw(crate::robot::irb140_opw()),
            thermal: ThermalExpansion::default(),
            point: Vector3::zeros(),
        }
    }
}

/// The warm geometry of a row before the effects' perturbation: the OPW
/// lengths expanded, or a general chain's link factors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Warm {
    Opw(Opw),
    Scales(LinkScales),
}

/// What the effects of one row depend on.
#[derive(Debug, Clone, Copy)]
pub struct RowState {
    pub q: Joints,
    /// Motor temperatures at the row's time.
    pub temps: MotorTemps,
    /// Motor temperatures through each link's thermal lag (base, lower
    /// arm, upper arm, wrist): the structure's temperatures, present when a
    /// thermal-lag effect is in the set.
    pub lagged: Option<[MotorTemps; 4]>,
}

/// What `effects` make of every row alike, computed once for many rows: a
/// geometry offset's joint-origin transforms and a tracker frame's
/// transform, per effect (in its order). Evaluating a fit's rows, they were
/// a third of the chain's cost when made again for each row.
pub struct RowFree {
    per_effect: Vec<Fixed>,
}

enum Fixed {
    None,
    Origins(Box<[Isometry3<f64>; 6]>),
    Frame(Isometry3<f64>),
}

impl RowFree {
    pub fn new(effects: &[Effect]) -> RowFree {
        let small = |e: &Effect, k: usize| {
            Isometry3::from_parts(
                Translation3::new(e.get(k), e.get(k + 1), e.get(k + 2)),
                UnitQuaternion::from_scaled_axis(
                    Vector3::new(e.get(k + 3), e.get(k + 4), e.get(k + 5)) * 1e-3,
                ),
            )
        };
        let per_effect = effects
            .iter()
            .map(|e| match e.kind {
                EffectKind::GeometryOffset => {
                    let g = super::effects::GEOMETRY_ORIGINS_FROM;
                    // Joint origins only where they are not all zero: the
                    // products they add are a third of the chain's cost.
                    if (g..g + 36).any(|k| e.get(k) != 0.0) {
                        Fixed::Origins(Box::new(std::array::from_fn(|j| small(e, g + 6 * j))))
                    } else {
                        Fixed::None
                    }
                }
                EffectKind::TrackerFrame => Fixed::Frame(small(e, 0)),
                _ => Fixed::None,
            })
            .collect();
        RowFree { per_effect }
    }
}

/// The expanded base geometry of a row and the perturbation of `effects`.
pub fn perturbation(base: &Base, effects: &[Effect], row: &RowState) -> (Warm, Perturbation) {
    perturbation_with(base, effects, &RowFree::new(effects), row)
}

/// [`perturbation`] with what the effects make of every row alike computed
/// before (`free`, of these `effects`).
pub fn perturbation_with(
    base: &Base,
    effects: &[Effect],
    free: &RowFree,
    row: &RowState,
) -> (Warm, Perturbation) {
    // `free` is made of these effects: an effect without its entry would
    // lose its origins or frame without a word.
    debug_assert_eq!(free.per_effect.len(), effects.len());
    let th = &base.thermal;
    let [l_lower, l_upper] = base.nominal.arm_lengths();
    let mut pert = Perturbation {
        point: base.point,
        ..Perturbation::default()
    };
    let motor_rise = th.link_temps(&row.temps).map(|t| t - th.t_ref);
    // The structure's temperature: the motors' unless a lag is modelled.
    let has_lag = effects.iter().any(|e| e.kind == EffectKind::ThermalLag);
    let struct_rise = match row.lagged {
        Some(l) if has_lag => [
            th.base.temperature(&l[0]) - th.t_ref,
            th.lower_arm.temperature(&l[1]) - th.t_ref,
            th.upper_arm.temperature(&l[2]) - th.t_ref,
            th.wrist.temperature(&l[3]) - th.t_ref,
        ],
        _ => motor_rise,
    };
    let mut scale = [1.0; 4];
    let mut thermal_lengths = false;
    for (ei, e) in effects.iter().enumerate() {
        match e.kind {
            EffectKind::ExpansionScale => {
                thermal_lengths = true;
                for (i, s) in scale.iter_mut().enumerate() {
                    *s += e.get(i);
                }
            }
            EffectKind::ThermalLag => thermal_lengths = true,
            EffectKind::ArmBending => {
                // κ = (tip rotation per K)·ΔT / L.
                pert.kappa_lower += e.get(0) * 1e-6 * struct_rise[1] / l_lower.max(1e-9);
                pert.kappa_upper += e.get(1) * 1e-6 * struct_rise[2] / l_upper.max(1e-9);
            }
            EffectKind::JointOffsetDrift => {
                for i in 0..6 {
                    pert.dq[i] += e.get(i) * 1e-6 * (row.temps[i] - th.t_ref);
                }
            }
            EffectKind::MountDrift => {
                let rise = row.temps[0] - th.t_ref;
                let t = Vector3::new(e.get(0), e.get(1), e.get(2)) * (1e-3 * rise);
                let r = UnitQuaternion::from_scaled_axis(Vector3::new(
                    e.get(3) * 1e-6 * rise,
                    e.get(4) * 1e-6 * rise,
                    0.0,
                ));
                pert.base = Isometry3::from_parts(Translation3::from(t), r) * pert.base;
            }
            EffectKind::GravitySag => {
                // Gravity torques of a two-link arm in its vertical plane are
                // combinations of the two lever arms, whatever the masses.
                let [lower, upper2, upper3] = match &base.nominal {
                    Geometry::Opw(_) => {
                        let upper = (row.q[1] + row.q[2]).cos();
                        [row.q[1].sin(), upper, upper]
                    }
                    Geometry::Chain(c) => gravity_levers(c, &row.q),
                };
                pert.dq[1] += 1e-6 * (e.get(0) * lower + e.get(1) * upper2);
                pert.dq[2] += 1e-6 * e.get(2) * upper3;
            }
            EffectKind::GeometryOffset => {
                // The OPW lengths: a general chain's joint origins take
                // their role (and they are never fitted there).
                for i in 0..5 {
                    pert.dlen[i] += e.get(i);
                }
                for i in 0..6 {
                    pert.dq[i] += 1e-3 * e.get(5 + i);
                }
                pert.dlen[5] += e.get(11);
                pert.dlen[6] += e.get(12);
                if let Some(Fixed::Origins(small)) = free.per_effect.get(ei) {
                    let origins = pert.origin.get_or_insert([Isometry3::identity(); 6]);
                    for (o, s) in origins.iter_mut().zip(small.iter()) {
                        *o = s * *o;
                    }
                }
                let g = super::effects::GEOMETRY_ORIGINS_FROM;
                pert.point += Vector3::new(e.get(g + 36), e.get(g + 37), e.get(g + 38));
            }
            EffectKind::TrackerFrame => {
                if let Some(Fixed::Frame(f)) = free.per_effect.get(ei) {
                    pert.frame = f * pert.frame;
                }
            }
        }
    }
    let mut scales = th.scales(&row.temps);
    if thermal_lengths {
        // Structure expansion replaces the base model's motor-driven one.
        // The effective coefficients of the model in use: an
        // expansion-scale factor is relative to them, K0 included.
        let alpha = [
            th.base.alpha,
            th.lower_arm.alpha,
            th.upper_arm.alpha,
            th.wrist.alpha,
        ]
        .map(|a| a * th.k0);
        let extra =
            |link: usize| alpha[link] * (scale[link] * struct_rise[link] - motor_rise[link]);
        match &base.nominal {
            Geometry::Opw(nominal) => {
                pert.dlen[0] += nominal.c1 * extra(0);
                pert.dlen[1] += nominal.a1 * extra(0);
                pert.dlen[2] += nominal.c2 * extra(1);
                pert.dlen[3] += nominal.c3 * extra(2);
                pert.dlen[4] += nominal.c4 * extra(3);
            }
            Geometry::Chain(_) => {
                for (link, s) in scales.iter_mut().enumerate() {
                    *s += extra(link);
                }
            }
        }
    }
    let warm = match &base.nominal {
        Geometry::Opw(nominal) => Warm::Opw(nominal.scaled(&scales)),
        Geometry::Chain(_) => Warm::Scales(scales),
    };
    (warm, pert)
}

/// Flange pose of a row's perturbed chain.
pub fn fk_perturbed(base: &Base, warm: &Warm, q: &Joints, pert: &Perturbation) -> Isometry3<f64> {
    match (warm, &base.nominal) {
        (Warm::Opw(opw), _) => super::chain::fk_chain(opw, q, pert),
        (Warm::Scales(s), Geometry::Chain(c)) => fk_general(c, s, q, pert),
        // A warm state of the other kind than the base (never built by
        // `perturbation`): the OPW lengths scaled by the factors.
        (Warm::Scales(s), Geometry::Opw(o)) => super::chain::fk_chain(&o.scaled(s), q, pert),
    }
}

/// Flange pose of a row with `effects` added to the base model.
pub fn predict(base: &Base, effects: &[Effect], row: &RowState) -> Isometry3<f64> {
    predict_with(base, effects, &RowFree::new(effects), row)
}

/// [`predict`] with what the effects make of every row alike computed
/// before (`free`, of these `effects`).
pub fn predict_with(
    base: &Base,
    effects: &[Effect],
    free: &RowFree,
    row: &RowState,
) -> Isometry3<f64> {
    let (warm, pert) = perturbation_with(base, effects, free, row);
    fk_perturbed(base, &warm, &row.q, &pert)
}

/// The thermal-lag time constants (base, lower arm, upper arm, wrist) of a
/// set of effects, if it has a lag.
pub fn lag_taus(effects: &[Effect]) -> Option<[f64; 4]> {
    effects
        .iter()
        .find(|e| e.kind == EffectKind::ThermalLag)
        .map(|e| std::array::from_fn(|i| e.get(i).max(0.0)))
}

/// A temperature history through each link's lag, for the effects' time
/// constants (`None` without a thermal-lag effect).
pub struct LinkLags<'a> {
    lags: [Lagged<'a>; 4],
}

impl<'a> LinkLags<'a> {
    pub fn new(history: &'a TempHistory, effects: &[Effect]) -> Option<LinkLags<'a>> {
        lag_taus(effects).map(|taus| LinkLags {
            lags: taus.map(|tau| history.lagged(tau)),
        })
    }

    /// Lagged motor temperatures per link at `t` minutes.
    pub fn at(&self, t: f64) -> [MotorTemps; 4] {
        std::array::from_fn(|i| self.lags[i].at(t))
    }
}
