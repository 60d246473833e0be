//! ABB's six-axis arms by name: the catalogue embedded from
//! `data/arms/*.toml` (one file per family, every number with its source;
//! `data/arms/README.md` says where they come from and which arms are left
//! out), and the lookup that turns `irb2600-12/1.65`, `IRB 2600-12/1.65`
//! or `irb140` into a [`Robot`].
//!
//! Every catalogue arm has the OPW shape and ABB's joint conventions
//! ([`super::ik::OpwArm::abb`]); its chain is built from the OPW lengths
//! ([`super::chain::Chain::from_opw`]). The IRB 140 entry names the
//! embedded URDF arm ([`Robot::irb140`]) rather than repeating its numbers.

use super::arm::{irb140_opw, Robot};
use super::Opw;
use crate::error::{Error, Remedy, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The family files, in the order the catalogue lists them.
const FILES: &[(&str, &str)] = &[
    (
        "data/arms/irb120.toml",
        include_str!("../../data/arms/irb120.toml"),
    ),
    (
        "data/arms/irb140.toml",
        include_str!("../../data/arms/irb140.toml"),
    ),
    (
        "data/arms/irb1200.toml",
        include_str!("../../data/arms/irb1200.toml"),
    ),
    (
        "data/arms/irb1600.toml",
        include_str!("../../data/arms/irb1600.toml"),
    ),
    (
        "data/arms/irb2400.toml",
        include_str!("../../data/arms/irb2400.toml"),
    ),
    (
        "data/arms/irb2600.toml",
        include_str!("../../data/arms/irb2600.toml"),
    ),
    (
        "data/arms/irb4600.toml",
        include_str!("../../data/arms/irb4600.toml"),
    ),
    (
        "data/arms/irb6640.toml",
        include_str!("../../data/arms/irb6640.toml"),
    ),
    (
        "data/arms/irb6650s.toml",
        include_str!("../../data/arms/irb6650s.toml"),
    ),
    (
        "data/arms/irb6700.toml",
        include_str!("../../data/arms/irb6700.toml"),
    ),
    (
        "data/arms/irb7600.toml",
        include_str!("../../data/arms/irb7600.toml"),
    ),
];

/// How the controller measures axis 3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis3 {
    /// Against the lower arm, as the URDF and the OPW model do.
    Serial,
    /// Against the horizontal: a parallel-arm robot (IRB 2400), whose
    /// serial angle is q3 − q2.
    Parallel,
}

impl Axis3 {
    /// The coupling of [`super::ik::serial_angles`].
    pub fn coupling(self) -> f64 {
        match self {
            Axis3::Serial => 0.0,
            Axis3::Parallel => -1.0,
        }
    }
}

/// Where some numbers of an arm come from: a short label (for a listing)
/// and the full citation (repository, path, commit; document and section).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Citation {
    pub label: String,
    pub cite: String,
}

/// The sources of each kind of number of one arm.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ArmSources {
    /// The OPW lengths.
    pub geometry: Vec<Citation>,
    pub limits: Vec<Citation>,
    /// Empty when no source gives the axis speeds.
    pub speeds: Vec<Citation>,
    /// Payload and reach.
    pub rating: Vec<Citation>,
    /// How the controller measures axis 3.
    pub axis3: Vec<Citation>,
}

/// One arm of the catalogue.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AbbArm {
    /// ABB's designation, `IRB 2600-12/1.65`: [`Robot::name`] of its robot.
    pub name: String,
    /// `IRB 2600`: a family name alone picks the arm when it is the only
    /// variant.
    pub family: String,
    /// Other names of the same arm (`IRB 2400-12/1.55` for the IRB 2400-10).
    pub aliases: Vec<String>,
    pub payload_kg: f64,
    /// Published reach to the wrist centre, m (the designation's, rounded).
    pub reach_m: f64,
    pub axis3: Axis3,
    /// Nominal lengths, mm.
    pub opw: Opw,
    /// Degrees, inclusive, in the controller's angles.
    pub limits_deg: [(f64, f64); 6],
    /// °/s; `None` where no source gives them.
    pub max_speed_deg_s: Option<[f64; 6]>,
    pub sources: ArmSources,
    /// The data file the arm is written in.
    pub file: &'static str,
    /// The embedded IRB 140 URDF rather than the OPW lengths.
    #[serde(skip)]
    embedded_irb140: bool,
}

