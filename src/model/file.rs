//! The model file (TOML): the robot's geometry, the base thermal-expansion
//! model, where motor temperatures come from, and the effects a diagnosis
//! added. `diagnose --save-model` writes it; `gap`, `diagnose --model` and
//! `correct --model` read it.
//!
//! ```toml
//! format = 2
//! [robot]
//! name = "IRB 140"
//! [robot.opw]
//! c1 = 352.0  # mm, likewise a1, c2, c3, c4, a2, b
//! [thermal]
//! t_ref = 7.0
//! [thermal.base]
//! alpha = 2.18e-5
//! motors = [1]
//! # ... lower_arm, upper_arm, wrist
//! [heating]
//! profile = "default"
//! [[effects]]
//! name = "arm-bending"
//! [effects.params]
//! lower_urad_per_k = 12.5
//! upper_urad_per_k = 30.1
//! ```

use super::effects::{Effect, EffectKind};
use super::expansion::ThermalExpansion;
use super::file_place::{dotted, locate, KeyStep};
use super::perturb::{Base, Geometry};
use crate::error::{Error, ErrorKind, Location, Result};
use crate::robot::{Opw, Robot};
use crate::thermal::{
    default_profile, FittedProfile, HeatingProfile, HeatingRecord, ModelKind, RecordedProfile,
};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

/// The model-file format this build writes. Format 1 (files without a
/// `format` key) named a URDF only by its path and had no `[instrument]`;
/// every format-1 file is a valid format-2 file, so both are read. A
/// newer format is refused with its number, never half read.
pub const FORMAT: u32 = 2;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// The file's format ([`FORMAT`]); absent in format-1 files.
    #[serde(default = "format_one")]
    pub format: u32,
    pub robot: RobotSection,
    pub thermal: ThermalExpansion,
    #[serde(default)]
    pub heating: HeatingSection,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effects: Vec<EffectEntry>,
    /// The instrument's frame the measurements were taken in, as a
    /// diagnosis registered it: `gap` and `diagnose` bring measured points
    /// into the robot base frame with it (unless asked to register anew).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instrument: Option<InstrumentSection>,
    /// The folder of the model file (relative recording paths start there).
    #[serde(skip)]
    pub dir: Option<PathBuf>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSection {
    pub name: String,
    /// The OPW lengths of an ABB arm (ABB's joint convention).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opw: Option<Opw>,
    /// Or the URDF of any serial arm (a path; relative to the model
    /// file's folder), whose chain and joint convention the effects use.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<String>,
    /// Or the URDF's content itself, so that the file stands alone
    /// (what `diagnose --save-model` writes for an arm read from a URDF).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf_text: Option<String>,
    /// Or an arm of the catalogue, by name (`rapidtherm arms`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub catalogue: Option<String>,
    /// The joint convention the effects' joint-angle parameters are
    /// written in, as the writer saw it: checked against the arm on
    /// reading, so that a file whose arm changed under it is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joints: Option<JointConvention>,
    /// The point the measurements were taken at (a tracker's reflector),
    /// in tool0, mm: what `diagnose --point` named or fitted. Only the
    /// diagnosis and `gap` use it; `correct` moves tool0 and the program's
    /// tools.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_mm: Option<[f64; 3]>,
}

/// The convention of joint angles in a model's effects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum JointConvention {
    /// The OPW chain's angles in ABB's convention (an arm of the OPW form:
    /// its own joints are mapped through its signs and offsets).
    AbbOpw,
    /// The URDF's own joint angles (a serial chain without the OPW form).
    Urdf,
}

impl JointConvention {
    /// The convention the diagnosis writes an arm's effects in.
    pub fn of(robot: &Robot) -> JointConvention {
        if robot.opw.is_ok() {
            JointConvention::AbbOpw
        } else {
            JointConvention::Urdf
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            JointConvention::AbbOpw => "abb-opw",
            JointConvention::Urdf => "urdf",
        }
    }
}

/// A rigid frame of the instrument: measured = T · base-frame point, with
/// T a translation (mm) after a rotation (rotation vector, degrees).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstrumentSection {
    pub translation_mm: [f64; 3],
    pub rotation_deg: [f64; 3],
}

