//! The effect library of `shared/spec/effects.md`: each physical departure
//! from the base model, its parameters (units documented per parameter) and
//! how it perturbs the kinematic chain of a row.
//!
//! Every parameter vector of zeros is the base model exactly, so a fit
//! starts from the simulation the user already has.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// The effects the diagnosis knows, by their names in `effects.md`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EffectKind {
    ExpansionScale,
    ThermalLag,
    ArmBending,
    JointOffsetDrift,
    MountDrift,
    GravitySag,
    GeometryOffset,
    TrackerFrame,
}

/// One parameter of an effect.
#[derive(Debug, Clone, Copy)]
pub struct ParamInfo {
    pub name: &'static str,
    pub unit: &'static str,
    pub what: &'static str,
    /// Value used by `simulate` when the user gives none: a magnitude that
    /// moves the IRB 140's flange by a few hundredths to tenths of a mm.
    pub default: f64,
}

const fn p(name: &'static str, unit: &'static str, what: &'static str, default: f64) -> ParamInfo {
    ParamInfo {
        name,
        unit,
        what,
        default,
    }
}

const EXPANSION: &[ParamInfo] = &[
    p("dk_base", "1", "k - 1 of the base link (c1, a1)", -0.5),
    p("dk_lower", "1", "k - 1 of the lower arm (c2)", -0.6),
    p("dk_upper", "1", "k - 1 of the upper arm (c3)", -0.6),
    p("dk_wrist", "1", "k - 1 of the wrist (c4)", -0.5),
];
const LAG: &[ParamInfo] = &[
    p(
        "tau_base_min",
        "min",
        "time constant of the base link's structure temperature behind its motors'",
        30.0,
    ),
    p("tau_lower_min", "min", "same, lower arm", 30.0),
    p("tau_upper_min", "min", "same, upper arm", 30.0),
    p("tau_wrist_min", "min", "same, wrist", 30.0),
];
const BENDING: &[ParamInfo] = &[
    p(
        "lower_urad_per_k",
        "urad/K",
        "tip rotation kL of the lower arm per K of its temperature rise",
        20.0,
    ),
    p(
        "upper_urad_per_k",
        "urad/K",
        "tip rotation kL of the upper arm per K of its temperature rise",
        30.0,
    ),
];
const JOINT_DRIFT: &[ParamInfo] = &[
    p(
        "c1_urad_per_k",
        "urad/K",
        "axis-1 zero drift per K of motor 1",
        20.0,
    ),
    p(
        "c2_urad_per_k",
        "urad/K",
        "axis-2 zero drift per K of motor 2",
        30.0,
    ),
    p(
        "c3_urad_per_k",
        "urad/K",
        "axis-3 zero drift per K of motor 3",
        -30.0,
    ),
    p(
        "c4_urad_per_k",
        "urad/K",
        "axis-4 zero drift per K of motor 4",
        20.0,
    ),
    p(
        "c5_urad_per_k",
        "urad/K",
        "axis-5 zero drift per K of motor 5",
        20.0,
    ),
    p(
        "c6_urad_per_k",
        "urad/K",
        "axis-6 zero drift per K of motor 6",
        20.0,
    ),
];
const MOUNT: &[ParamInfo] = &[
    p(
        "x_um_per_k",
        "um/K",
        "base shift along x per K of motor-1 rise",
        1.0,
    ),
    p(
        "y_um_per_k",
        "um/K",
        "base shift along y per K of motor-1 rise",
        1.0,
    ),
    p(
        "z_um_per_k",
        "um/K",
        "base shift along z per K of motor-1 rise",
        5.0,
    ),
    p("rx_urad_per_k", "urad/K", "base tilt about x per K", 2.0),
    p("ry_urad_per_k", "urad/K", "base tilt about y per K", 2.0),
];
const SAG: &[ParamInfo] = &[
    p(
        "axis2_lower_urad",
        "urad",
        "axis-2 twist at the lower arm horizontal (lever c2*sin q2)",
        100.0,
    ),
    p(
        "axis2_upper_urad",
        "urad",
        "axis-2 twist from the upper arm's weight at it horizontal (lever cos(q2+q3))",
        150.0,
    ),
    p(
        "axis3_urad",
        "urad",
        "axis-3 twist with the upper arm horizontal (lever cos(q2+q3))",
        120.0,
    ),
];
const GEOMETRY: &[ParamInfo] = &[
    p("dc1_mm", "mm", "error of c1", 0.1),
    p("da1_mm", "mm", "error of a1", -0.05),
    p("dc2_mm", "mm", "error of c2", 0.08),
    p("dc3_mm", "mm", "error of c3", -0.1),
    p("dc4_mm", "mm", "error of c4", 0.05),
    p("dq1_mrad", "mrad", "zero offset of axis 1", 0.1),
    p("dq2_mrad", "mrad", "zero offset of axis 2", -0.15),
    p("dq3_mrad", "mrad", "zero offset of axis 3", 0.1),
    p("dq4_mrad", "mrad", "zero offset of axis 4", 0.2),
    p("dq5_mrad", "mrad", "zero offset of axis 5", -0.2),
    p("dq6_mrad", "mrad", "zero offset of axis 6", 0.3),
    p(
        "da2_mm",
        "mm",
        "offset of the wrist centre across the upper arm (a2)",
        0.05,
    ),
    p(
        "db_mm",
        "mm",
        "lateral offset of the arm plane from axis 1 (b)",
        -0.05,
    ),
];
const TRACKER: &[ParamInfo] = &[
    p("x_mm", "mm", "tracker frame origin x", 0.2),
    p("y_mm", "mm", "tracker frame origin y", -0.1),
    p("z_mm", "mm", "tracker frame origin z", 0.15),
    p("rx_mrad", "mrad", "tracker frame rotation about x", 0.1),
    p("ry_mrad", "mrad", "tracker frame rotation about y", -0.1),
    p("rz_mrad", "mrad", "tracker frame rotation about z", 0.2),
];