impl AbbArm {
    /// The IRB 140, which is the embedded URDF arm ([`Robot::irb140`]).
    pub fn is_embedded_irb140(&self) -> bool {
        self.embedded_irb140
    }

    /// The robot: its chain (for FK), OPW form (closed-form IK), limits and
    /// speeds (0 where unknown, as a URDF without velocities gives).
    pub fn robot(&self) -> Robot {
        if self.embedded_irb140 {
            return Robot {
                name: self.name.clone(),
                ..Robot::irb140()
            };
        }
        Robot::from_opw(
            &self.name,
            self.opw,
            self.axis3.coupling(),
            self.limits_deg
                .map(|(lo, hi)| (lo.to_radians(), hi.to_radians())),
            self.max_speed_deg_s.unwrap_or([0.0; 6]),
        )
    }
}

impl Robot {
    /// An arm of the embedded ABB catalogue by name: `IRB 2600-12/1.65`,
    /// `irb2600-12/1.65`, `irb140` (case and spaces do not matter; a family
    /// name alone is enough when the family has one variant). An unknown or
    /// ambiguous name is an error listing the nearest names.
    pub fn abb(name: &str) -> Result<Robot> {
        find(name).map(AbbArm::robot)
    }
}

/// Every arm of the catalogue, parsed once per process. Tests parse the
/// embedded files and check every arm (`tests/robot/arms.rs`), so the
/// `expect` cannot fire on a tested build.
pub fn catalogue() -> &'static [AbbArm] {
    static CATALOGUE: OnceLock<Vec<AbbArm>> = OnceLock::new();
    CATALOGUE.get_or_init(|| load().expect("the embedded data/arms/*.toml are a valid catalogue"))
}

/// The names of every arm, in catalogue order.
pub fn names() -> Vec<&'static str> {
    catalogue().iter().map(|a| a.name.as_str()).collect()
}

/// The arm a name means (see [`Robot::abb`]).
pub fn find(name: &str) -> Result<&'static AbbArm> {
    let all = catalogue();
    let k = key(name);
    if let Some(arm) = all
        .iter()
        .find(|a| key(&a.name) == k || a.aliases.iter().any(|x| key(x) == k))
    {
        return Ok(arm);
    }
    let family: Vec<&AbbArm> = all.iter().filter(|a| key(&a.family) == k).collect();
    match family.as_slice() {
        [one] => return Ok(one),
        [first, ..] => {
            let list: Vec<&str> = family.iter().map(|a| a.name.as_str()).collect();
            return Err(Error::usage(format!(
                "{} comes in {} variants: {}; name one",
                first.family,
                list.len(),
                list.join(", ")
            )));
        }
        [] => {}
    }
    Err(Error::usage(format!(
        "no ABB arm named `{}` in the catalogue",
        name.trim()
    ))
    .with_note(format!("nearest: {}", nearest(&k).join(", ")))
    .with_remedy(Remedy::ListArms))
}

