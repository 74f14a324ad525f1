//! Mass, centre of mass and inertia of the rig's shapes, from the true solids.
//!
//! Jolt approximates a tapered capsule's mass properties by those of its bounding box, with
//! the centre of mass half way between its two ends; here the solid itself is integrated.
//! Jolt's samples then call `RagdollSettings::Stabilize`, which limits the mass ratio of parent
//! and child parts and raises parents' inertia; nothing here does that.
//!
//! A tapered capsule (Jolt's `TaperedCapsuleShape`) is the convex hull of two spheres on the y
//! axis: the top one of radius `a` centred at `y = +h`, the bottom one of radius `b` at
//! `y = -h`. With `sin α = (b - a) / 2h` the cone tangent to both touches the top sphere on
//! the circle at `y = h + a sin α` of radius `a cos α`, the bottom one at `y = -h + b sin α`,
//! radius `b cos α`. The solid is three pieces of revolution about y: the bottom sphere's cap
//! below its circle, the cone frustum between the circles (radius linear in y), the top
//! sphere's cap above its circle. Sliced into discs of radius `ρ(y)`, density `ρ_m`:
//!
//! ```text
//! V = ∫ π ρ² dy            m ȳ = ρ_m ∫ π ρ² y dy
//! I_yy = ρ_m ∫ π ρ⁴ / 2 dy   I_xx = I_zz = ρ_m ∫ π (ρ⁴ / 4 + ρ² y²) dy - m ȳ²
//! ```
//!
//! (a disc's own inertia, `ρ² dm / 2` about its axis and `ρ² dm / 4` about a diameter, plus
//! the parallel-axis term). On each piece `ρ²` is a polynomial of degree at most 2 in `y`
//! (`r² - (y - c)²` on a cap, the square of a linear function on the frustum), so every
//! integrand is a polynomial of degree at most 4, which 3-point Gauss-Legendre quadrature
//! integrates exactly: the results are exact up to rounding. Equal radii give the capsule
//! (a cylinder and two hemispheres); when one sphere holds the other (`|a - b| >= 2h`),
//! `sin α` clamps to ±1 and the result is the larger sphere, which is what Jolt builds then.

use super::{PartShape, SubShape};
use crate::math::{Mat3, Quat, Vec3};

/// The mass properties of a solid in some frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass (kg).
    pub mass: f32,
    /// Centre of mass in the frame (m).
    pub com: Vec3,
    /// Inertia tensor about the centre of mass, along the frame's axes (kg m^2).
    pub inertia: Mat3,
}

impl MassProperties {
    /// The same solid moved by `rotation` then `position`: `com' = p + R com`,
    /// `I' = R I Rᵀ`.
    pub fn transformed(&self, position: Vec3, rotation: Quat) -> MassProperties {
        let r = Mat3::from_quat(rotation);
        MassProperties {
            mass: self.mass,
            com: position + rotation * self.com,
            inertia: r * self.inertia * r.transpose(),
        }
    }

    /// The union of solids given in one frame: their masses add, the centre of mass is the
    /// mass-weighted mean, and each inertia moves to it by the parallel-axis theorem,
    /// `I + m (|d|² E - d dᵀ)`.
    pub fn sum(items: &[MassProperties]) -> MassProperties {
        let mass: f32 = items.iter().map(|p| p.mass).sum();
        let weighted: Vec3 = items.iter().map(|p| p.com * p.mass).sum();
        let com = if mass > 0.0 {
            weighted / mass
        } else {
            Vec3::ZERO
        };
        let mut inertia = Mat3::ZERO;
        for p in items {
            let d = p.com - com;
            let outer = Mat3::from_cols(d * d.x, d * d.y, d * d.z);
            inertia += p.inertia + (Mat3::IDENTITY * d.length_squared() - outer) * p.mass;
        }
        MassProperties { mass, com, inertia }
    }

    /// The same shape with mass `mass`: the inertia scales with it (Jolt's `ScaleToMass`).
    pub fn scaled_to_mass(&self, mass: f32) -> MassProperties {
        let scale = if self.mass > 0.0 {
            mass / self.mass
        } else {
            0.0
        };
        MassProperties {
            mass,
            com: self.com,
            inertia: self.inertia * scale,
        }
    }
}

impl PartShape {
    /// Mass properties of the solid shape of density `density`, in its own frame.
    pub fn mass_properties(&self, density: f32) -> MassProperties {
        match *self {
            PartShape::Capsule {
                half_height: h,
                radius,
            } => capsule(h, radius, density),
            PartShape::TaperedCapsule {
                half_height: h,
                top_radius: a,
                bottom_radius: b,
            } => tapered_capsule(h, a, b, density),
            PartShape::Box { half_extent, .. } => solid_box(half_extent, density),
        }
    }
}

/// The mass properties of a body made of `shapes`, in the body frame.
pub fn of_shapes(shapes: &[SubShape]) -> MassProperties {
    let placed = |s: &SubShape| {
        s.shape
            .mass_properties(s.density)
            .transformed(s.position, s.rotation)
    };
    MassProperties::sum(&shapes.iter().map(placed).collect::<Vec<_>>())
}

