//! The step: an impulse-based solver from preview coordinates with a fixed number of
//! iterations (paper §4, after Bender and Schmitt 2006), written in position-level form.
//!
//! Bender and Schmitt apply impulses to velocities so that the preview pose `x* = x + dt v`
//! satisfies each constraint. A velocity change `dv` moves the preview by `dt dv`, so applying
//! the correction to `x*` directly and deriving `v = (x* - x) / dt` at the end is the same
//! method with less bookkeeping (as in position-based dynamics). Soft constraints remove a
//! fraction alpha in [0, 1] of their error per iteration; hard constraints use alpha = 1.
//!
//! Step order, one frame of `dt`:
//! 1. apply gravity and external forces to the linear velocities; update angular velocities
//!    with the gyroscopic term (implicit, see [`gyroscopic_update`]); apply damping, if any;
//! 2. find the contact points at the current poses (speculative, when contacts are on); predict
//!    the preview poses `p* = p + dt v`, `q* = exp(dt w) q` (exact exponential map), and refresh
//!    each body's world inverse inertia at the preview orientation;
//! 3. `iterations` times: solve every constraint once in its stored order (joints, rods and
//!    targets as the builders appended them), then every contact point;
//! 4. derive the velocities `v = (p* - p) / dt`, `w = log(q* q^-1) / dt` and commit the poses;
//!    then the contacts' velocity pass: each contact that pushed leaves with zero relative
//!    normal velocity, or bounces (restitution);
//! 5. check every body for NaN and for speeds above the explosion bounds, then the caller
//!    measures residuals on the final poses (paper Fig. 8).
//!
//! Nothing here allocates: the step touches only the world's existing vectors.

use crate::body::{Body, BodyKind};
use crate::math::{quat_from_rotation_vector, rotation_vector, skew, Mat3, Vec3};
use crate::world::{SimulationError, World};

/// Advances `world` by one frame.
pub fn step(world: &mut World) -> Result<(), SimulationError> {
    let dt = world.settings.dt;
    let gravity = world.settings.gravity;
    let (linear_damping, angular_damping) = (
        world.settings.linear_damping,
        world.settings.angular_damping,
    );
    // 1. external forces and gravity
    for body in world.bodies.iter_mut().filter(|b| b.is_dynamic()) {
        body.linear_velocity += dt * (gravity + body.external_force * body.inverse_mass);
        body.angular_velocity = gyroscopic_update(body, dt) / (1.0 + dt * angular_damping);
        body.linear_velocity /= 1.0 + dt * linear_damping;
    }
    // 2. contacts at the current poses, then preview poses
    if world.settings.contacts {
        let margin = world.settings.contact_margin;
        world
            .contacts
            .detect(&world.bodies, &world.constraints, dt, margin);
    }
    for body in world
        .bodies
        .iter_mut()
        .filter(|b| b.kind != BodyKind::Fixed)
    {
        body.preview_position = body.position + dt * body.linear_velocity;
        let predicted =
            (quat_from_rotation_vector(dt * body.angular_velocity) * body.orientation).normalize();
        body.set_predicted_orientation(predicted);
        body.update_world_inertia();
    }
    // 3. fixed iterations over all constraints
    for _ in 0..world.settings.iterations {
        for constraint in &world.constraints {
            constraint.solve(&mut world.bodies);
        }
        world.contacts.solve(&mut world.bodies);
    }
    // 4. velocities from the corrected previews
    for body in world.bodies.iter_mut().filter(|b| b.is_dynamic()) {
        body.linear_velocity = (body.preview_position - body.position) / dt;
        body.angular_velocity =
            rotation_vector(body.preview_orientation * body.orientation.inverse()) / dt;
    }
    for body in world
        .bodies
        .iter_mut()
        .filter(|b| b.kind != BodyKind::Fixed)
    {
        body.position = body.preview_position;
        body.orientation = body.preview_orientation;
        body.update_world_inertia();
    }
    if world.settings.contacts {
        // bounces slower than two steps of free fall stay inelastic
        let threshold = 2.0 * gravity.length() * dt;
        world.contacts.velocity_pass(&mut world.bodies, threshold);
    }
    world.frame += 1;
    world.time += dt as f64;
    // 5. failure check (the residual measures live in `metrics`)
    world.check_health()
}

/// Torque-free update of the angular velocity (the gyroscopic term of Euler's equations).
///
/// In body space `dL_b/dt = L_b x w_b`; over a step with constant `w_b` its exact solution turns
/// `L_b` by `exp(-dt w_b)`, while the orientation turns by `exp(dt w_b)`, so world `L = R L_b` is
/// unchanged when both use the same `w_b`. We solve that for the new velocity,
/// `w_b = I^-1 exp(-dt w_b) L_b`, by fixed-point iteration started from one implicit Newton step
/// (Catto, GDC 2015). At the fixed point a free body's angular momentum is conserved exactly
/// (see `tests/conservation.rs` for the tolerance measured). If the iteration does not contract
/// (a very fast spin of a very elongated body at a long time step), the Newton step is kept: it is
/// unconditionally stable and only slightly dissipative.
pub fn gyroscopic_update(body: &Body, dt: f32) -> Vec3 {
    let q = body.orientation;
    let w = q.inverse() * body.angular_velocity;
    let inertia = Mat3::from_diagonal(body.inertia);
    let momentum = inertia * w;
    let f = dt * w.cross(momentum);
    let jacobian = inertia + dt * (skew(w) * inertia - skew(momentum));
    if jacobian.determinant().abs() < 1e-20 {
        return body.angular_velocity;
    }
    let newton = w - jacobian.inverse() * f;
    let inverse_inertia = body.inertia.recip();
    let mut current = newton;
    let mut last_change = f32::INFINITY;
    for _ in 0..4 {
        let next = inverse_inertia * (quat_from_rotation_vector(-dt * current) * momentum);
        let change = (next - current).length();
        if !(change < last_change) {
            return q * newton; // not contracting
        }
        current = next;
        last_change = change;
    }
    q * current
}
