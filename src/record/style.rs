//! Colours and line styles shared by the recordings.

use crate::ragdoll::SpineKind;
use crate::skeleton::BoneMethod;

/// A spine's colour (Fig. 8: a multi-joint spine blue, rod red; single joint green); a plain
/// group of loose joints is orange.
pub(super) fn spine_color(spine: Option<SpineKind>) -> rerun::Color {
    match spine {
        Some(SpineKind::Chain3 | SpineKind::Rig) => rerun::Color::from_rgb(60, 110, 220),
        Some(SpineKind::Rod) => rerun::Color::from_rgb(220, 60, 50),
        Some(SpineKind::Single) => rerun::Color::from_rgb(60, 170, 90),
        None => rerun::Color::from_rgb(230, 150, 40),
    }
}

/// The colour of bodies that are not dynamic (fixed or kinematic).
pub(super) fn fixed_color() -> rerun::Color {
    rerun::Color::from_rgb(110, 110, 110)
}

/// The colour of the bones posed by `method`.
pub(super) fn bone_color(method: BoneMethod) -> rerun::Color {
    match method {
        BoneMethod::Rigid => rerun::Color::from_rgb(240, 240, 240),
        BoneMethod::Orientation => rerun::Color::from_rgb(250, 220, 60),
        BoneMethod::OrientationPosition => rerun::Color::from_rgb(60, 220, 250),
        BoneMethod::Arc => rerun::Color::from_rgb(250, 90, 200),
    }
}

/// Static style of a line-strip entity.
pub(super) fn strip_style(radius: f32, color: rerun::Color) -> rerun::LineStrips3D {
    rerun::LineStrips3D::update_fields()
        .with_radii([radius])
        .with_colors([color])
}
