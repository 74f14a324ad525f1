//! Small math helpers on top of `glam`: rigid transforms, the quaternion exponential map,
//! and swing-twist decomposition.

pub use glam::{Mat3, Quat, Vec3};

// Transcendental functions from one implementation, the `libm` crate (a Rust port of musl's,
// after Sun's fdlibm): the C library's differ between platforms and versions, and glibc picks
// a variant by the CPU it runs on, so results would depend on the machine. glam's rotations
// that take an angle call the C library's, so the quaternions made from angles are built
// here. Square roots are exact everywhere and need none of this.

/// `atan2(y, x)` (rad).
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    libm::atan2f(y, x)
}

/// Sine (rad).
#[inline]
pub fn sin(x: f32) -> f32 {
    libm::sinf(x)
}

/// Cosine (rad).
#[inline]
pub fn cos(x: f32) -> f32 {
    libm::cosf(x)
}

/// Tangent (rad).
#[inline]
pub fn tan(x: f32) -> f32 {
    libm::tanf(x)
}

/// `e^x`.
#[inline]
pub fn exp(x: f32) -> f32 {
    libm::expf(x)
}

/// `x^y`.
#[inline]
pub fn powf(x: f32, y: f32) -> f32 {
    libm::powf(x, y)
}

/// Arc cosine (rad).
#[inline]
pub fn acos(x: f32) -> f32 {
    libm::acosf(x)
}

/// The rotation by `angle` (rad) about the unit `axis` (glam's `Quat::from_axis_angle`).
pub fn quat_from_axis_angle(axis: Vec3, angle: f32) -> Quat {
    let (s, c) = libm::sincosf(0.5 * angle);
    let v = axis * s;
    Quat::from_xyzw(v.x, v.y, v.z, c)
}

/// The rotation by `angle` (rad) about x.
pub fn quat_from_rotation_x(angle: f32) -> Quat {
    quat_from_axis_angle(Vec3::X, angle)
}

/// The rotation by `angle` (rad) about y.
pub fn quat_from_rotation_y(angle: f32) -> Quat {
    quat_from_axis_angle(Vec3::Y, angle)
}

/// The rotation by `angle` (rad) about z.
pub fn quat_from_rotation_z(angle: f32) -> Quat {
    quat_from_axis_angle(Vec3::Z, angle)
}

/// The shortest rotation taking the unit `from` to the unit `to` (glam's
/// `Quat::from_rotation_arc`, whose half turn for opposite vectors is made here).
pub fn quat_from_rotation_arc(from: Vec3, to: Vec3) -> Quat {
    const ONE_MINUS_EPS: f32 = 1.0 - 2.0 * f32::EPSILON;
    let dot = from.dot(to);
    if dot > ONE_MINUS_EPS {
        Quat::IDENTITY
    } else if dot < -ONE_MINUS_EPS {
        quat_from_axis_angle(from.any_orthonormal_vector(), std::f32::consts::PI)
    } else {
        let c = from.cross(to);
        Quat::from_xyzw(c.x, c.y, c.z, 1.0 + dot).normalize()
    }
}

/// Spherical interpolation from `a` (at `s = 0`) to `b` (at 1) along the shorter arc (glam's
/// `Quat::slerp`, with the arc cosine and sines above).
pub fn quat_slerp(a: Quat, b: Quat, s: f32) -> Quat {
    let mut dot = a.dot(b);
    let b = if dot < 0.0 {
        dot = -dot;
        -b
    } else {
        b
    };
    if dot > 1.0 - f32::EPSILON {
        return a.lerp(b, s);
    }
    let theta = acos(dot);
    (a * sin(theta * (1.0 - s)) + b * sin(theta * s)) * (1.0 / sin(theta))
}

/// A rigid transform: rotation then translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iso {
    /// Translation (m), applied after the rotation.
    pub translation: Vec3,
    /// Rotation (unit quaternion).
    pub rotation: Quat,
}

impl Iso {
    /// The transform that changes nothing.
    pub const IDENTITY: Iso = Iso {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
    };

    /// A transform from its translation and rotation.
    pub fn new(translation: Vec3, rotation: Quat) -> Self {
        Self {
            translation,
            rotation,
        }
    }

