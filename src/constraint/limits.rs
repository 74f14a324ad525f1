//! Angular joint limits in swing-twist form, shared by ball-and-socket joints.
//!
//! The joint frame F_i = q_i f_i of each body has its x axis along the twist (or hinge) axis.
//! With the relative rotation `r = F_a^-1 F_b = swing * twist` (twist about x first):
//! - swing angle = angle between the world x axes `a_x = F_a x` and `b_x = F_b x`; above
//!   `swing_max` it is reduced by turning b about `a_x x b_x`;
//! - twist angle = 2 atan2(r_x, r_w); outside [twist_min, twist_max] it is clamped by turning b
//!   about its own x axis, which changes the twist and nothing else. The preview's twist is
//!   unwrapped next to the twist at the start of the step, so a body that turns past +-pi in
//!   one step is clamped back to the side it came from. Clamping the wrapped angle instead sends
//!   it to the opposite bound, and the velocity derived from that jump feeds a flip between the
//!   two bounds every step (an arm spinning at 130 rad/s in the drop, before this).
//!
//! A hinge (knee, elbow) is the same limit with `swing_max = 0`: the two x axes are held aligned
//! and the twist angle is the hinge angle. Aligning the axes is two rows (the error's two
//! components across a's axis); the exact flavour solves them as one 2x2 block, the cheap one as
//! one row along the error, which a limb's anisotropic inertia turns into a twist back and forth
//! every substep ([`super::parts::relative_rotation_across`]).

use super::parts::{relative_rotation, relative_rotation_across};
use crate::math::{angle_between, any_perpendicular, twist_angle, wrap_angle, Quat, Vec3};
use crate::solver_body::SolverBody;

/// A hinge's axes apart by more than this (rad) are aligned by one row along the error even in
/// the exact flavour: the block is the linearisation about aligned axes, and far from it (a
/// hinge folded back on itself) the free turn it adds about the axis can carry the twist across
/// +-pi, where rounding decides which bound it is clamped to.
pub const HINGE_BLOCK_MAX_SWING: f32 = 1.0;

/// An angular limit on a joint's frames: a swing cone about the x axis and a twist range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngularLimit {
    /// Cone half-angle (rad) of the twist axis; 0 makes a hinge.
    pub swing_max: f32,
    /// Lowest twist angle about the x axis (rad).
    pub twist_min: f32,
    /// Highest twist angle about the x axis (rad).
    pub twist_max: f32,
}

impl AngularLimit {
    /// A cone of half-angle `swing_max` with twist range [twist_min, twist_max] (rad).
    pub fn cone(swing_max: f32, twist_min: f32, twist_max: f32) -> Self {
        Self {
            swing_max,
            twist_min,
            twist_max,
        }
    }

    /// A hinge about the joint frame's x axis with angle range [min, max].
    pub fn hinge(min: f32, max: f32) -> Self {
        Self {
            swing_max: 0.0,
            twist_min: min,
            twist_max: max,
        }
    }

    /// Current (swing, twist) of the joint frames.
    pub fn angles(frame_a: Quat, frame_b: Quat) -> (f32, f32) {
        let swing = angle_between(frame_a * Vec3::X, frame_b * Vec3::X);
        let twist = twist_angle(frame_a.inverse() * frame_b, Vec3::X);
        (swing, twist)
    }

    /// How far (rad) the swing and twist lie outside the limit, summed.
    pub fn violation(&self, frame_a: Quat, frame_b: Quat) -> f32 {
        let (swing, twist) = Self::angles(frame_a, frame_b);
        (swing - self.swing_max).max(0.0) + self.twist_excess(twist).abs()
    }

    fn twist_excess(&self, twist: f32) -> f32 {
        if twist > self.twist_max {
            twist - self.twist_max
        } else if twist < self.twist_min {
            twist - self.twist_min
        } else {
            0.0
        }
    }

    /// Twist at the start of the substep (prepare stage), which the solve unwraps against.
    pub fn start_twist(frame_a: Quat, frame_b: Quat) -> f32 {
        twist_angle(frame_a.inverse() * frame_b, Vec3::X)
    }

    /// Projects the preview orientations onto the limit (hard, relaxation 1). `start_twist` is
    /// [`AngularLimit::start_twist`] at the substep's start poses. With `hinge_block` a hinge's
    /// two axes are aligned by the 2x2 block across a's axis
    /// ([`super::parts::relative_rotation_across`], the exact flavour's), else by one row along
    /// the error (the cheap flavour's, and every cone's: a cone past its edge is one row).
    #[inline(always)]
    pub fn solve(
        &self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        local_frame_a: Quat,
        local_frame_b: Quat,
        start_twist: f32,
        hinge_block: bool,
    ) {
        let ax = a.orientation * local_frame_a * Vec3::X;
        let bx = b.orientation * local_frame_b * Vec3::X;
        let swing = angle_between(ax, bx);
        if swing > self.swing_max {
            let axis = ax
                .cross(bx)
                .try_normalize()
                .unwrap_or_else(|| any_perpendicular(ax));
            if hinge_block && self.swing_max == 0.0 && swing < HINGE_BLOCK_MAX_SWING {
                relative_rotation_across(a, b, -swing * axis, ax);
            } else {
                relative_rotation(a, b, -(swing - self.swing_max) * axis);
            }
        }
        let frame_a = a.orientation * local_frame_a;
        let frame_b = b.orientation * local_frame_b;
        let twist = twist_angle(frame_a.inverse() * frame_b, Vec3::X);
        let excess = self.twist_excess(start_twist + wrap_angle(twist - start_twist));
        if excess != 0.0 {
            relative_rotation(a, b, -excess * (frame_b * Vec3::X));
        }
    }
}
