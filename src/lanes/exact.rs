//! The scalar code's own arithmetic on lanes, to the bit, where the SIMD solver must compute a
//! per-substep constant exactly as the scalar reference does: glam's quaternion product in its
//! SSE2 operation order, and the twist through [`maths::atan2_libm`], which is the scalar code's
//! `atan2` ([`crate::math::atan2`]) to the bit. The joints' starting twist ([`start_twist`]),
//! computed lane by lane with the scalar calls, would take a tenth of the 1000-ragdoll rain's
//! integrate phase.

use super::{maths, not, Lane, Q};
use crate::math::wrap_angle;

/// glam's `Quat * Quat` (`mul_quat` of its SSE2 build) per lane: each component the sum of two
/// partial sums, as the 4-wide shuffles add them.
#[inline(always)]
pub fn quat_mul<L: Lane>(l: Q<L>, r: Q<L>) -> Q<L> {
    Q {
        x: (l.w * r.x + l.x * r.w) + (l.y * r.z - l.z * r.y),
        y: (l.w * r.y - l.x * r.z) + (l.y * r.w + l.z * r.x),
        z: (l.w * r.z + l.x * r.y) + (-(l.y * r.x) + l.z * r.w),
        w: (l.w * r.w - l.x * r.x) + (-(l.y * r.y) - l.z * r.z),
    }
}

/// [`crate::math::twist_angle`] about x of `frame_a^-1 frame_b` per lane, the joints' starting
/// twist ([`crate::constraint::AngularLimit::start_twist`]), to the bit.
#[inline(always)]
pub fn start_twist<L: Lane>(frame_a: Q<L>, frame_b: Q<L>) -> L {
    let q = quat_mul(frame_a.conjugate(), frame_b);
    // glam's `Vec3::dot` with the x axis, with its additions of signed zeros
    let projection = (q.x * L::splat(1.0) + q.y * L::splat(0.0)) + q.z * L::splat(0.0);
    let angle = L::splat(2.0) * maths::atan2_libm(projection, q.w);
    // `wrap_angle`: below a full turn its `a % TAU` is `a` itself; a full turn (or NaN) takes
    // the scalar function, whose remainder keeps the sign of a zero
    let (pi, tau) = (
        L::splat(std::f32::consts::PI),
        L::splat(std::f32::consts::TAU),
    );
    let wrapped = angle
        .gt(pi)
        .select(angle - tau, angle.lt(-pi).select(angle + tau, angle));
    let within = angle.abs().lt(tau);
    if !not(within).any() {
        return wrapped;
    }
    L::from_fn(|i| match within.at(i).to_bits() != 0 {
        true => wrapped.at(i),
        false => wrap_angle(angle.at(i)),
    })
}

#[cfg(test)]
mod tests {
    use super::super::maths::tests::{floats, same_bits, W};
    use super::*;
    use crate::constraint::AngularLimit;
    use crate::math::Quat;

    /// The starting twist in lanes is the scalar `AngularLimit::start_twist`, to the bit, for
    /// random unit frames (and frames a half turn apart, where the twist wraps).
    #[test]
    fn start_twist_is_the_scalar_ones_to_the_bit() {
        let mut f = floats(3, 1.0);
        let mut unit = || Quat::from_xyzw(f(), f(), f(), f()).normalize();
        for round in 0..20_000 {
            let a: [Quat; 16] = std::array::from_fn(|_| unit());
            let b: [Quat; 16] = std::array::from_fn(|i| match round % 3 {
                0 => unit(),
                1 => a[i] * Quat::from_rotation_x(std::f32::consts::PI + 1e-3 * i as f32),
                _ => a[i],
            });
            let lanes = start_twist(Q::<W>::from_fn(|i| a[i]), Q::<W>::from_fn(|i| b[i]));
            same_bits(
                lanes,
                |i| AngularLimit::start_twist(a[i], b[i]),
                "twist",
                |i| format!("{:?} {:?}", a[i], b[i]),
            );
        }
    }

    #[test]
    fn the_quaternion_product_is_glams_to_the_bit() {
        let mut f = floats(5, 2.0);
        for _ in 0..20_000 {
            let a: [Quat; 16] = std::array::from_fn(|_| Quat::from_xyzw(f(), f(), f(), f()));
            let b: [Quat; 16] = std::array::from_fn(|_| Quat::from_xyzw(f(), f(), f(), f()));
            let q = quat_mul(Q::<W>::from_fn(|i| a[i]), Q::<W>::from_fn(|i| b[i]));
            for i in 0..16 {
                let glam = a[i] * b[i];
                assert_eq!(
                    q.lane(i).to_array().map(f32::to_bits),
                    glam.to_array().map(f32::to_bits),
                    "lane {i}"
                );
            }
        }
    }
}