impl InstrumentSection {
    /// The transform from the robot base frame to the instrument's.
    pub fn transform(&self) -> nalgebra::Isometry3<f64> {
        let r = nalgebra::Vector3::from(self.rotation_deg).map(f64::to_radians);
        nalgebra::Isometry3::from_parts(
            nalgebra::Translation3::from(nalgebra::Vector3::from(self.translation_mm)),
            nalgebra::UnitQuaternion::from_scaled_axis(r),
        )
    }
}

fn format_one() -> u32 {
    1
}

/// Where motor temperatures come from when the data do not carry them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeatingSection {
    /// `"default"`: the embedded IRB 140 warm-up profile.
    #[serde(default = "default_profile_name")]
    pub profile: String,
    /// A heating record (CSV) to use instead of the embedded profile:
    /// interpolated in time (refused outside its window), or, with `fit`,
    /// a model fitted to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub recording: Option<String>,
    /// Model fitted to the recording: `two-tau`, `first-order`, `poly3`, ...
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<String>,
}

fn default_profile_name() -> String {
    "default".to_string()
}

impl Default for HeatingSection {
    fn default() -> Self {
        HeatingSection {
            profile: default_profile_name(),
            recording: None,
            fit: None,
        }
    }
}

/// One effect: its name (`docs/model.md`) and parameters by name, in the units
/// the effect library documents.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectEntry {
    pub name: String,
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
    /// Standard errors of the fitted parameters (informative only).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub stderr: BTreeMap<String, f64>,
}

/// A value the TOML parser took and the model cannot use: its key path
/// and what is wrong.
struct Invalid {
    at: Vec<KeyStep>,
    message: String,
}

/// The embedded default model: the nominal IRB 140 with the base thermal
/// model of `docs/model.md`, in the model-file format (`data/irb140/model.toml`).
pub const DEFAULT_MODEL_TOML: &str = include_str!("../../data/irb140/model.toml");

/// The embedded default model, parsed once per process. A unit test parses
/// the embedded file, so the `expect` cannot fire on a tested build.
pub(crate) fn default_model() -> &'static Model {
    static MODEL: OnceLock<Model> = OnceLock::new();
    MODEL.get_or_init(|| {
        Model::parse("data/irb140/model.toml", DEFAULT_MODEL_TOML)
            .expect("the embedded data/irb140/model.toml is a valid model file")
    })
}

impl Default for Model {
    /// The nominal IRB 140 with the calibrated default of `docs/model.md`
    /// (`data/irb140/model.toml`: the base thermal model, every link's
    /// expansion scaled by K0).
    fn default() -> Self {
        default_model().clone()
    }
}

impl Default for ThermalExpansion {
    /// The thermal section of the embedded default model
    /// (`data/irb140/model.toml`): the table of `docs/model.md`, T_ref 7 °C,
    /// A380 everywhere.
    fn default() -> Self {
        default_model().thermal.clone()
    }
}

impl Model {
    /// The embedded models by name: `default` (calibrated, K0 of the data
    /// file) and `base` (docs/model.md's base model, K0 = 1, unscaled).
    pub fn named(name: &str) -> Option<Model> {
        match name.to_ascii_lowercase().as_str() {
            "default" => Some(Model::default()),
            "base" => {
                let mut m = Model::default();
                m.thermal.k0 = 1.0;
                Some(m)
            }
            _ => None,
        }
    }
}

impl EffectEntry {
    pub fn from_effect(effect: &Effect, stderr: Option<&[Option<f64>]>) -> EffectEntry {
        let infos = effect.kind.params();
        // A parameter held at zero and never fitted (geometry-offset's joint
        // origins from too few poses) is what loading gives anyway: left out.
        let fitted = |i: usize| stderr.is_none_or(|s| s.get(i).is_some_and(Option::is_some));
        let params = infos
            .iter()
            .zip(&effect.params)
            .enumerate()
            .filter(|&(i, (_, v))| *v != 0.0 || fitted(i))
            .map(|(_, (p, v))| (p.name.to_string(), *v))
            .collect();
        let stderr = stderr
            .map(|s| {
                infos
                    .iter()
                    .zip(s)
                    .filter_map(|(p, e)| e.map(|e| (p.name.to_string(), e)))
                    .collect()
            })
            .unwrap_or_default();
        EffectEntry {
            name: effect.kind.name().to_string(),
            params,
            stderr,
        }
    }