/// A solid box of half extents `half` centred on the origin, density `density` (kg/m^3).
pub fn solid_box(half: Vec3, density: f32) -> MassProperties {
    let mass = 8.0 * half.x * half.y * half.z * density;
    let sq = half * half;
    let diagonal = Vec3::new(sq.y + sq.z, sq.x + sq.z, sq.x + sq.y) * (mass / 3.0);
    MassProperties {
        mass,
        com: Vec3::ZERO,
        inertia: Mat3::from_diagonal(diagonal),
    }
}

/// A capsule along y: the sphere centres at `±half_height`, radius `radius`.
pub fn capsule(half_height: f32, radius: f32, density: f32) -> MassProperties {
    tapered_capsule(half_height, radius, radius, density)
}

/// The squared radius of a solid of revolution's disc at height y.
type Profile<'a> = &'a dyn Fn(f64) -> f64;

/// A tapered capsule along y: the convex hull of the sphere of radius `top_radius` at
/// `y = +half_height` and the one of radius `bottom_radius` at `y = -half_height` (module
/// docs for the derivation).
pub fn tapered_capsule(
    half_height: f32,
    top_radius: f32,
    bottom_radius: f32,
    density: f32,
) -> MassProperties {
    let (h, a, b) = (
        f64::from(half_height),
        f64::from(top_radius),
        f64::from(bottom_radius),
    );
    let sin = if h > 0.0 {
        ((b - a) / (2.0 * h)).clamp(-1.0, 1.0)
    } else {
        (b - a).signum()
    };
    let cos = (1.0 - sin * sin).max(0.0).sqrt();
    let (y_bottom, y_top) = (-h + b * sin, h + a * sin);
    let (rho_bottom, rho_top) = (b * cos, a * cos);
    let frustum = |y: f64| {
        let t = if y_top > y_bottom {
            (y - y_bottom) / (y_top - y_bottom)
        } else {
            0.0
        };
        let rho = rho_bottom + t * (rho_top - rho_bottom);
        rho * rho
    };
    let pieces: [(f64, f64, Profile); 3] = [
        (-h - b, y_bottom, &|y| b * b - (y + h) * (y + h)),
        (y_bottom, y_top, &frustum),
        (y_top, h + a, &|y| a * a - (y - h) * (y - h)),
    ];
    // Gauss-Legendre, 3 points on [-1, 1]: exact for polynomials up to degree 5.
    let node = (0.6f64).sqrt();
    let gauss = [(-node, 5.0 / 9.0), (0.0, 8.0 / 9.0), (node, 5.0 / 9.0)];
    let (mut volume, mut moment, mut i_axis, mut i_across) = (0.0, 0.0, 0.0, 0.0);
    for (y0, y1, rho2) in pieces {
        let half = 0.5 * (y1 - y0);
        for (x, w) in gauss {
            let y = y0 + half * (x + 1.0);
            let r2 = rho2(y).max(0.0);
            let dv = std::f64::consts::PI * r2 * w * half;
            volume += dv;
            moment += dv * y;
            i_axis += dv * r2 * 0.5;
            i_across += dv * (r2 * 0.25 + y * y);
        }
    }
    let rho_m = f64::from(density);
    let mass = volume * rho_m;
    let y_com = if volume > 0.0 { moment / volume } else { 0.0 };
    let across = (i_across * rho_m - mass * y_com * y_com) as f32;
    MassProperties {
        mass: mass as f32,
        com: Vec3::new(0.0, y_com as f32, 0.0),
        inertia: Mat3::from_diagonal(Vec3::new(across, (i_axis * rho_m) as f32, across)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32, rel: f32) -> bool {
        (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-12)
    }

    /// The capsule's textbook formulas: a cylinder of height 2h and two hemispheres.
    #[test]
    fn equal_radii_give_the_capsule_formulas() {
        use std::f32::consts::PI;
        for (h, r, density) in [(0.073, 0.106, 1000.0), (0.5, 0.1, 7.0), (0.0, 0.3, 1.0)] {
            let p = capsule(h, r, density);
            let (m_cyl, m_sph) = (
                density * PI * r * r * 2.0 * h,
                density * 4.0 / 3.0 * PI * r * r * r,
            );
            let i_yy = m_cyl * r * r / 2.0 + m_sph * 2.0 * r * r / 5.0;
            let i_xx = m_cyl * (r * r / 4.0 + h * h / 3.0)
                + m_sph * (2.0 * r * r / 5.0 + h * h + 0.75 * h * r);
            assert!(
                close(p.mass, m_cyl + m_sph, 1e-5),
                "{h} {r}: mass {} vs {}",
                p.mass,
                m_cyl + m_sph
            );
            assert!(p.com.length() < 1e-6 * (h + r));
            assert!(
                close(p.inertia.y_axis.y, i_yy, 1e-5),
                "{} vs {i_yy}",
                p.inertia.y_axis.y
            );
            assert!(
                close(p.inertia.x_axis.x, i_xx, 1e-5),
                "{} vs {i_xx}",
                p.inertia.x_axis.x
            );
            assert!(close(p.inertia.z_axis.z, i_xx, 1e-5));
        }
    }

    /// Brute force: the hull of the two spheres is the union of the balls whose centre and
    /// radius interpolate linearly between them, so a point is inside when the convex function
    /// `f(t) = |p - c(t)| - r(t)` reaches 0 or below on [0, 1]; its minimum is where
    /// `f'(t) = 0`, clamped to [0, 1]. A fine grid of cell midpoints sums volume, first and
    /// second moments.
    fn voxel(h: f64, a: f64, b: f64, n: usize) -> (f64, f64, f64, f64) {
        let s = (b - a) / (2.0 * h);
        let inside = |x: f64, y: f64, z: f64| {
            let rho = (x * x + z * z).sqrt();
            let u = s * rho / (1.0 - s * s).sqrt();
            let t = ((y - u + h) / (2.0 * h)).clamp(0.0, 1.0);
            let (cy, r) = (-h + 2.0 * h * t, b + (a - b) * t);
            (rho * rho + (y - cy) * (y - cy)).sqrt() <= r
        };
        let rmax = a.max(b);
        let (y0, y1) = (-h - b, h + a);
        let (dx, dy) = (2.0 * rmax / n as f64, (y1 - y0) / n as f64);
        let (mut v, mut my, mut iyy, mut ixx) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..n {
            let x = -rmax + (i as f64 + 0.5) * dx;
            for j in 0..n {
                let y = y0 + (j as f64 + 0.5) * dy;
                for k in 0..n {
                    let z = -rmax + (k as f64 + 0.5) * dx;
                    if inside(x, y, z) {
                        v += 1.0;
                        my += y;
                        iyy += x * x + z * z;
                        ixx += y * y + z * z;
                    }
                }
            }
        }
        let cell = dx * dx * dy;
        let ycom = my / v;
        (
            v * cell,
            ycom,
            iyy * cell,
            ixx * cell - v * cell * ycom * ycom,
        )
    }

    #[test]
    fn tapered_capsule_matches_a_voxel_integration() {
        // The rig's thigh and shin (half height, top, bottom radius), and a steep taper.
        for (h, a, b) in [
            (0.1468, 0.08, 0.06),
            (0.1616, 0.06, 0.04),
            (0.1, 0.02, 0.15),
        ] {
            let p = tapered_capsule(h as f32, a as f32, b as f32, 1.0);
            let (v, ycom, iyy, ixx) = voxel(h, a, b, 200);
            assert!(
                close(p.mass, v as f32, 0.001),
                "{h} {a} {b}: volume {} vs {v}",
                p.mass
            );
            assert!(
                (p.com.y - ycom as f32).abs() < 1e-4 * (h + a + b) as f32,
                "{} vs {ycom}",
                p.com.y
            );
            assert!(
                close(p.inertia.y_axis.y, iyy as f32, 0.001),
                "{} vs {iyy}",
                p.inertia.y_axis.y
            );
            assert!(
                close(p.inertia.x_axis.x, ixx as f32, 0.001),
                "{} vs {ixx}",
                p.inertia.x_axis.x
            );
            // The centre of mass lies toward the larger sphere.
            assert_eq!(p.com.y > 0.0, a > b);
        }
    }

    #[test]
    fn one_sphere_inside_the_other_is_the_larger_sphere() {
        let p = tapered_capsule(0.05, 0.3, 0.1, 2.0);
        let sphere = 2.0 * 4.0 / 3.0 * std::f32::consts::PI * 0.027;
        assert!(
            close(p.mass, sphere, 1e-5) && (p.com.y - 0.05).abs() < 1e-6,
            "{p:?}"
        );
        assert!(close(p.inertia.x_axis.x, 0.4 * sphere * 0.09, 1e-5));
    }

    #[test]
    fn two_half_boxes_sum_to_the_whole_box_and_rotation_permutes_the_axes() {
        let whole = solid_box(Vec3::new(2.0, 0.5, 0.25), 3.0);
        let half = solid_box(Vec3::new(1.0, 0.5, 0.25), 3.0);
        let left = half.transformed(Vec3::new(-1.0, 0.0, 0.0), Quat::IDENTITY);
        let right = half.transformed(Vec3::new(1.0, 0.0, 0.0), Quat::IDENTITY);
        let sum = MassProperties::sum(&[left, right]);
        assert!(close(sum.mass, whole.mass, 1e-6) && sum.com.length() < 1e-6);
        assert!(sum
            .inertia
            .abs_diff_eq(whole.inertia, 1e-4 * whole.inertia.x_axis.x));
        let turned = whole.transformed(
            Vec3::ONE,
            crate::math::quat_from_rotation_z(std::f32::consts::FRAC_PI_2),
        );
        let d = whole.inertia;
        let expected = Mat3::from_diagonal(Vec3::new(d.y_axis.y, d.x_axis.x, d.z_axis.z));
        assert!(
            turned.inertia.abs_diff_eq(expected, 1e-4) && turned.com.abs_diff_eq(Vec3::ONE, 1e-6)
        );
    }
}
