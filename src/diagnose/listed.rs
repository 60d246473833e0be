//! Which fitted parameters a report lists: those with a place on the arm,
//! and geometry's joint origins only where they were fitted.

use crate::model::effects::GEOMETRY_ORIGINS_FROM;
use crate::model::EffectKind;

/// Whether the parameter `name` (`effect.param`) has a place on the arm
/// ([`crate::model::Geometry::has_param`]): one without is not listed.
pub(super) fn has_place(geometry: &crate::model::Geometry, name: &str) -> bool {
    let Some((effect, param)) = name.split_once('.') else {
        return true;
    };
    let Some(kind) = EffectKind::from_name(effect) else {
        return true;
    };
    kind.params()
        .iter()
        .position(|p| p.name == param)
        .is_none_or(|i| geometry.has_param(kind, i))
}

/// Whether `name` (`effect.param`) is one of geometry-offset's joint-origin
/// or measured-point parameters.
pub(super) fn is_origin_param(name: &str) -> bool {
    name.strip_prefix("geometry-offset.").is_some_and(|p| {
        EffectKind::GeometryOffset.params()[GEOMETRY_ORIGINS_FROM..]
            .iter()
            .any(|info| info.name == p)
    })
}