impl EffectKind {
    pub const ALL: [EffectKind; 8] = [
        EffectKind::ExpansionScale,
        EffectKind::ThermalLag,
        EffectKind::ArmBending,
        EffectKind::JointOffsetDrift,
        EffectKind::MountDrift,
        EffectKind::GravitySag,
        EffectKind::GeometryOffset,
        EffectKind::TrackerFrame,
    ];

    pub fn name(self) -> &'static str {
        match self {
            EffectKind::ExpansionScale => "expansion-scale",
            EffectKind::ThermalLag => "thermal-lag",
            EffectKind::ArmBending => "arm-bending",
            EffectKind::JointOffsetDrift => "joint-offset-drift",
            EffectKind::MountDrift => "mount-drift",
            EffectKind::GravitySag => "gravity-sag",
            EffectKind::GeometryOffset => "geometry-offset",
            EffectKind::TrackerFrame => "tracker-frame",
        }
    }

    pub fn from_name(name: &str) -> Option<EffectKind> {
        EffectKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name.trim()))
    }

    pub fn params(self) -> &'static [ParamInfo] {
        match self {
            EffectKind::ExpansionScale => EXPANSION,
            EffectKind::ThermalLag => LAG,
            EffectKind::ArmBending => BENDING,
            EffectKind::JointOffsetDrift => JOINT_DRIFT,
            EffectKind::MountDrift => MOUNT,
            EffectKind::GravitySag => SAG,
            EffectKind::GeometryOffset => GEOMETRY,
            EffectKind::TrackerFrame => TRACKER,
        }
    }

    /// Thermal effects vanish at T_ref (the cold start) and grow with the
    /// warm-up; static ones are there from the start.
    pub fn is_thermal(self) -> bool {
        !matches!(
            self,
            EffectKind::GravitySag | EffectKind::GeometryOffset | EffectKind::TrackerFrame
        )
    }

    /// A parameter step for numeric derivatives, in the parameter's unit,
    /// small against its typical size.
    pub fn step(self, index: usize, value: f64) -> f64 {
        match self {
            EffectKind::ThermalLag => 1e-3 * (1.0 + value.abs()),
            _ => {
                let typical = self
                    .params()
                    .get(index)
                    .map_or(1.0, |p| p.default.abs().max(1e-3));
                // Large enough that rounding in the kinematics (1e-13 mm)
                // stays far below the step's effect: near-collinear columns
                // must not look independent through rounding noise.
                1e-2 * typical.max(value.abs())
            }
        }
    }
}

/// Index meaning "every thermal-lag time constant" (`tau_min`).
const ALL_TAUS: usize = usize::MAX;

/// An effect with its parameter values (in the units of [`ParamInfo`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Effect {
    pub kind: EffectKind,
    pub params: Vec<f64>,
}

impl Effect {
    pub fn zero(kind: EffectKind) -> Effect {
        Effect {
            kind,
            params: vec![0.0; kind.params().len()],
        }
    }

    pub fn with_defaults(kind: EffectKind) -> Effect {
        Effect {
            kind,
            params: kind.params().iter().map(|p| p.default).collect(),
        }
    }

