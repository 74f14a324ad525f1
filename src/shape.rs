//! Collision and mass shapes, in body space with the centre of mass at the origin.

use crate::math::{Quat, Vec3};
use serde::Deserialize;

/// Local axis of a capsule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// Body-space x axis.
    X,
    /// Body-space y axis.
    Y,
    /// Body-space z axis.
    Z,
}

impl Axis {
    /// The axis as a unit vector.
    pub fn unit(self) -> Vec3 {
        match self {
            Axis::X => Vec3::X,
            Axis::Y => Vec3::Y,
            Axis::Z => Vec3::Z,
        }
    }
}

/// A body's shape. Capsules and boxes are centred on the body's origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A ball.
    Sphere {
        /// Radius (m).
        radius: f32,
    },
    /// `half_height` is half the distance between the two cap centres.
    Capsule {
        /// Half the distance between the cap centres (m).
        half_height: f32,
        /// Radius of the caps and the cylinder (m).
        radius: f32,
        /// Body-space axis through the two cap centres.
        axis: Axis,
    },
    /// A box.
    Cuboid {
        /// Half the box's size along each body axis (m).
        half_extents: Vec3,
    },
    /// The solid below the plane through the body's origin with normal `+Y` (body space); for
    /// fixed bodies only (floors, ramps).
    HalfSpace,
}

impl Shape {
    /// Volume (m^3); infinite for a half-space.
    pub fn volume(&self) -> f32 {
        use std::f32::consts::PI;
        match *self {
            Shape::Sphere { radius } => 4.0 / 3.0 * PI * radius.powi(3),
            Shape::Capsule {
                half_height,
                radius,
                ..
            } => PI * radius * radius * 2.0 * half_height + 4.0 / 3.0 * PI * radius.powi(3),
            Shape::Cuboid { half_extents: h } => 8.0 * h.x * h.y * h.z,
            Shape::HalfSpace => f32::INFINITY,
        }
    }

    /// Principal moments of inertia (body axes) for uniform density and total `mass`.
    pub fn principal_inertia(&self, mass: f32) -> Vec3 {
        match *self {
            Shape::HalfSpace => Vec3::ZERO, // fixed bodies only: never inverted
            Shape::Sphere { radius } => Vec3::splat(0.4 * mass * radius * radius),
            Shape::Cuboid { half_extents: h } => {
                let (x2, y2, z2) = (4.0 * h.x * h.x, 4.0 * h.y * h.y, 4.0 * h.z * h.z);
                mass / 12.0 * Vec3::new(y2 + z2, x2 + z2, x2 + y2)
            }
            Shape::Capsule {
                half_height: h,
                radius: r,
                axis,
            } => {
                // Cylinder of length 2h plus two hemispheres, mass shared by volume.
                let cylinder_volume = std::f32::consts::PI * r * r * 2.0 * h;
                let cylinder_mass = mass * cylinder_volume / self.volume();
                let caps_mass = mass - cylinder_mass;
                let axial = cylinder_mass * r * r / 2.0 + caps_mass * 0.4 * r * r;
                // Each hemisphere about the capsule centre: 2r^2/5 + h^2 + 3hr/4 (parallel axis
                // through the hemisphere's centroid at 3r/8 from its flat face).
                let transverse = cylinder_mass * (r * r / 4.0 + h * h / 3.0)
                    + caps_mass * (0.4 * r * r + h * h + 0.75 * h * r);
                let mut inertia = Vec3::splat(transverse);
                match axis {
                    Axis::X => inertia.x = axial,
                    Axis::Y => inertia.y = axial,
                    Axis::Z => inertia.z = axial,
                }
                inertia
            }
        }
    }

    /// Half-size of the tightest world axis-aligned box around the shape at `orientation`,
    /// centred on the body's origin (the broad phase's boxes): a capsule's is its segment's
    /// extent plus the radius, a box's is `|R| h`. Infinite for a half-space.
    pub fn world_half_extents(&self, orientation: Quat) -> Vec3 {
        match *self {
            Shape::Sphere { radius } => Vec3::splat(radius),
            Shape::Capsule {
                half_height,
                radius,
                axis,
            } => (orientation * (half_height * axis.unit())).abs() + Vec3::splat(radius),
            Shape::Cuboid { half_extents } => {
                let r = crate::math::Mat3::from_quat(orientation);
                r.x_axis.abs() * half_extents.x
                    + r.y_axis.abs() * half_extents.y
                    + r.z_axis.abs() * half_extents.z
            }
            Shape::HalfSpace => Vec3::INFINITY,
        }
    }

