//! A body as contact detection reads it: a compact record per body, built once per step.
//!
//! The settled 1000-ragdoll rain tests about 57 000 candidate pairs a frame, two thirds of them
//! without a contact. Read from [`Body`] (256 bytes, the fields a pair needs spread over several
//! cache lines) every pair waited on its bodies' lines, and a pair that touches on its bodies'
//! friction coefficients in yet another (in a profile, a third of the pair loop's own time
//! stood on those loads). The record holds all that the broad phase's box loop, the narrow
//! phase's tests and a new point read (pose, velocities, speed bound, the capsule's world
//! segment, filter bits, friction) in 112 bytes. Every derived value is computed as the body's
//! own methods compute it, so detection gives the same points to the bit.

use crate::body::{Body, BodyKind};
use crate::math::{Quat, Vec3};
use crate::shape::Shape;

/// The record of one body that contact detection reads (112 bytes).
///
/// `repr(C)` in this order so that a float follows each `Vec3` and the shape, never the filter
/// bits (why: [`super::handover::Handed`]); left to the compiler, the collision group followed
/// the velocity.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct Collider {
    /// Body-to-world rotation.
    pub orientation: Quat,
    /// World position of the centre of mass (m).
    pub position: Vec3,
    /// [`Body::spin_speed_bound`]: how fast spin moves a surface point at most (m/s).
    pub spin_bound: f32,
    /// Velocity of the centre of mass (m/s).
    pub linear_velocity: Vec3,
    /// [`Shape::bounding_radius`].
    pub bounding_radius: f32,
    /// A capsule's cap centres are `position -+ half_axis` (world space); zero for the rest.
    pub half_axis: Vec3,
    /// Static friction coefficient mu_s.
    pub static_friction: f32,
    /// The body's shape (a box's half extents end it).
    pub shape: Shape,
    /// Dynamic friction coefficient mu_d.
    pub dynamic_friction: f32,
    /// Read only for the pairs that touch.
    pub angular_velocity: Vec3,
    /// Coefficient of restitution.
    pub restitution: f32,
    /// Collision filter group bits.
    pub collision_group: u32,
    /// Collision filter mask bits.
    pub collision_mask: u32,
    /// Dynamic, fixed or kinematic.
    pub kind: BodyKind,
    /// [`Body::moves_this_step`].
    pub moves: bool,
}

impl Collider {
    /// The record of `body` at its current pose.
    pub fn new(body: &Body) -> Self {
        let half_axis = match body.shape {
            Shape::Capsule {
                half_height, axis, ..
            } => body.orientation * (half_height * axis.unit()),
            _ => Vec3::ZERO,
        };
        Collider {
            position: body.position,
            spin_bound: body.spin_speed_bound(),
            orientation: body.orientation,
            linear_velocity: body.linear_velocity,
            collision_group: body.collision_group,
            shape: body.shape,
            half_axis,
            collision_mask: body.collision_mask,
            bounding_radius: body.shape.bounding_radius(),
            kind: body.kind,
            moves: body.moves_this_step(),
            angular_velocity: body.angular_velocity,
            static_friction: body.static_friction,
            dynamic_friction: body.dynamic_friction,
            restitution: body.restitution,
        }
    }

    /// World position of a body-space point.
    #[inline]
    pub fn world_point(&self, local: Vec3) -> Vec3 {
        self.position + self.orientation * local
    }

    /// Body-space coordinates of a world point (the inverse of [`Self::world_point`]).
    #[inline]
    pub fn local_point(&self, world: Vec3) -> Vec3 {
        self.orientation.inverse() * (world - self.position)
    }

    /// Velocity (m/s) of the body's material at world `point`.
    #[inline]
    pub fn point_velocity(&self, point: Vec3) -> Vec3 {
        self.linear_velocity + self.angular_velocity.cross(point - self.position)
    }