    /// Parse `NAME[:param=value,...]` (the `--effect` syntax); parameters
    /// not given take their defaults.
    pub fn parse_spec(spec: &str) -> Result<Effect> {
        let (name, rest) = spec.split_once(':').unwrap_or((spec, ""));
        let kind = EffectKind::from_name(name).ok_or_else(|| {
            Error::usage(format!(
                "unknown effect `{name}`; known: {}",
                EffectKind::ALL.map(|k| k.name()).join(", ")
            ))
        })?;
        let mut effect = Effect::with_defaults(kind);
        for item in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (key, value) = item.split_once('=').ok_or_else(|| {
                Error::usage(format!("effect parameter `{item}` is not NAME=VALUE"))
            })?;
            effect.set(key.trim(), value.trim())?;
        }
        Ok(effect)
    }

    /// Set one parameter by name from text.
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        let infos = self.kind.params();
        let index = infos
            .iter()
            .position(|p| p.name.eq_ignore_ascii_case(key))
            .or_else(|| {
                (self.kind == EffectKind::ThermalLag && key.eq_ignore_ascii_case("tau_min"))
                    .then_some(ALL_TAUS)
            })
            .ok_or_else(|| {
                Error::usage(format!(
                    "effect `{}` has no parameter `{key}`; it has: {}",
                    self.kind.name(),
                    infos.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
                ))
            })?;
        let v: f64 = value
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| Error::usage(format!("`{value}` is not a finite number ({key})")))?;
        if self.kind == EffectKind::ThermalLag && v < 0.0 {
            return Err(Error::usage(
                "thermal-lag time constants must not be negative",
            ));
        }
        match index {
            // `tau_min`: one time constant for every link.
            ALL_TAUS => self.params.iter_mut().for_each(|p| *p = v),
            i => self.params[i] = v,
        }
        Ok(())
    }

    pub(crate) fn get(&self, i: usize) -> f64 {
        self.params.get(i).copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::perturb::{perturbation, predict, Base, RowState};
    use crate::thermal::{MotorTemps, TempHistory};
    use approx::assert_relative_eq;

    #[test]
    fn zero_parameters_are_the_base_model() {
        let base = Base::default();
        let row = RowState {
            q: [0.3, 0.2, -0.4, 0.5, 0.6, 0.7],
            temps: [15.0, 18.0, 16.0, 19.0, 22.0, 25.0],
            lagged: Some([[9.0; 6]; 4]),
        };
        let effects: Vec<Effect> = EffectKind::ALL
            .into_iter()
            .filter(|k| *k != EffectKind::ThermalLag)
            .map(Effect::zero)
            .collect();
        let a = predict(&base, &effects, &row);
        let b = base.thermal.expand(&base.nominal, &row.temps).fk(&row.q);
        assert_relative_eq!(a.translation.vector, b.translation.vector, epsilon = 1e-9);
    }

    #[test]
    fn lag_of_a_ramp_trails_by_tau() {
        // u = t: the exact first-order response is t − τ(1 − e^(−t/τ)).
        let recs: Vec<(f64, MotorTemps)> = (0..=10)
            .map(|i| (i as f64 * 10.0, [i as f64 * 10.0; 6]))
            .collect();
        let h = TempHistory::from_records(&recs, 0.0);
        let tau = 15.0;
        let lag = h.lagged(tau);
        for t in [0.0, 7.5, 33.0, 100.0] {
            let expect = t - tau * (1.0 - (-t / tau).exp());
            assert_relative_eq!(lag.at(t)[0], expect, epsilon = 1e-9);
        }
    }

    #[test]
    fn scale_of_one_link_changes_only_that_length() {
        let base = Base::default();
        let row = RowState {
            q: [0.0; 6],
            temps: [17.0; 6],
            lagged: None,
        };
        let mut e = Effect::zero(EffectKind::ExpansionScale);
        e.params[1] = -1.0; // lower arm does not expand at all
        let (_, pert) = perturbation(&base, &[e], &row);
        assert_relative_eq!(pert.dlen[2], -360.0 * 21.8e-6 * 10.0, epsilon = 1e-12);
        assert_eq!(pert.dlen[0], 0.0);
        assert_eq!(pert.dlen[3], 0.0);
    }

    #[test]
    fn effect_specs_parse() {
        let e = Effect::parse_spec("arm-bending:upper_urad_per_k=5").unwrap();
        assert_eq!(e.params, vec![20.0, 5.0]);
        assert!(Effect::parse_spec("warp-drive").is_err());
        assert!(Effect::parse_spec("thermal-lag:tau_min=nan").is_err());
    }
}