    pub fn to_effect(&self) -> Result<Effect> {
        let kind = EffectKind::from_name(&self.name)
            .ok_or_else(|| Error::input(format!("model: unknown effect `{}`", self.name)))?;
        let mut effect = Effect::zero(kind);
        for (key, value) in &self.params {
            effect
                .set(key, &value.to_string())
                .map_err(|e| Error::input(format!("model: {}", e.message)))?;
        }
        Ok(effect)
    }
}

/// A model file's format, read before the rest: a file of a format this
/// build does not know is refused with its number, before its first
/// unknown key could be blamed instead.
fn check_format(file: &str, text: &str) -> Result<()> {
    #[derive(Deserialize)]
    struct Head {
        format: Option<toml::Value>,
    }
    // A file that does not parse is reported by the full parse.
    let Ok(head) = toml::from_str::<Head>(text) else {
        return Ok(());
    };
    let Some(v) = head.format else {
        return Ok(());
    };
    let at = || locate(file, text, &[KeyStep::Key("format")]);
    match v.as_integer() {
        Some(n) if (1..=i64::from(FORMAT)).contains(&n) => Ok(()),
        Some(n) if n > i64::from(FORMAT) => Err(Error::input(format!(
            "model file format {n} is newer than this rapidtherm reads (formats 1 to {FORMAT}): use a newer rapidtherm"
        ))
        .at(at())),
        _ => Err(Error::input(format!(
            "`format` must be a model-file format number, 1 to {FORMAT}"
        ))
        .at(at())),
    }
}

/// The arm a model names beside OPW lengths: the robot, where it came
/// from (for messages), and how a saved model names it again.
#[derive(Debug, Clone)]
pub struct ModelArm {
    pub robot: Robot,
    /// A path, the model's embedded URDF or a catalogue name.
    pub source: String,
    /// The URDF's text (a file named by path is read, once).
    pub urdf_text: Option<String>,
    /// The catalogue arm's name.
    pub catalogue: Option<String>,
}

impl Model {
    /// The robot the model's `[robot]` names (a URDF file, a URDF's text
    /// or a catalogue arm; `None` for OPW lengths), its joint convention
    /// checked against the one the file says its effects use.
    pub fn arm(&self) -> Result<Option<ModelArm>> {
        let r = &self.robot;
        let urdf = |source: String, text: String| -> Result<ModelArm> {
            Ok(ModelArm {
                robot: Robot::from_urdf_str(&source, &text)?,
                source,
                urdf_text: Some(text),
                catalogue: None,
            })
        };
        let arm = if let Some(text) = &r.urdf_text {
            urdf(
                format!("the URDF in the model's [robot] ({})", r.name),
                text.clone(),
            )?
        } else if let Some(name) = &r.catalogue {
            let arm = crate::robot::abb::find(name)
                .map_err(|e| e.with_note("the arm named by the model's [robot] catalogue"))?;
            ModelArm {
                robot: arm.robot(),
                source: format!("catalogue {}", arm.name),
                urdf_text: None,
                catalogue: Some(arm.name.clone()),
            }
        } else if let Some(p) = self.urdf_path() {
            let note = |e: Error| e.with_note("the URDF named by the model's [robot] urdf");
            let bytes = crate::input::read_path(&p).map_err(note)?;
            let text = String::from_utf8(bytes).map_err(|_| {
                note(Error::input(format!(
                    "{}: a URDF file must be UTF-8",
                    p.display()
                )))
            })?;
            urdf(p.display().to_string(), text).map_err(note)?
        } else {
            return Ok(None);
        };
        let found = JointConvention::of(&arm.robot);
        match r.joints {
            Some(said) if said != found => Err(Error::input(format!(
                "model: [robot] joints = \"{}\", but {} ({}) has the {} convention: the effects were written for another arm",
                said.name(),
                arm.robot.name,
                arm.source,
                found.name()
            ))),
            _ => Ok(Some(arm)),
        }
    }

    /// Parse a model file's text (`file` names it in messages). An error
    /// names the key and its line and column.
    pub fn parse(file: &str, text: &str) -> Result<Model> {
        check_format(file, text)?;
        let model: Model = toml::from_str(text).map_err(|e| {
            let mut err = Error::input(format!("bad model file: {}", e.message()));
            if let Some(span) = e.span() {
                err = err.at(Location::from_offset(file, text.as_bytes(), span.start));
            }
            err
        })?;
        model.validate().map_err(|bad| {
            Error::input(format!("`{}`: {}", dotted(&bad.at), bad.message))
                .at(locate(file, text, &bad.at))
        })?;
        Ok(model)
    }

