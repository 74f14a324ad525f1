//! The per-body steps of a substep: velocity integration (step 3.1), the preview pose (3.2)
//! and the commit (3.4), with the gyroscopic update of the angular velocity.

use super::body::SolverBody;
use super::Settings;
use crate::body::{Body, BodyKind};
use crate::math::{quat_from_rotation_vector, rotation_vector, skew, Mat3, Vec3};

/// Fixed-point passes of the gyroscopic update, at most.
pub const GYROSCOPIC_PASSES: u32 = 4;

/// Step 3.1: gravity, external force, the gyroscopic term, damping, and the angular speed
/// limit if any.
pub(super) fn integrate_velocity(body: &mut Body, settings: &Settings, h: f32) {
    if !body.is_awake_dynamic() {
        return;
    }
    body.linear_velocity += h * (settings.gravity + body.external_force * body.inverse_mass);
    // Substeps stop the fixed point once it has converged to rounding (one or two passes at
    // h = dt/4); one step a frame keeps its four passes, bit for bit the reference. The implicit
    // Newton step alone would cost a fifth as much but lets a free spinning brick lose 1.4% of
    // its angular momentum over 10 s at 4 substeps.
    let converged = if settings.substeps > 1 { 1e-6 } else { 0.0 };
    body.angular_velocity =
        gyroscopic_update(body, h, converged) / (1.0 + h * settings.angular_damping);
    body.linear_velocity /= 1.0 + h * settings.linear_damping;
    let spin = body.angular_velocity.length();
    if spin > settings.angular_speed_limit {
        body.angular_velocity *= settings.angular_speed_limit / spin;
    }
}

/// Step 3.2: the preview pose of a body as the hot solver body. Fixed bodies stay put.
#[inline(always)]
pub(super) fn predict_pose(body: &Body, h: f32) -> SolverBody {
    if body.asleep {
        // immovable until its island wakes
        return SolverBody {
            orientation: body.orientation,
            predicted: body.orientation,
            position: body.position,
            inverse_mass: 0.0,
            rotation_correction: Vec3::ZERO,
            inverse_inertia: Mat3::ZERO,
        };
    }
    let (position, orientation) = if body.kind == BodyKind::Fixed {
        (body.position, body.orientation)
    } else {
        (
            body.position + h * body.linear_velocity,
            (quat_from_rotation_vector(h * body.angular_velocity) * body.orientation).normalize(),
        )
    };
    SolverBody {
        orientation,
        predicted: orientation,
        position,
        inverse_mass: body.inverse_mass,
        rotation_correction: Vec3::ZERO,
        inverse_inertia: {
            let r = Mat3::from_quat(orientation);
            r * Mat3::from_diagonal(body.inverse_inertia_body) * r.transpose()
        },
    }
}

/// Step 3.4: velocities from the corrected preview, then the pose is committed.
#[inline(always)]
pub(super) fn commit_pose(body: &mut Body, hot: &SolverBody, h: f32) {
    if body.kind == BodyKind::Fixed || body.asleep {
        return;
    }
    if body.is_dynamic() {
        body.linear_velocity = (hot.position - body.position) / h;
        body.angular_velocity = rotation_vector(hot.orientation * body.orientation.inverse()) / h;
    }
    body.position = hot.position;
    body.orientation = hot.orientation;
    body.update_world_inertia();
}

/// Torque-free update of the angular velocity (the gyroscopic term of Euler's equations).
///
/// In body space `dL_b/dt = L_b x w_b`; over a step with constant `w_b` its exact solution turns
/// `L_b` by `exp(-dt w_b)`, while the orientation turns by `exp(dt w_b)`, so world `L = R L_b` is
/// unchanged when both use the same `w_b`. We solve that for the new velocity,
/// `w_b = I^-1 exp(-dt w_b) L_b`, by fixed-point iteration started from one implicit Newton step
/// (Catto, GDC 2015). At the fixed point a free body's angular momentum is conserved exactly
/// (see `tests/it/conservation.rs` for the tolerance measured). If the iteration does not contract
/// (a very fast spin of a very elongated body at a long time step), the Newton step is kept: it is
/// unconditionally stable and only slightly dissipative. The iteration stops early once a pass
/// changes `w` by less than `converged` times its length (0: always four passes), and keeps the
/// Newton step without passes where `(dt |w|)^2` is under `converged`.
pub fn gyroscopic_update(body: &Body, dt: f32, converged: f32) -> Vec3 {
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
    // Newton's error is of order (dt |w|)^2 relative: where that is under `converged`, the
    // first pass would change w by less than the threshold that stops the passes, so stop
    // before it (most bodies of a settled pile; a fast spin still runs its passes)
    if converged > 0.0 && dt * dt * w.length_squared() <= converged {
        return q * newton;
    }
    let inverse_inertia = body.inertia.recip();
    let mut current = newton;
    let mut last_change = f32::INFINITY;
    for _ in 0..GYROSCOPIC_PASSES {
        let next = inverse_inertia * (quat_from_rotation_vector(-dt * current) * momentum);
        let change = (next - current).length();
        if !(change < last_change) {
            return q * newton; // not contracting
        }
        current = next;
        last_change = change;
        if converged > 0.0 && change <= converged * current.length() {
            break;
        }
    }
    q * current
}
