//! Collision and mass shapes, in body space with the centre of mass at the origin.

use crate::math::Vec3;
use serde::Deserialize;

/// Local axis of a capsule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
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
    Sphere {
        radius: f32,
    },
    /// `half_height` is half the distance between the two cap centres.
    Capsule {
        half_height: f32,
        radius: f32,
        axis: Axis,
    },
    Cuboid {
        half_extents: Vec3,
    },
    /// The solid below the plane through the body's origin with normal `+Y` (body space); for
    /// fixed bodies only (floors, ramps).
    HalfSpace,
}

impl Shape {
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
}