    pub fn load(path: &Path) -> Result<Model> {
        let bytes = crate::input::read_path(path)?;
        let text = String::from_utf8(bytes)
            .map_err(|_| Error::input(format!("{}: model files must be UTF-8", path.display())))?;
        let mut model = Model::parse(&path.display().to_string(), &text)?;
        // A recording named by a relative path lies beside the model file.
        model.dir = path.parent().map(Path::to_path_buf);
        Ok(model)
    }

    /// The model as a file of the current [`FORMAT`] (a model read from
    /// an older file is written in the current one).
    pub fn to_toml(&self) -> Result<String> {
        let current = Model {
            format: FORMAT,
            ..self.clone()
        };
        toml::to_string(&current)
            .map_err(|e| Error::new(ErrorKind::Input, format!("cannot write the model: {e}")))
    }

    /// Every value the parser took and the model cannot use, by its key.
    fn validate(&self) -> std::result::Result<(), Invalid> {
        use KeyStep::Key;
        let bad = |at: Vec<KeyStep>, message: &str| {
            Err(Invalid {
                at,
                message: message.to_string(),
            })
        };
        let r = &self.robot;
        let sources = [
            r.opw.is_some(),
            r.urdf.is_some(),
            r.urdf_text.is_some(),
            r.catalogue.is_some(),
        ];
        if sources.iter().filter(|&&s| s).count() != 1 {
            return bad(
                vec![Key("robot")],
                "needs exactly one of its OPW lengths ([robot.opw]), `urdf = \"FILE\"`, `urdf_text` or `catalogue = \"NAME\"`",
            );
        }
        if let (Some(_), Some(j)) = (&r.opw, r.joints) {
            if j != JointConvention::AbbOpw {
                return bad(
                    vec![Key("robot"), Key("joints")],
                    "an arm given by its OPW lengths has ABB's joint convention (`abb-opw`)",
                );
            }
        }
        if let Some(i) = &self.instrument {
            if !i
                .translation_mm
                .iter()
                .all(|v| v.is_finite() && v.abs() <= 1e5)
            {
                return bad(
                    vec![Key("instrument"), Key("translation_mm")],
                    "must be three finite mm (within 100 m of the robot base)",
                );
            }
            let turn = nalgebra::Vector3::from(i.rotation_deg).norm();
            if !(turn.is_finite() && turn <= 180.0) {
                return bad(
                    vec![Key("instrument"), Key("rotation_deg")],
                    "must be a rotation vector of at most 180°",
                );
            }
        }
        if let Some(o) = &self.robot.opw {
            let lengths = [
                ("c1", o.c1),
                ("a1", o.a1),
                ("c2", o.c2),
                ("c3", o.c3),
                ("c4", o.c4),
                ("a2", o.a2),
                ("b", o.b),
            ];
            for (name, v) in lengths {
                let positive = matches!(name, "c2" | "c3");
                // A millimetre length beyond 100 m is no robot arm.
                if !v.is_finite() || v.abs() > 1e5 || (positive && v <= 0.0) {
                    return bad(
                        vec![Key("robot"), Key("opw"), Key(name)],
                        if positive {
                            "must be a positive length in mm (at most 100,000)"
                        } else {
                            "must be a finite length in mm (at most 100,000 either way)"
                        },
                    );
                }
            }
        }
        if !self.point().iter().all(|v| v.is_finite() && v.abs() <= 1e4) {
            return bad(
                vec![Key("robot"), Key("point_mm")],
                "must be three finite mm (within 10 m of the flange)",
            );
        }
        let th = &self.thermal;
        for (key, link) in [
            ("base", &th.base),
            ("lower_arm", &th.lower_arm),
            ("upper_arm", &th.upper_arm),
            ("wrist", &th.wrist),
        ] {
            if link.motors.is_empty() || link.motors.iter().any(|&m| !(1..=6).contains(&m)) {
                return bad(
                    vec![Key("thermal"), Key(key), Key("motors")],
                    "each link needs motors among 1..6",
                );
            }
            // Engineering metals expand by 1e-6 to 3e-5 per kelvin.
            if !(link.alpha.is_finite() && link.alpha.abs() < 1e-3) {
                return bad(
                    vec![Key("thermal"), Key(key), Key("alpha")],
                    "must be a finite expansion coefficient per kelvin (aluminium: 2.2e-5)",
                );
            }
        }
        if !th.k0.is_finite() {
            return bad(vec![Key("thermal"), Key("k0")], "must be a finite factor");
        }
        if let Some(why) = super::plausible::implausible_k0(th.k0) {
            return bad(vec![Key("thermal"), Key("k0")], &why);
        }
        if !(th.t_ref.is_finite() && (-50.0..=150.0).contains(&th.t_ref)) {
            return bad(
                vec![Key("thermal"), Key("t_ref")],
                "must be a temperature in °C from -50 to 150",
            );
        }
        for (i, entry) in self.effects.iter().enumerate() {
            let at = |rest: Vec<KeyStep>| {
                let mut at = vec![Key("effects"), KeyStep::Index(i)];
                at.extend(rest);
                at
            };
            let Some(kind) = EffectKind::from_name(&entry.name) else {
                return bad(at(vec![Key("name")]), "unknown effect");
            };
            let mut effect = Effect::zero(kind);
            for (key, value) in &entry.params {
                if let Err(e) = effect.set(key, &value.to_string()) {
                    return Err(Invalid {
                        at: at(vec![Key("params"), KeyStep::Name(key.clone())]),
                        message: e.message,
                    });
                }
                // The project's own bounds of a real arm: a model beyond
                // them moves targets by centimetres.
                if let Some(why) = super::plausible::implausible(kind, key, *value) {
                    return Err(Invalid {
                        at: at(vec![Key("params"), KeyStep::Name(key.clone())]),
                        message: why,
                    });
                }
            }
        }
        Ok(())
    }

