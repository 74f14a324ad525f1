//! Contact points W at a time: [`ContactPoint::solve`] on [`Lane`]s, branch-free (paper §7's
//! batching applied to contacts, as Box2D v3's `contact_solver.c` does with `b2FloatW`).
//!
//! The same two parts as the scalar solve, with its branches as masks:
//! 1. non-penetration: the accumulated impulse `total = max(P_n - C / w, 0)`, active where the
//!    point penetrates or has pushed this substep (`C < 0 or P_n > 0`) and `w > 0`;
//! 2. friction on the anchors' tangential slip, only where `P_n > 0`: the whole slip while the
//!    accumulated friction stays within `mu_s P_n` (sticking), else at most `mu_d P_n` in all
//!    (sliding, which clears the point's `sticking` flag).
//!
//! An inactive lane applies a zero impulse, which leaves its bodies as they were (the
//! orientation is rebuilt from the same predicted orientation and correction).

use super::ContactPoint;
use crate::lanes::{BodyLanes, Lane, V3};
use crate::solver_body::SharedBodies;

/// Solves `rows` (4 or 8 of one colour's points, sharing no movable body, as
/// [`crate::solver::SIMD_WIDTH`] gives them) in `wide::f32x4` or `wide::f32x8` lanes.
pub fn solve_batch(rows: &mut [ContactPoint], bodies: SharedBodies) {
    match rows.len() {
        8 => solve_lanes::<wide::f32x8>(rows, bodies),
        _ => solve_lanes::<wide::f32x4>(rows, bodies),
    }
}

/// Solves `L::W` points at once.
pub fn solve_lanes<L: Lane>(rows: &mut [ContactPoint], bodies: SharedBodies) {
    assert_eq!(rows.len(), L::W, "a batch is exactly one point per lane");
    let mut index_a = [0u32; crate::lanes::MAX_LANES];
    let mut index_b = [0u32; crate::lanes::MAX_LANES];
    for (i, p) in rows.iter().enumerate() {
        index_a[i] = p.body_a.0;
        index_b[i] = p.body_b.0;
    }
    let (index_a, index_b) = (&index_a[..L::W], &index_b[..L::W]);
    // SAFETY: the rows of a batch share no movable body (graph colouring).
    let (mut a, mut b) = unsafe {
        (
            BodyLanes::<L>::gather(bodies, index_a),
            BodyLanes::<L>::gather(bodies, index_b),
        )
    };
    let n = V3::<L>::from_fn(|i| rows[i].normal);
    let local_a = V3::<L>::from_fn(|i| rows[i].local_a);
    let local_b = V3::<L>::from_fn(|i| rows[i].local_b);
    let mut normal_impulse = L::from_fn(|i| rows[i].normal_impulse);
    let zero = L::zero();

    // 1. non-penetration: measured at the turned points, pushed at the fixed lever arms
    let point_a = a.position + a.orientation.rotate(local_a);
    let point_b = b.position + b.orientation.rotate(local_b);
    let allowed = L::from_fn(|i| rows[i].allowed_penetration);
    let separation = (point_b - point_a).dot(n) + allowed;
    let ra = V3::<L>::from_fn(|i| rows[i].arm_a);
    let rb = V3::<L>::from_fn(|i| rows[i].arm_b);
    let w = a.positional_inverse_mass(ra, n) + b.positional_inverse_mass(rb, n);
    let active = w.gt(zero) & (separation.lt(zero) | normal_impulse.gt(zero));
    // soft contacts as the scalar code; a batch of hard points (zero compliance and damping,
    // the paper's projection) skips the soft terms, which would add exact zeros
    let (error, denominator) = if rows.iter().any(|r| r.compliance != 0.0 || r.damping != 0.0) {
        let soft = L::from_fn(|i| rows[i].compliance) * w;
        let damping = L::from_fn(|i| rows[i].damping);
        let start = L::from_fn(|i| rows[i].start_separation);
        (
            separation + soft * normal_impulse + damping * (separation - start),
            (L::splat(1.0) + damping) * w + soft,
        )
    } else {
        (separation, w)
    };
    let total = (normal_impulse - error / denominator.max(L::splat(f32::MIN_POSITIVE))).max(zero);
    let total = active.select(total, normal_impulse);
    let lambda = total - normal_impulse;
    normal_impulse = total;
    a.apply_positional_impulse(n.scale(-lambda), ra);
    b.apply_positional_impulse(n.scale(lambda), rb);

    // 2. friction, where the point pushes
    let pushing = normal_impulse.gt(zero);
    let mut friction_impulse = L::from_fn(|i| rows[i].friction_impulse);
    let mut slid = zero;
    if pushing.any() {
        let anchor_a = V3::<L>::from_fn(|i| rows[i].anchor_a);
        let anchor_b = V3::<L>::from_fn(|i| rows[i].anchor_b);
        let static_friction = L::from_fn(|i| rows[i].static_friction);
        let dynamic_friction = L::from_fn(|i| rows[i].dynamic_friction);
        let slip = (b.position + b.orientation.rotate(anchor_b))
            - (a.position + a.orientation.rotate(anchor_a));
        let tangential = slip - n.scale(slip.dot(n));
        let length = tangential.length();
        let moving = length.gt(L::splat(1e-9));
        let t = tangential.scale(moving.select(L::splat(1.0) / length.max(L::splat(1e-9)), zero));
        let w = a.positional_inverse_mass(ra, t) + b.positional_inverse_mass(rb, t);
        let active = pushing & moving & w.gt(zero);
        let needed = length / w.max(L::splat(f32::MIN_POSITIVE));
        // `<=` as in the scalar code
        let limit = static_friction * normal_impulse;
        let within = (friction_impulse + needed).le(limit);
        let sliding = (dynamic_friction * normal_impulse - friction_impulse)
            .max(zero)
            .min(needed);
        let applied = active.select(within.select(needed, sliding), zero);
        slid = active & limit.lt(friction_impulse + needed);
        a.apply_positional_impulse(t.scale(applied), ra);
        b.apply_positional_impulse(t.scale(-applied), rb);
        friction_impulse = friction_impulse + applied.max(zero);
    }

    // SAFETY: as for the gather.
    unsafe {
        a.scatter(bodies, index_a);
        b.scatter(bodies, index_b);
    }
    for (i, p) in rows.iter_mut().enumerate() {
        p.normal_impulse = normal_impulse.lane(i);
        p.friction_impulse = friction_impulse.lane(i);
        if slid.lane(i).to_bits() != 0 {
            p.sticking = false;
        }
    }
}