    /// Two body-space points that show how the shape turns: the ends of its two longest half
    /// extents (a capsule's segment end plus radius, and its radius across). With the centre
    /// they are the sleep test's points ([`crate::sleep`]); a turn about any axis moves one.
    pub fn sleep_test_offsets(&self) -> [Vec3; 2] {
        match *self {
            Shape::Sphere { radius } => [radius * Vec3::X, radius * Vec3::Y],
            Shape::Capsule {
                half_height,
                radius,
                axis,
            } => {
                let along = axis.unit();
                let across = along.any_orthonormal_vector();
                [(half_height + radius) * along, radius * across]
            }
            Shape::Cuboid { half_extents: h } => {
                let mut axes = [h.x * Vec3::X, h.y * Vec3::Y, h.z * Vec3::Z];
                axes.sort_by(|a, b| b.length_squared().total_cmp(&a.length_squared()));
                [axes[0], axes[1]]
            }
            Shape::HalfSpace => [Vec3::ZERO; 2],
        }
    }

    /// Half-size of an axis-aligned box around the shape in body space (for drawing and checks).
    pub fn bounding_radius(&self) -> f32 {
        match *self {
            Shape::Sphere { radius } => radius,
            Shape::Capsule {
                half_height,
                radius,
                ..
            } => half_height + radius,
            Shape::Cuboid { half_extents } => half_extents.length(),
            Shape::HalfSpace => f32::INFINITY,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capsule_tends_to_sphere_and_rod() {
        let sphere = Shape::Sphere { radius: 0.5 }.principal_inertia(2.0);
        let capsule = Shape::Capsule {
            half_height: 0.0,
            radius: 0.5,
            axis: Axis::Y,
        }
        .principal_inertia(2.0);
        assert!((sphere - capsule).abs().max_element() < 1e-6);
        // A long thin capsule approaches a thin rod: m L^2 / 12 transverse.
        let rod = Shape::Capsule {
            half_height: 5.0,
            radius: 1e-3,
            axis: Axis::X,
        }
        .principal_inertia(1.0);
        assert!((rod.y - 100.0 / 12.0).abs() / (100.0 / 12.0) < 1e-3);
        assert!(rod.x < 1e-6);
    }

    /// The world box is tight: it holds every surface point of a tumbled capsule and box, and
    /// on each axis some surface point reaches its face.
    #[test]
    fn world_box_is_tight_around_rotated_shapes() {
        let orientation = Quat::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 0.9);
        let capsule = Shape::Capsule {
            half_height: 0.3,
            radius: 0.1,
            axis: Axis::Z,
        };
        let cuboid = Shape::Cuboid {
            half_extents: Vec3::new(0.4, 0.1, 0.25),
        };
        let capsule_points = (0..=20).flat_map(|i| {
            let centre = orientation * Vec3::new(0.0, 0.0, -0.3 + 0.03 * i as f32);
            [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z].map(|d| centre + 0.1 * d)
        });
        let corners = (0..8).map(|i| {
            let sign = |bit: u32| if i >> bit & 1 == 1 { 1.0 } else { -1.0 };
            orientation * (Vec3::new(sign(0), sign(1), sign(2)) * Vec3::new(0.4, 0.1, 0.25))
        });
        let check = |shape: Shape, points: Vec<Vec3>| {
            let half = shape.world_half_extents(orientation);
            let reach = points.iter().fold(Vec3::ZERO, |m, p| m.max(p.abs()));
            assert!(
                (reach - half).max_element() < 1e-5,
                "{reach} outside {half}"
            );
            assert!(
                (half - reach).max_element() < 1e-5,
                "{half} looser than {reach}"
            );
        };
        check(capsule, capsule_points.collect());
        check(cuboid, corners.collect());
    }
}
