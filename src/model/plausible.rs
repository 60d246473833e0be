//! The largest magnitude each effect parameter can take on a real arm
//! (`data/plausible_effects.toml`): a model file that gives one beyond it
//! is refused where it is read ([`super::file`]), and a fitted value
//! beyond it is the fit wandering along a direction the data hardly
//! constrain, declared not identifiable instead of reported
//! (`diagnose`).

use super::effects::EffectKind;
use crate::error::{Error, Result};
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The embedded bounds.
pub const PLAUSIBLE_EFFECTS_TOML: &str = include_str!("../../data/plausible_effects.toml");

/// The plausible bound of parameter `index` of `kind`, in its unit.
pub fn bound(kind: EffectKind, index: usize) -> f64 {
    static BOUNDS: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    BOUNDS
        .get_or_init(|| {
            parse("data/plausible_effects.toml", PLAUSIBLE_EFFECTS_TOML)
                .expect("the embedded data/plausible_effects.toml bounds every effect parameter")
        })
        .get(kind as usize)
        .and_then(|b| b.get(index))
        .copied()
        .unwrap_or(f64::INFINITY)
}

/// Why `value` cannot be parameter `name` of `kind` on a real arm (beyond
/// its bound), or `None` when it can.
pub fn implausible(kind: EffectKind, name: &str, value: f64) -> Option<String> {
    let params = kind.params();
    // As `Effect::set` takes keys: without regard to case, and
    // thermal-lag's `tau_min` for every link's time constant (one unit).
    let index = params
        .iter()
        .position(|p| p.name.eq_ignore_ascii_case(name))
        .or_else(|| {
            (kind == EffectKind::ThermalLag && name.eq_ignore_ascii_case("tau_min")).then_some(0)
        })?;
    let limit = bound(kind, index);
    if value.abs() <= limit {
        return None;
    }
    let unit = params[index].unit;
    Some(format!(
        "{value} {unit} is beyond what a real arm shows (rapidtherm takes at most {limit} {unit} either way, data/plausible_effects.toml): a unit or a fit gone astray?"
    ))
}

/// Why `k0`, the base model's expansion factor, cannot be a real arm's:
/// the expansion-scale bound of `k - 1` holds for it as for each link's
/// own factor (`data/plausible_effects.toml`).
pub fn implausible_k0(k0: f64) -> Option<String> {
    let limit = bound(EffectKind::ExpansionScale, 0);
    if (0.0..=1.0 + limit).contains(&k0) {
        return None;
    }
    Some(format!(
        "{k0} is no expansion factor of a real arm (rapidtherm takes 0 to {}: k - 1 within ±{limit}, data/plausible_effects.toml)",
        1.0 + limit
    ))
}

/// Every effect's bounds (in the order of [`EffectKind::ALL`]) from `text`:
/// a table per effect, a bound per unit of its parameters or per parameter
/// name (a name wins over its unit). Every parameter needs a positive
/// finite bound; unknown effects and keys are refused.
fn parse(file: &str, text: &str) -> Result<Vec<Vec<f64>>> {
    let mut given: BTreeMap<String, BTreeMap<String, f64>> = toml::from_str(text)
        .map_err(|e| Error::input(format!("{file}: plausible bounds: {}", e.message())))?;
    let bad = |msg: String| Error::input(format!("{file}: plausible bounds: {msg}"));
    let mut out = Vec::with_capacity(EffectKind::ALL.len());
    for kind in EffectKind::ALL {
        let table = given
            .remove(kind.name())
            .ok_or_else(|| bad(format!("no table [{}]", kind.name())))?;
        let params = kind.params();
        for key in table.keys() {
            if !params.iter().any(|p| p.name == key || p.unit == key) {
                return Err(bad(format!(
                    "[{}] has no parameter or unit `{key}`",
                    kind.name()
                )));
            }
        }
        let mut bounds = Vec::with_capacity(params.len());
        for p in params {
            let b = table
                .get(p.name)
                .or_else(|| table.get(p.unit))
                .copied()
                .ok_or_else(|| bad(format!("[{}] bounds no `{}`", kind.name(), p.name)))?;
            if !(b.is_finite() && b > 0.0) {
                return Err(bad(format!(
                    "[{}] {}: a bound must be positive and finite",
                    kind.name(),
                    p.name
                )));
            }
            bounds.push(b);
        }
        out.push(bounds);
    }
    if let Some(extra) = given.keys().next() {
        return Err(bad(format!("unknown effect `{extra}`")));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_is_bounded_beyond_its_default() {
        let all = parse("data/plausible_effects.toml", PLAUSIBLE_EFFECTS_TOML).unwrap();
        for kind in EffectKind::ALL {
            for (i, p) in kind.params().iter().enumerate() {
                let b = all[kind as usize][i];
                // A default is an illustration of a real size: far inside.
                assert!(b >= 5.0 * p.default.abs(), "{}.{}", kind.name(), p.name);
            }
        }
        assert_eq!(bound(EffectKind::GeometryOffset, 0), 10.0);
        let point_z = EffectKind::GeometryOffset
            .params()
            .iter()
            .position(|p| p.name == "point_z_mm")
            .unwrap();
        assert_eq!(bound(EffectKind::GeometryOffset, point_z), 100.0);
    }

    #[test]
    fn unknown_keys_and_missing_bounds_are_refused() {
        let text = PLAUSIBLE_EFFECTS_TOML.replace("[gravity-sag]\nurad", "[gravity-sag]\nurads");
        let e = parse("x.toml", &text).unwrap_err();
        assert!(e.message.contains("urads"), "{}", e.message);
        let text =
            PLAUSIBLE_EFFECTS_TOML.replace("[tracker-frame]\nmm = 100.0\n", "[tracker-frame]\n");
        let e = parse("x.toml", &text).unwrap_err();
        assert!(e.message.contains("tracker-frame"), "{}", e.message);
    }
}
