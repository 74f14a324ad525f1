//! Reusable constraint parts (as in Jolt's `ConstraintPart/`): position-level corrections of
//! two bodies' preview poses that every constraint kind composes.
//!
//! A positional impulse `P` (kg m) applied to body i at world offset `r_i` moves its preview
//! pose by `dp = P / m`, `dtheta = I^-1 (r x P)`. An angular impulse `L` turns it by
//! `dtheta = I^-1 L`. Equal and opposite impulses on the pair conserve its linear and angular
//! momentum, which every part below respects.

use crate::math::{Mat3, Vec3};
pub use crate::solver_body::pair_mut;
use crate::solver_body::SolverBody as Body;

/// Scalar projection: removes `relaxation` times the distance `|d|` along `n = d / |d|`, where
/// `d = anchor_b - anchor_a`. One row of the point constraint; the cross-coupling of the three
/// rows through the bodies' rotation is ignored, so repeated application converges slowly.
#[inline(always)]
pub fn point_along_error(a: &mut Body, b: &mut Body, ra: Vec3, rb: Vec3, d: Vec3, relaxation: f32) {
    let distance = d.length();
    if distance < 1e-9 {
        return;
    }
    let n = d / distance;
    let w = a.positional_inverse_mass(ra, n) + b.positional_inverse_mass(rb, n);
    if w <= 0.0 {
        return;
    }
    let impulse = n * (relaxation * distance / w);
    a.apply_positional_impulse(impulse, ra);
    b.apply_positional_impulse(-impulse, rb);
}

/// Block solve: the impulse `P = K^-1 d` with the 3x3 inverse effective mass
/// `K = K_a + K_b`, `K_i = 1/m_i E - [r_i] I_i^-1 [r_i]`. Removes the linearised error in one go.
#[inline(always)]
pub fn point_block(a: &mut Body, b: &mut Body, ra: Vec3, rb: Vec3, d: Vec3, relaxation: f32) {
    if d.length_squared() < 1e-18 {
        return;
    }
    let k: Mat3 = a.point_inverse_mass_matrix(ra) + b.point_inverse_mass_matrix(rb);
    let det = k.determinant();
    if det.abs() < 1e-20 {
        return; // both bodies immovable
    }
    let impulse = k.inverse() * (relaxation * d);
    a.apply_positional_impulse(impulse, ra);
    b.apply_positional_impulse(-impulse, rb);
}

/// Turns b by the world rotation vector `rotation_b` relative to a (a turns the opposite way),
/// shared by the bodies' inertia about the rotation axis.
#[inline(always)]
pub fn relative_rotation(a: &mut Body, b: &mut Body, rotation_b: Vec3) {
    let angle = rotation_b.length();
    if angle < 1e-9 {
        return;
    }
    let n = rotation_b / angle;
    let w = a.angular_inverse_mass(n) + b.angular_inverse_mass(n);
    if w <= 0.0 {
        return;
    }
    let l = n * (angle / w);
    a.apply_angular_impulse(-l);
    b.apply_angular_impulse(l);
}

/// Turns b relative to a by the rotation vector `rotation_b`, which lies across the unit `axis`,
/// removing both of its components across `axis` at once: the 2x2 block `L = K^-1 e` with
/// `K_ij = u_i . (I_a^-1 + I_b^-1) u_j` over a basis `u, v` of the plane normal to `axis`. The
/// pair is left free to turn about `axis` by whatever the inertia couples in. One row along
/// `rotation_b` ([`relative_rotation`]) is exact only where the inertia is isotropic about it; a
/// limb's axial inverse inertia is about 60 times its transverse one, so that row mostly spins
/// the limb about its long axis, leaves a new error across the first, and the sweeps settle
/// into a turn back and forth every substep (`tests/it/hinge.rs`).
#[inline(always)]
pub fn relative_rotation_across(a: &mut Body, b: &mut Body, rotation_b: Vec3, axis: Vec3) {
    let u = crate::math::any_perpendicular(axis);
    let v = axis.cross(u);
    relative_rotation_block(a, b, (u, v), (rotation_b.dot(u), rotation_b.dot(v)));
}

/// Turns b relative to a by `e_u` about the unit `u` and `e_v` about the unit `v` (`u . v = 0`)
/// at once: the 2x2 block `L = K^-1 e`, `K_ij = u_i . (I_a^-1 + I_b^-1) u_j`. Shared by a hinge's
/// two rows ([`relative_rotation_across`]) and the rod's bend and twist
/// ([`super::rod::BendTwist::Block`]).
#[inline(always)]
pub fn relative_rotation_block(
    a: &mut Body,
    b: &mut Body,
    (u, v): (Vec3, Vec3),
    (eu, ev): (f32, f32),
) {
    if eu * eu + ev * ev < 1e-18 {
        return;
    }
    // immovable bodies (fixed, asleep) have a zero inverse inertia in the hot array
    let (wu, wv) = (
        a.inverse_inertia * u + b.inverse_inertia * u,
        a.inverse_inertia * v + b.inverse_inertia * v,
    );
    let (kuu, kuv, kvv) = (u.dot(wu), u.dot(wv), v.dot(wv));
    let det = kuu * kvv - kuv * kuv;
    if !(det > 1e-20) {
        return; // both immovable about u and v
    }
    let l = ((kvv * eu - kuv * ev) / det) * u + ((kuu * ev - kuv * eu) / det) * v;
    a.apply_angular_impulse(-l);
    b.apply_angular_impulse(l);
}