    /// The effects the model adds to the base simulation.
    pub fn effects(&self) -> Result<Vec<Effect>> {
        self.effects.iter().map(EffectEntry::to_effect).collect()
    }

    /// The base model: the robot's nominal geometry (its URDF loaded when
    /// the model names one) and the thermal expansion.
    pub fn base(&self) -> Result<Base> {
        let nominal = match (&self.robot.opw, self.robot_urdf()?) {
            (Some(o), _) => Geometry::Opw(*o),
            // An arm of the OPW form is modelled by its OPW lengths, in
            // ABB's convention, as the diagnosis fitted it.
            (None, Some(robot)) => match robot.opw {
                Ok(arm) => Geometry::Opw(arm.geom),
                Err(_) => Geometry::Chain(Arc::new(robot.chain)),
            },
            (None, None) => return Err(Error::input("model: [robot] has no geometry")),
        };
        Ok(Base {
            nominal,
            thermal: self.thermal.clone(),
            point: self.point().into(),
        })
    }

    /// The measured point in tool0, mm (zero when the model names none).
    pub fn point(&self) -> [f64; 3] {
        self.robot.point_mm.unwrap_or([0.0; 3])
    }

    /// The path of the URDF the model's `[robot]` names, resolved against
    /// the model file's folder.
    pub fn urdf_path(&self) -> Option<PathBuf> {
        let rel = self.robot.urdf.as_ref()?;
        Some(match &self.dir {
            Some(dir) if Path::new(rel).is_relative() => dir.join(rel),
            _ => PathBuf::from(rel),
        })
    }

    /// The robot the model names (`None` for an OPW model).
    pub fn robot_urdf(&self) -> Result<Option<Robot>> {
        Ok(self.arm()?.map(|a| a.robot))
    }

