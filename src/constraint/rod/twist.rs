//! The rod's twist measure tau (eq. 12-13): exact (parallel transport along the arc) or the
//! paper's eq. 12.

use super::TwistMode;
use crate::math::{angle_between, twist_angle, Quat, Vec3};

/// tau by `mode` (see [`TwistMode`]).
#[inline(always)]
pub fn measure_twist(mode: TwistMode, frame_a: Quat, frame_b: Quat) -> f32 {
    let exact = twist_exact(frame_a, frame_b);
    match mode {
        TwistMode::Exact => exact,
        TwistMode::Paper => twist_paper(frame_a, frame_b).copysign(exact),
    }
}

/// Signed twist about t_b: `F(1)` against `F(0)` carried along the arc by the minimal rotation
/// taking t_a to t_b.
pub fn twist_exact(frame_a: Quat, frame_b: Quat) -> f32 {
    let transport = crate::math::quat_from_rotation_arc(frame_a * Vec3::X, frame_b * Vec3::X);
    twist_angle((transport * frame_a).inverse() * frame_b, Vec3::X)
}

/// The paper's eq. 12: `tau = xi - psi`, xi the total angle between the two frames.
pub fn twist_paper(frame_a: Quat, frame_b: Quat) -> f32 {
    let xi = crate::math::rotation_vector(frame_a.inverse() * frame_b).length();
    xi - angle_between(frame_a * Vec3::X, frame_b * Vec3::X)
}