    /// Maps point `p`: `R p + t`.
    pub fn transform_point(&self, p: Vec3) -> Vec3 {
        self.rotation * p + self.translation
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Iso {
        let rotation = self.rotation.inverse();
        Iso {
            translation: -(rotation * self.translation),
            rotation,
        }
    }
}

impl std::ops::Mul for Iso {
    type Output = Iso;
    fn mul(self, rhs: Iso) -> Iso {
        Iso {
            translation: self.transform_point(rhs.translation),
            rotation: (self.rotation * rhs.rotation).normalize(),
        }
    }
}

/// Quaternion of the rotation vector `v` (axis times angle, radians): the exponential map.
/// Exact for any angle, so integrating `q' = exp(dt w) q` and reading `w` back with
/// [`rotation_vector`] is lossless; a first-order update would shrink |w| every step.
pub fn quat_from_rotation_vector(v: Vec3) -> Quat {
    let angle = v.length();
    if angle < 1e-6 {
        // Taylor: sin(a/2)/a ~ 1/2 - a^2/48
        let s = 0.5 - angle * angle / 48.0;
        return Quat::from_xyzw(v.x * s, v.y * s, v.z * s, 1.0 - angle * angle / 8.0).normalize();
    }
    quat_from_axis_angle(v / angle, angle)
}

/// Rotation vector (axis times angle in [-pi, pi]) of `q`: the logarithm map, shortest arc.
pub fn rotation_vector(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    let xyz = Vec3::new(q.x, q.y, q.z);
    let s = xyz.length();
    if s < 1e-7 {
        return 2.0 * xyz; // angle ~ 2 s, axis xyz/s
    }
    let angle = 2.0 * atan2(s, q.w);
    xyz * (angle / s)
}

/// Rotates `q` by the small world-space rotation vector `theta` to first order, as
/// position-based solvers do: `q += 0.5 [theta, 0] q`, then renormalise.
#[inline(always)]
pub fn rotate_by_small(q: Quat, theta: Vec3) -> Quat {
    let dq = Quat::from_xyzw(theta.x, theta.y, theta.z, 0.0) * q;
    Quat::from_xyzw(
        q.x + 0.5 * dq.x,
        q.y + 0.5 * dq.y,
        q.z + 0.5 * dq.z,
        q.w + 0.5 * dq.w,
    )
    .normalize()
}

/// Signed twist angle of `q` about the unit local axis `axis` in the swing-twist
/// decomposition `q = swing * twist`, wrapped to [-pi, pi].
pub fn twist_angle(q: Quat, axis: Vec3) -> f32 {
    let projection = Vec3::new(q.x, q.y, q.z).dot(axis);
    let angle = 2.0 * atan2(projection, q.w);
    wrap_angle(angle)
}

/// Wraps an angle to [-pi, pi].
pub fn wrap_angle(a: f32) -> f32 {
    use std::f32::consts::{PI, TAU};
    let mut a = a % TAU;
    if a > PI {
        a -= TAU;
    } else if a < -PI {
        a += TAU;
    }
    a
}

/// Angle between two unit vectors, robust near 0 and pi (atan2 of |a x b| and a.b).
pub fn angle_between(a: Vec3, b: Vec3) -> f32 {
    atan2(a.cross(b).length(), a.dot(b))
}

/// A unit vector perpendicular to the unit vector `v`.
pub fn any_perpendicular(v: Vec3) -> Vec3 {
    v.any_orthonormal_vector()
}

/// Skew-symmetric cross-product matrix: `skew(a) * b = a x b`.
pub fn skew(a: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.0, a.z, -a.y),
        Vec3::new(-a.z, 0.0, a.x),
        Vec3::new(a.y, -a.x, 0.0),
    )
}

/// Parses a rotation given as a rotation vector in degrees.
pub fn quat_from_degrees(rotation_vector_deg: [f32; 3]) -> Quat {
    quat_from_rotation_vector(Vec3::from(rotation_vector_deg) * std::f32::consts::PI / 180.0)
}

/// Asserts that each listed `Vec3` field of `$record` is followed directly by the field named
/// after it (a float, or a vector or matrix starting with one), as the hot records lay them
/// out: glam loads a `Vec3` field with one 16-byte load, so the 4 bytes after it go through
/// the arithmetic in the unused SSE lane, and a flag or bit field there reads as a subnormal
/// float, which the processor handles on a slow path ([`crate::contact::handover::Handed`]).
#[cfg(test)]
macro_rules! assert_float_follows {
    ($record:ty: $($vector:ident => $next:ident),+ $(,)?) => {
        $(assert_eq!(
            std::mem::offset_of!($record, $vector) + std::mem::size_of::<$crate::math::Vec3>(),
            std::mem::offset_of!($record, $next),
            concat!(stringify!($vector), " must be followed by ", stringify!($next)),
        );)+
    };
}
#[cfg(test)]
pub(crate) use assert_float_follows;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_log_round_trip() {
        for v in [
            Vec3::new(0.3, -0.2, 1.1),
            Vec3::new(1e-8, 0.0, 2e-8),
            Vec3::new(0.0, 3.0, 0.0),
        ] {
            let back = rotation_vector(quat_from_rotation_vector(v));
            assert!((back - v).length() < 1e-5, "{v} -> {back}");
        }
    }

    #[test]
    fn twist_of_pure_twist() {
        let q = Quat::from_rotation_x(0.7);
        assert!((twist_angle(q, Vec3::X) - 0.7).abs() < 1e-6);
        let swing_then_twist = Quat::from_rotation_y(0.4) * Quat::from_rotation_x(-0.5);
        assert!((twist_angle(swing_then_twist, Vec3::X) + 0.5).abs() < 1e-5);
    }
}