    /// The heating profile that supplies motor temperatures.
    pub fn profile(&self) -> Result<Box<dyn HeatingProfile>> {
        if let Some(rec) = &self.heating.recording {
            let path = match &self.dir {
                Some(dir) if Path::new(rec).is_relative() => dir.join(rec),
                _ => PathBuf::from(rec),
            };
            let bytes = crate::input::read_path(&path)?;
            let record = HeatingRecord::parse(&path.display().to_string(), &bytes)?;
            return match &self.heating.fit {
                // A recording of the actual run: interpolated, refused
                // outside the recorded window.
                None => Ok(Box::new(RecordedProfile::new(&record))),
                Some(kind) => {
                    let kind: ModelKind = kind.parse()?;
                    Ok(Box::new(FittedProfile::fit(&record, kind, None)?))
                }
            };
        }
        if self.heating.profile != "default" {
            return Err(Error::input(format!(
                "model: unknown heating profile `{}` (known: default; or give `recording`)",
                self.heating.profile
            )));
        }
        Ok(Box::new(default_profile()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::perturb::{predict, RowState};

    #[test]
    fn default_model_round_trips_and_is_the_base_model() {
        let mut m = Model::default();
        m.effects.push(EffectEntry::from_effect(
            &Effect::with_defaults(EffectKind::ArmBending),
            None,
        ));
        let text = m.to_toml().unwrap();
        let back = Model::parse("m.toml", &text).unwrap();
        assert_eq!(back, m);
        let q = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6];
        let m = Model::default();
        let base = predict(
            &m.base().unwrap(),
            &m.effects().unwrap(),
            &RowState {
                q,
                temps: [m.thermal.t_ref; 6],
                lagged: None,
            },
        );
        assert!(
            (base.translation.vector - crate::robot::irb140_opw().fk(&q).translation.vector).norm()
                < 1e-9
        );
    }

    /// A value the TOML parser takes but the model cannot use is reported
    /// at its key, with the key named.
    #[test]
    fn an_unusable_value_is_reported_at_its_key() {
        let cases = [
            ("k0 = 0.33699", "k0 = -1", "`thermal.k0`"),
            ("t_ref = 7.0", "t_ref = 289.0", "`thermal.t_ref`"),
            ("c2 = 360.0", "c2 = -360.0", "`robot.opw.c2`"),
            (
                "motors = [2, 3]",
                "motors = [2, 7]",
                "`thermal.lower_arm.motors`",
            ),
        ];
        for (from, to, key) in cases {
            assert!(DEFAULT_MODEL_TOML.contains(from), "{from}");
            let text = DEFAULT_MODEL_TOML.replacen(from, to, 1);
            let e = Model::parse("m.toml", &text).unwrap_err();
            let line = 1 + text[..text.find(to).unwrap()].matches('\n').count();
            let loc = e.location.as_ref().unwrap();
            assert_eq!(loc.line, line, "{to}: {e}");
            assert!(e.message.contains(key), "{to}: {e}");
        }
        let text = format!(
            "{DEFAULT_MODEL_TOML}\n[[effects]]\nname = \"arm-bending\"\n[effects.params]\nnot_a_param = 1.0\n"
        );
        let e = Model::parse("m.toml", &text).unwrap_err();
        assert!(e.message.contains("`effects[1].params.not_a_param`"), "{e}");
        assert_eq!(e.location.unwrap().line, text.lines().count());
    }

    #[test]
    fn embedded_default_model_is_the_spec() {
        let m = Model::parse("model.toml", DEFAULT_MODEL_TOML).unwrap();
        assert_eq!(&m, default_model());
        assert_eq!(m, Model::default());
        assert_eq!(m.robot.name, "IRB 140");
        // docs/model.md, "Geometry" (mm).
        let spec = Opw {
            c1: 352.0,
            a1: 70.0,
            c2: 360.0,
            c3: 380.0,
            c4: 65.0,
            a2: 0.0,
            b: 0.0,
        };
        assert_eq!(m.robot.opw, Some(spec));
        // The same numbers as the embedded URDF's chain, bit for bit.
        assert_eq!(m.robot.opw, Some(crate::robot::irb140_opw()));
        // docs/model.md, "Materials" and "Base thermal-expansion model".
        let th = &m.thermal;
        assert_eq!(th.t_ref, 7.0);
        for (link, motors) in [
            (&th.base, vec![1]),
            (&th.lower_arm, vec![2, 3]),
            (&th.upper_arm, vec![4, 5, 6]),
            (&th.wrist, vec![5, 6]),
        ] {
            assert_eq!(link.alpha, 21.8e-6);
            assert_eq!(link.motors, motors);
        }
        assert_eq!(ThermalExpansion::default(), m.thermal);
        assert_eq!(m.heating, HeatingSection::default());
        assert!(m.effects.is_empty());
        assert_eq!(m.dir, None);
        // The default heating profile starts at T_ref exactly.
        assert_eq!(crate::thermal::default_heating().t0_c, th.t_ref);
    }

    #[test]
    fn unknown_effect_parameter_is_an_error() {
        let mut text = Model::default().to_toml().unwrap();
        text.push_str("\n[[effects]]\nname = \"arm-bending\"\n[effects.params]\nfoo = 1.0\n");
        let e = Model::parse("m.toml", &text).unwrap_err();
        assert!(e.message.contains("foo"), "{}", e.message);
    }
    /// Files are written in the current format, a format-1 file (no
    /// `format` key) still reads, and a newer one is refused with its
    /// number at its line.
    #[test]
    fn the_format_is_written_old_files_read_and_newer_ones_are_refused() {
        let text = Model::default().to_toml().unwrap();
        assert!(text.starts_with("format = 2\n"), "{text}");
        let v1 = DEFAULT_MODEL_TOML.replace("format = 2\n", "");
        assert!(!v1.contains("format ="));
        let m = Model::parse("v1.toml", &v1).unwrap();
        assert_eq!(m.format, 1);
        assert!(m.to_toml().unwrap().starts_with("format = 2\n"));
        let v3 = DEFAULT_MODEL_TOML.replace("format = 2", "format = 3");
        let e = Model::parse("v3.toml", &v3).unwrap_err();
        assert!(e.message.contains("format 3 is newer"), "{e}");
        let line = 1 + v3[..v3.find("format = 3").unwrap()].matches('\n').count();
        assert_eq!(e.location.unwrap().line, line);
        let bad = DEFAULT_MODEL_TOML.replace("format = 2", "format = \"two\"");
        assert!(Model::parse("bad.toml", &bad).is_err());
    }

    const UR5: &str = include_str!("../../tests/data/ur5/ur5.urdf");

    fn ur5_model() -> Model {
        let base = Model::default();
        Model {
            robot: RobotSection {
                name: "ur5".into(),
                opw: None,
                urdf: None,
                urdf_text: Some(UR5.into()),
                catalogue: None,
                joints: Some(JointConvention::Urdf),
                point_mm: Some([0.0, 0.0, 31.0]),
            },
            instrument: Some(InstrumentSection {
                translation_mm: [1500.0, -20.0, 3.5],
                rotation_deg: [0.5, -1.0, 120.0],
            }),
            ..base
        }
    }

    /// A model that embeds its URDF stands alone: it reads back with the
    /// arm, its convention, point and instrument frame, needing no file.
    #[test]
    fn a_model_with_its_urdf_and_frame_stands_alone() {
        let m = ur5_model();
        let back = Model::parse("m.toml", &m.to_toml().unwrap()).unwrap();
        assert_eq!(
            back,
            Model {
                format: FORMAT,
                ..m
            }
        );
        let arm = back.arm().unwrap().unwrap();
        assert!(arm.robot.opw.is_err(), "the UR5 has no OPW form");
        assert_eq!(arm.urdf_text.as_deref(), Some(UR5));
        let t = back.instrument.unwrap().transform();
        // 120° about (nearly) z: the base x axis turns towards y.
        let x = t.rotation * nalgebra::Vector3::x();
        assert!((x.y - (120f64).to_radians().sin()).abs() < 0.03, "{x}");
        assert_eq!(
            t.translation.vector,
            nalgebra::Vector3::new(1500.0, -20.0, 3.5)
        );
    }

    /// The joint convention written is checked against the arm: effects
    /// written for ABB's OPW angles are refused on a URDF chain.
    #[test]
    fn a_joint_convention_that_is_not_the_arms_is_refused() {
        let mut m = ur5_model();
        m.robot.joints = Some(JointConvention::AbbOpw);
        let e = Model::parse("m.toml", &m.to_toml().unwrap())
            .unwrap()
            .arm()
            .unwrap_err();
        assert!(e.message.contains("convention"), "{e}");
        let mut m = ur5_model();
        m.robot.opw = Some(crate::robot::irb140_opw());
        let e = Model::parse("m.toml", &m.to_toml().unwrap()).unwrap_err();
        assert!(e.message.contains("exactly one"), "{e}");
        let mut m = ur5_model();
        m.instrument = Some(InstrumentSection {
            translation_mm: [0.0; 3],
            rotation_deg: [200.0, 0.0, 0.0],
        });
        let e = Model::parse("m.toml", &m.to_toml().unwrap()).unwrap_err();
        assert!(e.message.contains("instrument.rotation_deg"), "{e}");
    }
}
