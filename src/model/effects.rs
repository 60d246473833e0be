//! The effect library of `docs/model.md` ("The effect library"): each physical departure
//! from the base model, its parameters (units documented per parameter) and
//! how it perturbs the kinematic chain of a row.
//!
//! Every parameter vector of zeros is the base model exactly, so a fit
//! starts from the simulation the user already has.

use crate::error::{Error, Location, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The effects the diagnosis knows, by their names in `docs/model.md`.
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

/// One parameter of an effect: its name, unit and meaning (here, in code)
/// and its default value (from `data/effects.toml`).
#[derive(Debug, Clone, Copy)]
pub struct ParamInfo {
    pub name: &'static str,
    pub unit: &'static str,
    pub what: &'static str,
    /// Value used by `simulate` when the user gives none: a magnitude that
    /// moves the IRB 140's flange by a few hundredths to tenths of a mm
    /// (`data/effects.toml`).
    pub default: f64,
}

/// What the code says about a parameter: everything but its default.
#[derive(Debug, Clone, Copy)]
struct ParamText {
    name: &'static str,
    unit: &'static str,
    what: &'static str,
}

const fn p(name: &'static str, unit: &'static str, what: &'static str) -> ParamText {
    ParamText { name, unit, what }
}

/// The default magnitude of every effect parameter, by effect and name.
pub const EFFECT_DEFAULTS_TOML: &str = include_str!("../../data/effects.toml");

const EXPANSION: &[ParamText] = &[
    p("dk_base", "1", "k - 1 of the base link (c1, a1)"),
    p("dk_lower", "1", "k - 1 of the lower arm (c2)"),
    p("dk_upper", "1", "k - 1 of the upper arm (c3)"),
    p("dk_wrist", "1", "k - 1 of the wrist (c4)"),
];
const LAG: &[ParamText] = &[
    p(
        "tau_base_min",
        "min",
        "time constant of the base link's structure temperature behind its motors'",
    ),
    p("tau_lower_min", "min", "same, lower arm"),
    p("tau_upper_min", "min", "same, upper arm"),
    p("tau_wrist_min", "min", "same, wrist"),
];
const BENDING: &[ParamText] = &[
    p(
        "lower_urad_per_k",
        "urad/K",
        "tip rotation kL of the lower arm per K of its temperature rise",
    ),
    p(
        "upper_urad_per_k",
        "urad/K",
        "tip rotation kL of the upper arm per K of its temperature rise",
    ),
];
const JOINT_DRIFT: &[ParamText] = &[
    p(
        "c1_urad_per_k",
        "urad/K",
        "axis-1 zero drift per K of motor 1",
    ),
    p(
        "c2_urad_per_k",
        "urad/K",
        "axis-2 zero drift per K of motor 2",
    ),
    p(
        "c3_urad_per_k",
        "urad/K",
        "axis-3 zero drift per K of motor 3",
    ),
    p(
        "c4_urad_per_k",
        "urad/K",
        "axis-4 zero drift per K of motor 4",
    ),
    p(
        "c5_urad_per_k",
        "urad/K",
        "axis-5 zero drift per K of motor 5",
    ),
    p(
        "c6_urad_per_k",
        "urad/K",
        "axis-6 zero drift per K of motor 6",
    ),
];
const MOUNT: &[ParamText] = &[
    p(
        "x_um_per_k",
        "um/K",
        "base shift along x per K of motor-1 rise",
    ),
    p(
        "y_um_per_k",
        "um/K",
        "base shift along y per K of motor-1 rise",
    ),
    p(
        "z_um_per_k",
        "um/K",
        "base shift along z per K of motor-1 rise",
    ),
    p("rx_urad_per_k", "urad/K", "base tilt about x per K"),
    p("ry_urad_per_k", "urad/K", "base tilt about y per K"),
];
const SAG: &[ParamText] = &[
    p(
        "axis2_lower_urad",
        "urad",
        "axis-2 twist at the lower arm horizontal (lever c2*sin q2)",
    ),
    p(
        "axis2_upper_urad",
        "urad",
        "axis-2 twist from the upper arm's weight at it horizontal (lever cos(q2+q3))",
    ),
    p(
        "axis3_urad",
        "urad",
        "axis-3 twist with the upper arm horizontal (lever cos(q2+q3))",
    ),
];
const GEOMETRY: &[ParamText] = &[
    p("dc1_mm", "mm", "error of c1"),
    p("da1_mm", "mm", "error of a1"),
    p("dc2_mm", "mm", "error of c2"),
    p("dc3_mm", "mm", "error of c3"),
    p("dc4_mm", "mm", "error of c4"),
    p("dq1_mrad", "mrad", "zero offset of axis 1"),
    p("dq2_mrad", "mrad", "zero offset of axis 2"),
    p("dq3_mrad", "mrad", "zero offset of axis 3"),
    p("dq4_mrad", "mrad", "zero offset of axis 4"),
    p("dq5_mrad", "mrad", "zero offset of axis 5"),
    p("dq6_mrad", "mrad", "zero offset of axis 6"),
    p(
        "da2_mm",
        "mm",
        "offset of the wrist centre across the upper arm (a2)",
    ),
    p(
        "db_mm",
        "mm",
        "lateral offset of the arm plane from axis 1 (b)",
    ),
    p(
        "j1_x_mm",
        "mm",
        "joint-1 origin error along x, in the frame after axis 1",
    ),
    p(
        "j1_y_mm",
        "mm",
        "joint-1 origin error along y, in the frame after axis 1",
    ),
    p(
        "j1_z_mm",
        "mm",
        "joint-1 origin error along z, in the frame after axis 1",
    ),
    p(
        "j1_rx_mrad",
        "mrad",
        "joint-1 origin error, rotation about x after axis 1",
    ),
    p(
        "j1_ry_mrad",
        "mrad",
        "joint-1 origin error, rotation about y after axis 1",
    ),
    p(
        "j1_rz_mrad",
        "mrad",
        "joint-1 origin error, rotation about z after axis 1",
    ),
    p(
        "j2_x_mm",
        "mm",
        "joint-2 origin error along x, in the frame after axis 2",
    ),
    p(
        "j2_y_mm",
        "mm",
        "joint-2 origin error along y, in the frame after axis 2",
    ),
    p(
        "j2_z_mm",
        "mm",
        "joint-2 origin error along z, in the frame after axis 2",
    ),
    p(
        "j2_rx_mrad",
        "mrad",
        "joint-2 origin error, rotation about x after axis 2",
    ),
    p(
        "j2_ry_mrad",
        "mrad",
        "joint-2 origin error, rotation about y after axis 2",
    ),
    p(
        "j2_rz_mrad",
        "mrad",
        "joint-2 origin error, rotation about z after axis 2",
    ),
    p(
        "j3_x_mm",
        "mm",
        "joint-3 origin error along x, in the frame after axis 3",
    ),
    p(
        "j3_y_mm",
        "mm",
        "joint-3 origin error along y, in the frame after axis 3",
    ),
    p(
        "j3_z_mm",
        "mm",
        "joint-3 origin error along z, in the frame after axis 3",
    ),
    p(
        "j3_rx_mrad",
        "mrad",
        "joint-3 origin error, rotation about x after axis 3",
    ),
    p(
        "j3_ry_mrad",
        "mrad",
        "joint-3 origin error, rotation about y after axis 3",
    ),
    p(
        "j3_rz_mrad",
        "mrad",
        "joint-3 origin error, rotation about z after axis 3",
    ),
    p(
        "j4_x_mm",
        "mm",
        "joint-4 origin error along x, in the frame after axis 4",
    ),
    p(
        "j4_y_mm",
        "mm",
        "joint-4 origin error along y, in the frame after axis 4",
    ),
    p(
        "j4_z_mm",
        "mm",
        "joint-4 origin error along z, in the frame after axis 4",
    ),
    p(
        "j4_rx_mrad",
        "mrad",
        "joint-4 origin error, rotation about x after axis 4",
    ),
    p(
        "j4_ry_mrad",
        "mrad",
        "joint-4 origin error, rotation about y after axis 4",
    ),
    p(
        "j4_rz_mrad",
        "mrad",
        "joint-4 origin error, rotation about z after axis 4",
    ),
    p(
        "j5_x_mm",
        "mm",
        "joint-5 origin error along x, in the frame after axis 5",
    ),
    p(
        "j5_y_mm",
        "mm",
        "joint-5 origin error along y, in the frame after axis 5",
    ),
    p(
        "j5_z_mm",
        "mm",
        "joint-5 origin error along z, in the frame after axis 5",
    ),
    p(
        "j5_rx_mrad",
        "mrad",
        "joint-5 origin error, rotation about x after axis 5",
    ),
    p(
        "j5_ry_mrad",
        "mrad",
        "joint-5 origin error, rotation about y after axis 5",
    ),
    p(
        "j5_rz_mrad",
        "mrad",
        "joint-5 origin error, rotation about z after axis 5",
    ),
    p(
        "j6_x_mm",
        "mm",
        "joint-6 origin error along x, in the frame after axis 6",
    ),
    p(
        "j6_y_mm",
        "mm",
        "joint-6 origin error along y, in the frame after axis 6",
    ),
    p(
        "j6_z_mm",
        "mm",
        "joint-6 origin error along z, in the frame after axis 6",
    ),
    p(
        "j6_rx_mrad",
        "mrad",
        "joint-6 origin error, rotation about x after axis 6",
    ),
    p(
        "j6_ry_mrad",
        "mrad",
        "joint-6 origin error, rotation about y after axis 6",
    ),
    p(
        "j6_rz_mrad",
        "mrad",
        "joint-6 origin error, rotation about z after axis 6",
    ),
    p(
        "point_x_mm",
        "mm",
        "measured point off tool0 along the flange's x",
    ),
    p(
        "point_y_mm",
        "mm",
        "measured point off tool0 along the flange's y",
    ),
    p(
        "point_z_mm",
        "mm",
        "measured point off tool0 along the flange's z",
    ),
];
const TRACKER: &[ParamText] = &[
    p("x_mm", "mm", "tracker frame origin x"),
    p("y_mm", "mm", "tracker frame origin y"),
    p("z_mm", "mm", "tracker frame origin z"),
    p("rx_mrad", "mrad", "tracker frame rotation about x"),
    p("ry_mrad", "mrad", "tracker frame rotation about y"),
    p("rz_mrad", "mrad", "tracker frame rotation about z"),
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

    /// The parameters of this effect, with their defaults.
    pub fn params(self) -> &'static [ParamInfo] {
        &effect_params()[self as usize]
    }

    /// Names, units and meanings of this effect's parameters.
    fn texts(self) -> &'static [ParamText] {
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

/// Every effect's parameters with their defaults (indexed by
/// `EffectKind as usize`, the order of [`EffectKind::ALL`]), built once per
/// process from the embedded `data/effects.toml`. A unit test parses the
/// embedded file, so the `expect` cannot fire on a tested build.
fn effect_params() -> &'static [Vec<ParamInfo>] {
    static PARAMS: OnceLock<Vec<Vec<ParamInfo>>> = OnceLock::new();
    PARAMS.get_or_init(|| {
        parse_defaults("data/effects.toml", EFFECT_DEFAULTS_TOML)
            .expect("the embedded data/effects.toml gives every effect parameter a default")
    })
}