/// Names that start with `k` (a name cut short), else the three nearest by
/// edit distance.
fn nearest(k: &str) -> Vec<&'static str> {
    let all = catalogue();
    let starting: Vec<&str> = all
        .iter()
        .filter(|a| !k.is_empty() && key(&a.name).starts_with(k))
        .map(|a| a.name.as_str())
        .collect();
    if !starting.is_empty() {
        return starting;
    }
    // A family name near the input brings all its variants.
    let mut by_distance: Vec<(usize, usize, &str)> = all
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let d = edit_distance(k, &key(&a.name)).min(edit_distance(k, &key(&a.family)));
            (d, i, a.name.as_str())
        })
        .collect();
    by_distance.sort();
    let best = by_distance.first().map_or(0, |b| b.0);
    by_distance
        .iter()
        .enumerate()
        .take_while(|(n, (d, _, _))| *n < 3 || (*d == best && *n < 8))
        .map(|(_, (_, _, name))| *name)
        .collect()
}

/// A name as it is compared: lower case, no white space, without a leading
/// `ABB` or `IRB`, and the reach after the last `/` as a number (`2.60` and
/// `2.6` are the same arm).
fn key(name: &str) -> String {
    let k: String = name
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect();
    let k = k.strip_prefix("abb").unwrap_or(&k);
    let k = k.strip_prefix("irb").unwrap_or(k);
    let k = k.trim_start_matches(['-', '_']);
    match k.rsplit_once('/') {
        Some((head, reach)) => match reach.parse::<f64>() {
            Ok(r) if r.is_finite() => format!("{head}/{r}"),
            _ => k.to_string(),
        },
        None => k.to_string(),
    }
}

/// Levenshtein distance in characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != *cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FamilyFile {
    family: String,
    sources: BTreeMap<String, Citation>,
    arm: Vec<ArmFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ArmFile {
    name: String,
    family: Option<String>,
    #[serde(default)]
    aliases: Vec<String>,
    payload_kg: f64,
    reach_m: f64,
    axis3: Axis3,
    opw_mm: Option<Opw>,
    limits_deg: Option<[[f64; 2]; 6]>,
    max_speed_deg_s: Option<[f64; 6]>,
    /// `irb140`: the embedded URDF's geometry, limits and speeds.
    embedded: Option<String>,
    from: FromFile,
}

/// Keys of the file's `[sources]` for each kind of number.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FromFile {
    geometry: Vec<String>,
    limits: Vec<String>,
    #[serde(default)]
    speeds: Vec<String>,
    rating: Vec<String>,
    axis3: Vec<String>,
}

/// Parse and check every family file: sources named by each arm exist,
/// every kind of number has a source (speeds: exactly when there are
/// speeds), lengths, limits and speeds are finite and ordered, and no two
/// names (arm names, aliases) mean the same arm.
pub fn load() -> Result<Vec<AbbArm>> {
    let mut out: Vec<AbbArm> = Vec::new();
    for (file, text) in FILES {
        let parsed: FamilyFile = toml::from_str(text)
            .map_err(|e| Error::input(format!("{file}: not a valid arm catalogue: {e}")))?;
        for a in parsed.arm {
            out.push(arm_of(file, &parsed.family, &parsed.sources, a)?);
        }
    }
    let mut seen: BTreeMap<String, &str> = BTreeMap::new();
    for a in &out {
        for n in std::iter::once(&a.name).chain(&a.aliases) {
            if let Some(other) = seen.insert(key(n), &a.name) {
                return Err(Error::input(format!(
                    "{}: `{n}` names {} as well as {other}",
                    a.file, a.name
                )));
            }
        }
    }
    Ok(out)
}