    /// World segment (cap centres) and radius of a sphere or capsule.
    #[inline]
    pub fn segment(&self) -> Option<(Vec3, Vec3, f32)> {
        match self.shape {
            Shape::Sphere { radius } => Some((self.position, self.position, radius)),
            Shape::Capsule { radius, .. } => Some((
                self.position - self.half_axis,
                self.position + self.half_axis,
                radius,
            )),
            _ => None,
        }
    }

    /// [`Shape::world_half_extents`] at this orientation (a capsule's from its half axis).
    #[inline]
    pub fn world_half_extents(&self) -> Vec3 {
        match self.shape {
            Shape::Capsule { radius, .. } => self.half_axis.abs() + Vec3::splat(radius),
            shape => shape.world_half_extents(self.orientation),
        }
    }
}

const _: () = assert!(std::mem::size_of::<Collider>() == 112);

/// A world of at least this many bodies builds its records and boxes on several threads (a
/// small one would spend more waiting for the threads than it saves).
pub const PARALLEL_BODIES: usize = 4096;

/// Refills `colliders` from `bodies` (on several threads for a large world; each record is
/// its body's alone, so the result is the same).
pub fn build(bodies: &[Body], colliders: &mut Vec<Collider>) {
    colliders.clear();
    if bodies.len() >= PARALLEL_BODIES && rayon::current_num_threads() > 1 {
        use rayon::prelude::*;
        colliders.par_extend(bodies.par_iter().map(Collider::new));
    } else {
        colliders.extend(bodies.iter().map(Collider::new));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::Axis;

    /// The record's segment and boxes are the body's, to the bit.
    #[test]
    fn a_collider_derives_what_the_body_does() {
        let shapes = [
            Shape::Sphere { radius: 0.1 },
            Shape::Capsule {
                half_height: 0.2,
                radius: 0.05,
                axis: Axis::Z,
            },
            Shape::Cuboid {
                half_extents: Vec3::new(0.3, 0.1, 0.2),
            },
        ];
        for shape in shapes {
            let mut body = Body::new("b", BodyKind::Dynamic, shape, 1.0).with_pose(
                Vec3::new(0.3, -1.7, 2.9),
                Quat::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.7),
            );
            body.angular_velocity = Vec3::new(3.0, -1.0, 0.5);
            let c = Collider::new(&body);
            let half = body.shape.world_half_extents(body.orientation);
            assert_eq!(c.world_half_extents().to_array(), half.to_array());
            assert_eq!(c.spin_bound, body.spin_speed_bound());
            let p = Vec3::new(0.1, 0.2, -0.3);
            assert_eq!(c.world_point(p), body.world_point(p));
            if let Shape::Capsule { radius, .. } = shape {
                let axis = body.orientation * (0.2 * Vec3::Z);
                let expected = (body.position - axis, body.position + axis, radius);
                assert_eq!(c.segment(), Some(expected));
            }
        }
    }

    /// A float follows each `Vec3` of the record, and the shape, which a box's half extents
    /// end ([`Collider`]'s field order).
    #[test]
    fn a_float_follows_each_vector() {
        use std::mem::{offset_of, size_of};
        crate::math::assert_float_follows!(Collider:
            position => spin_bound,
            linear_velocity => bounding_radius,
            half_axis => static_friction,
            angular_velocity => restitution,
        );
        let shape = Shape::Cuboid {
            half_extents: Vec3::new(1.5, 2.5, 3.5),
        };
        let end = size_of::<Shape>() - size_of::<f32>();
        // SAFETY: the shape's last four bytes lie within it and hold the half extents' z
        let last = unsafe {
            (&raw const shape)
                .cast::<u8>()
                .add(end)
                .cast::<f32>()
                .read_unaligned()
        };
        assert_eq!(last, 3.5, "a box's half extents end the shape");
        let shape_end = offset_of!(Collider, shape) + size_of::<Shape>();
        assert_eq!(shape_end, offset_of!(Collider, dynamic_friction));
        assert_eq!(size_of::<Collider>(), 112);
    }
}