/// The parameter tables of every effect (in the order of
/// [`EffectKind::ALL`]) with the defaults of `text`, an `effects.toml`
/// (`file` names it in messages): a table per effect name, a value per
/// parameter name. Every parameter needs exactly one finite default;
/// unknown effects and parameters are refused.
fn parse_defaults(file: &str, text: &str) -> Result<Vec<Vec<ParamInfo>>> {
    let mut given: BTreeMap<String, BTreeMap<String, f64>> = toml::from_str(text).map_err(|e| {
        let err = Error::input(format!("effect defaults: {}", e.message()));
        match e.span() {
            Some(span) => err.at(Location::from_offset(file, text.as_bytes(), span.start)),
            None => err.with_note(format!("in {file}")),
        }
    })?;
    let bad = |msg: String| Error::input(format!("{file}: effect defaults: {msg}"));
    let mut all = Vec::with_capacity(EffectKind::ALL.len());
    for (i, kind) in EffectKind::ALL.into_iter().enumerate() {
        debug_assert_eq!(kind as usize, i);
        let mut values = given
            .remove(kind.name())
            .ok_or_else(|| bad(format!("no table [{}]", kind.name())))?;
        let mut params = Vec::with_capacity(kind.texts().len());
        for t in kind.texts() {
            let default = values
                .remove(t.name)
                .ok_or_else(|| bad(format!("[{}] has no default for `{}`", kind.name(), t.name)))?;
            if !default.is_finite() {
                return Err(bad(format!(
                    "[{}] {} must be a finite number",
                    kind.name(),
                    t.name
                )));
            }
            params.push(ParamInfo {
                name: t.name,
                unit: t.unit,
                what: t.what,
                default,
            });
        }
        if let Some(extra) = values.keys().next() {
            return Err(bad(format!(
                "effect `{}` has no parameter `{extra}`",
                kind.name()
            )));
        }
        all.push(params);
    }
    if let Some(extra) = given.keys().next() {
        return Err(bad(format!("unknown effect `{extra}`")));
    }
    Ok(all)
}