fn arm_of(
    file: &'static str,
    family: &str,
    sources: &BTreeMap<String, Citation>,
    a: ArmFile,
) -> Result<AbbArm> {
    let bad = |msg: String| Error::input(format!("{file}: {}: {msg}", a.name));
    let cite = |what: &str, keys: &[String], needed: bool| -> Result<Vec<Citation>> {
        if needed && keys.is_empty() {
            return Err(bad(format!("no source for its {what}")));
        }
        keys.iter()
            .map(|k| {
                sources
                    .get(k)
                    .cloned()
                    .ok_or_else(|| bad(format!("its {what} cite `{k}`, not in [sources]")))
            })
            .collect()
    };
    let family = a.family.clone().unwrap_or_else(|| family.to_string());
    if !key(&a.name).starts_with(&key(&family)) {
        return Err(bad(format!("the name is not in its family {family}")));
    }
    if !(a.payload_kg.is_finite() && a.payload_kg > 0.0 && a.reach_m.is_finite() && a.reach_m > 0.0)
    {
        return Err(bad("payload and reach must be positive".into()));
    }
    let (opw, limits_deg, speeds, embedded_irb140) =
        match (a.embedded.as_deref(), a.opw_mm, a.limits_deg) {
            (Some("irb140"), None, None) if a.max_speed_deg_s.is_none() => {
                // The URDF's radians in degrees, without the conversion's
                // last-bit noise (110.00000000000001°).
                let deg = |rad: f64| (rad.to_degrees() * 1e9).round() / 1e9;
                let r = Robot::irb140();
                let lim = r.limits.map(|(lo, hi)| (deg(lo), deg(hi)));
                let speeds = r.max_speed_deg_s.map(|v| (v * 1e9).round() / 1e9);
                (irb140_opw(), lim, Some(speeds), true)
            }
            (None, Some(opw), Some(lim)) => (
                opw,
                lim.map(|[lo, hi]| (lo, hi)),
                a.max_speed_deg_s,
                false,
            ),
            _ => {
                return Err(bad(
                "give opw_mm and limits_deg (and max_speed_deg_s if known), or embedded = \"irb140\" alone"
                    .into(),
            ))
            }
        };
    let lengths = [opw.c1, opw.a1, opw.c2, opw.c3, opw.c4, opw.a2, opw.b];
    if !(lengths.iter().all(|v| v.is_finite()) && opw.c2 > 0.0 && opw.c3 > 0.0 && opw.c4 >= 0.0) {
        return Err(bad("OPW lengths must be finite, c2 and c3 positive".into()));
    }
    if let Some(axis) = limits_deg
        .iter()
        .position(|(lo, hi)| !(lo.is_finite() && hi.is_finite() && lo < hi))
    {
        return Err(bad(format!(
            "axis {} needs limits with lower < upper",
            axis + 1
        )));
    }
    if let Some(s) = speeds {
        if !s.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(bad("axis speeds must be positive".into()));
        }
    }
    let has_speeds = speeds.is_some();
    if has_speeds == a.from.speeds.is_empty() {
        return Err(bad(
            "speeds and their source go together (both given or both left out)".into(),
        ));
    }
    Ok(AbbArm {
        sources: ArmSources {
            geometry: cite("geometry", &a.from.geometry, true)?,
            limits: cite("limits", &a.from.limits, true)?,
            speeds: cite("speeds", &a.from.speeds, has_speeds)?,
            rating: cite("payload and reach", &a.from.rating, true)?,
            axis3: cite("axis 3", &a.from.axis3, true)?,
        },
        name: a.name,
        family,
        aliases: a.aliases,
        payload_kg: a.payload_kg,
        reach_m: a.reach_m,
        axis3: a.axis3,
        opw,
        limits_deg,
        max_speed_deg_s: speeds,
        file,
        embedded_irb140,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_compare_without_case_spaces_prefix_or_trailing_zeros() {
        assert_eq!(key("IRB 2600-12/1.65"), key("irb2600-12/1.65"));
        assert_eq!(key(" ABB IRB 6700-200/2.60 "), key("irb6700-200/2.6"));
        assert_eq!(key("IRB 140"), "140");
        assert_ne!(key("IRB 2600-12/1.65"), key("IRB 2600-12/1.85"));
    }

    #[test]
    fn edit_distance_counts_single_changes() {
        assert_eq!(edit_distance("2600", "2600"), 0);
        assert_eq!(edit_distance("2600", "2700"), 1);
        assert_eq!(edit_distance("260", "2600"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
    }
}
