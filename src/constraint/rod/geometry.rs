//! The rod's geometry: the chord ratio of the length constraint (eq. 9), the curve constraint
//! (eq. 6) with its gradient, and points of the circular arc (eq. 7-8).

use crate::math::{angle_between, any_perpendicular, atan2, cos, sin, Vec3};

/// `2 sin(psi/2) / psi`, the chord of a unit-length arc bent by psi (eq. 9), with its series
/// `1 - psi^2/24 + psi^4/1920` near 0.
pub fn chord_ratio(psi: f32) -> f32 {
    if psi.abs() < 1e-2 {
        let p2 = psi * psi;
        1.0 - p2 / 24.0 + p2 * p2 / 1920.0
    } else {
        2.0 * sin(0.5 * psi) / psi
    }
}

/// `d/dpsi (2 sin(psi/2) / psi)`, with its series `-psi/12 + psi^3/480` near 0.
pub fn chord_ratio_derivative(psi: f32) -> f32 {
    if psi.abs() < 1e-2 {
        -psi / 12.0 + psi * psi * psi / 480.0
    } else {
        (psi * cos(0.5 * psi) - 2.0 * sin(0.5 * psi)) / (psi * psi)
    }
}

/// Unit offset axis o^; along the tangents when the centres coincide.
pub fn offset_axis(pa: Vec3, pb: Vec3, ta: Vec3) -> Vec3 {
    (pb - pa).try_normalize().unwrap_or(ta)
}

/// The vector form of eq. 6: `t_a + t_b - 2 (t_a . o^) o^`.
pub fn curve_vector(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> Vec3 {
    let o = offset_axis(pa, pb, ta);
    ta + tb - 2.0 * ta.dot(o) * o
}

/// Angle (rad) between t_b and the reflection `S t_a` of t_a about o^: the scalar form of eq. 6.
pub fn curve_error(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> f32 {
    curve_projection(pa, ta, pb, tb).0
}

/// eq. 9: `|p_b - p_a| - 2 l_0 sin(psi/2) / psi`.
pub fn length_error(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3, rest_length: f32) -> f32 {
    (pb - pa).length() - rest_length * chord_ratio(angle_between(ta, tb))
}

/// Gradient of [`curve_error`] with respect to positions and rotation vectors of both bodies.
#[derive(Clone, Copy, Debug)]
pub struct CurveGradient {
    /// `dC/dp_a = -g_o` (rad/m).
    pub p_a: Vec3,
    /// `dC/dtheta_a = S n`, with respect to body a's rotation vector.
    pub theta_a: Vec3,
    /// `dC/dp_b = g_o` (rad/m).
    pub p_b: Vec3,
    /// `dC/dtheta_b = -n`, with respect to body b's rotation vector.
    pub theta_b: Vec3,
}

/// The gradient of [`curve_error`] (eq. 6) alone; see [`curve_projection`].
pub fn curve_gradient(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> CurveGradient {
    curve_projection(pa, ta, pb, tb).1
}

/// [`curve_error`] and [`curve_gradient`] together, sharing the geometry (§7).
#[inline(always)]
pub fn curve_projection(pa: Vec3, ta: Vec3, pb: Vec3, tb: Vec3) -> (f32, CurveGradient) {
    let offset = pb - pa;
    let distance = offset.length();
    let o = if distance > 1e-12 {
        offset / distance
    } else {
        ta
    };
    let reflect = |v: Vec3| 2.0 * v.dot(o) * o - v;
    let r = reflect(ta);
    let cross = tb.cross(r);
    let sin = cross.length();
    let error = atan2(sin, tb.dot(r));
    let n = if sin > 1e-12 {
        cross / sin
    } else {
        any_perpendicular(tb)
    };
    let m = n.cross(r);
    let g_o = if distance > 1e-6 {
        let v = ta.dot(o) * m + m.dot(o) * ta;
        (2.0 / distance) * (v - v.dot(o) * o)
    } else {
        Vec3::ZERO
    };
    let gradient = CurveGradient {
        p_a: -g_o,
        theta_a: reflect(n),
        p_b: g_o,
        theta_b: -n,
    };
    (error, gradient)
}

/// A point of the arc from p_a with tangent t_a bent toward t_b, length `rest_length`, s in [0, 1].
pub fn arc_point(pa: Vec3, ta: Vec3, tb: Vec3, rest_length: f32, s: f32) -> Vec3 {
    let psi = angle_between(ta, tb);
    let k = (tb - ta.dot(tb) * ta)
        .try_normalize()
        .unwrap_or_else(|| any_perpendicular(ta));
    let (along, across) = if psi < 1e-3 {
        let ps = psi * s;
        (s * (1.0 - ps * ps / 6.0), s * ps * (0.5 - ps * ps / 24.0))
    } else {
        // 1 - cos x = 2 sin^2(x/2), without the cancellation of the left side in f32
        let half = sin(0.5 * psi * s);
        (sin(psi * s) / psi, 2.0 * half * half / psi)
    };
    pa + rest_length * (along * ta + across * k)
}