/// Parameters of `geometry-offset` that are OPW lengths (c1, a1, c2, c3,
/// c4, a2, b): a general chain has none (its joint origins take their
/// role), so they are never fitted there.
pub const GEOMETRY_OPW_LENGTHS: [usize; 7] = [0, 1, 2, 3, 4, 11, 12];

/// Parameters of `geometry-offset` after the lengths and zeros: an error
/// of every joint origin and the measured point, what a full kinematic
/// calibration identifies. Fitted only from enough poses
/// ([`FULL_GEOMETRY_POSES`]).
pub const GEOMETRY_ORIGINS_FROM: usize = 13;

/// Fewest distinct poses from which the joint-origin part of
/// `geometry-offset` is fitted: about 30 of its parameters are
/// identifiable from positions, 3 numbers per pose, and held-out poses
/// must remain.
pub const FULL_GEOMETRY_POSES: usize = 30;

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
        let b = base
            .nominal
            .fk_scaled(&row.q, &base.thermal.scales(&row.temps));
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
        // Relative to the model in use: its K0 included.
        let k0 = base.thermal.k0;
        assert_relative_eq!(pert.dlen[2], -360.0 * k0 * 21.8e-6 * 10.0, epsilon = 1e-12);
        assert_eq!(pert.dlen[0], 0.0);
        assert_eq!(pert.dlen[3], 0.0);
    }

    #[test]
    fn embedded_defaults_cover_every_parameter_exactly_once() {
        let all = parse_defaults("data/effects.toml", EFFECT_DEFAULTS_TOML).unwrap();
        assert_eq!(all.len(), EffectKind::ALL.len());
        for kind in EffectKind::ALL {
            let params = kind.params();
            let names: Vec<&str> = params.iter().map(|p| p.name).collect();
            let texts: Vec<&str> = kind.texts().iter().map(|t| t.name).collect();
            assert_eq!(names, texts, "{}", kind.name());
            assert_eq!(all[kind as usize].len(), params.len());
            for (a, b) in all[kind as usize].iter().zip(params) {
                assert_eq!(a.default.to_bits(), b.default.to_bits(), "{}", a.name);
                assert!(a.default.is_finite() && a.default != 0.0, "{}", a.name);
            }
        }
        // The defaults the tests and transcripts were written with.
        assert_eq!(
            Effect::with_defaults(EffectKind::ArmBending).params,
            vec![20.0, 30.0]
        );
        assert_eq!(
            Effect::with_defaults(EffectKind::ThermalLag).params,
            vec![30.0; 4]
        );
    }

    #[test]
    fn effect_defaults_refuse_missing_duplicate_and_unknown_names() {
        let text = EFFECT_DEFAULTS_TOML;
        let missing = text.replace("dk_wrist = -0.5\n", "");
        let e = parse_defaults("e.toml", &missing).unwrap_err();
        assert!(e.message.contains("dk_wrist"), "{}", e.message);
        let duplicate = text.replace("dk_wrist = -0.5\n", "dk_wrist = -0.5\ndk_wrist = 1.0\n");
        assert!(parse_defaults("e.toml", &duplicate).is_err());
        let unknown = text.replace("dk_wrist = -0.5\n", "dk_wrist = -0.5\ndk_elbow = 1.0\n");
        let e = parse_defaults("e.toml", &unknown).unwrap_err();
        assert!(e.message.contains("dk_elbow"), "{}", e.message);
        let effect = format!("{text}\n[warp-drive]\nfactor = 9.0\n");
        let e = parse_defaults("e.toml", &effect).unwrap_err();
        assert!(e.message.contains("warp-drive"), "{}", e.message);
        let e = parse_defaults("e.toml", "[arm-bending\n").unwrap_err();
        assert!(e.message.contains("effect defaults"), "{}", e.message);
    }

    #[test]
    fn effect_specs_parse() {
        let e = Effect::parse_spec("arm-bending:upper_urad_per_k=5").unwrap();
        assert_eq!(e.params, vec![20.0, 5.0]);
        assert!(Effect::parse_spec("warp-drive").is_err());
        assert!(Effect::parse_spec("thermal-lag:tau_min=nan").is_err());
    }
}
