//! The lane maths: [`V3`], [`Q`] and [`SymM3`], glam's `Vec3`, `Quat` and a symmetric 3x3
//! matrix with one lane per constraint, each operation mirroring the scalar one.

use super::{Lane, MAX_LANES};
use crate::math::{Quat, Vec3};
use std::ops::{Add, Neg, Sub};

/// `Vec3` with one lane per constraint.
#[derive(Clone, Copy, Debug)]
pub struct V3<L> {
    /// x components, one per lane.
    pub x: L,
    /// y components, one per lane.
    pub y: L,
    /// z components, one per lane.
    pub z: L,
}

impl<L: Lane> V3<L> {
    /// The zero vector in every lane.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::splat(Vec3::ZERO)
    }
    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        V3 {
            x: L::splat(v.x),
            y: L::splat(v.y),
            z: L::splat(v.z),
        }
    }
    /// Lane `i` from `f(i)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> Vec3) -> Self {
        let mut v = [Vec3::ZERO; MAX_LANES];
        for (i, x) in v.iter_mut().take(L::W).enumerate() {
            *x = f(i);
        }
        V3 {
            x: L::from_fn(|i| v[i].x),
            y: L::from_fn(|i| v[i].y),
            z: L::from_fn(|i| v[i].z),
        }
    }
    /// Lane `i` as a `Vec3`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> Vec3 {
        Vec3::new(self.x.at(i), self.y.at(i), self.z.at(i))
    }
    /// Per-lane dot product.
    #[inline(always)]
    pub fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Per-lane cross product `self x o`.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        V3 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }
    /// Per-lane squared length.
    #[inline(always)]
    pub fn length_squared(self) -> L {
        self.dot(self)
    }
    /// Per-lane length.
    #[inline(always)]
    pub fn length(self) -> L {
        self.dot(self).sqrt()
    }
    /// Each lane scaled by its lane of `s`.
    #[inline(always)]
    pub fn scale(self, s: L) -> Self {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    /// Per lane: `self / |self|`, or `fallback` where `|self|` is not above `eps`; with the
    /// length. (The fallback is computed for every lane: skipping it when no lane needs it adds
    /// a branch that cost the rod kernel about 20%.)
    #[inline(always)]
    pub fn normalize_or(self, fallback: Self, eps: f32) -> (Self, L) {
        let length = self.length();
        let ok = length.gt(L::splat(eps));
        let unit = self.scale(L::splat(1.0) / length.max(L::splat(eps)));
        (V3::select(ok, unit, fallback), length)
    }
    /// Per lane: `t` where `mask` is set, else `f`.
    #[inline(always)]
    pub fn select(mask: L, t: Self, f: Self) -> Self {
        V3 {
            x: mask.select(t.x, f.x),
            y: mask.select(t.y, f.y),
            z: mask.select(t.z, f.z),
        }
    }
    /// A unit vector perpendicular to each lane's unit `self`: glam's `any_orthonormal_vector`
    /// (Duff et al. 2017) branch-free, with its `signum`, so `-0.0` counts as negative and the
    /// lanes pick the scalar code's vector.
    #[inline(always)]
    pub fn any_orthonormal(self) -> Self {
        let sign = (self.z & L::splat(-0.0)) | L::splat(1.0);
        let a = -L::splat(1.0) / (sign + self.z);
        let b = self.x * self.y * a;
        V3 {
            x: b,
            y: sign + self.y * self.y * a,
            z: -self.y,
        }
    }
}

impl<L: Lane> Add for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl<L: Lane> Sub for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl<L: Lane> Neg for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

/// `Quat` with one lane per constraint.
#[derive(Clone, Copy, Debug)]
pub struct Q<L> {
    /// x components, one per lane.
    pub x: L,
    /// y components, one per lane.
    pub y: L,
    /// z components, one per lane.
    pub z: L,
    /// w (scalar) components, one per lane.
    pub w: L,
}

impl<L: Lane> Q<L> {
    /// Per lane: `t` where `mask` is set, else `f`.
    #[inline(always)]
    pub fn select(mask: L, t: Self, f: Self) -> Self {
        Q {
            x: mask.select(t.x, f.x),
            y: mask.select(t.y, f.y),
            z: mask.select(t.z, f.z),
            w: mask.select(t.w, f.w),
        }
    }
    /// Lane `i` from `f(i)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> Quat) -> Self {
        let mut v = [Quat::IDENTITY; MAX_LANES];
        for (i, x) in v.iter_mut().take(L::W).enumerate() {
            *x = f(i);
        }
        Q {
            x: L::from_fn(|i| v[i].x),
            y: L::from_fn(|i| v[i].y),
            z: L::from_fn(|i| v[i].z),
            w: L::from_fn(|i| v[i].w),
        }
    }
    /// Lane `i` as a `Quat`.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> Quat {
        Quat::from_xyzw(self.x.at(i), self.y.at(i), self.z.at(i), self.w.at(i))
    }
    /// The vector part (x, y, z).
    #[inline(always)]
    pub fn xyz(self) -> V3<L> {
        V3 {
            x: self.x,
            y: self.y,
            z: self.z,
        }
    }
    /// The conjugate, the inverse of a unit quaternion.
    #[inline(always)]
    pub fn conjugate(self) -> Self {
        Q {
            x: -self.x,
            y: -self.y,
            z: -self.z,
            w: self.w,
        }
    }
    /// Hamilton product `self * o`.
    #[inline(always)]
    #[allow(clippy::should_implement_trait)]
    pub fn mul(self, o: Self) -> Self {
        Q {
            x: self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            y: self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            z: self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
            w: self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
        }
    }
    /// `self * v * self^-1` for a unit quaternion: `v + 2 w (u x v) + 2 u x (u x v)`.
    #[inline(always)]
    pub fn rotate(self, v: V3<L>) -> V3<L> {
        let u = self.xyz();
        let t = u.cross(v);
        let t = t + t;
        v + t.scale(self.w) + u.cross(t)
    }
    /// The image of the x axis, `self * (1, 0, 0)` (the joint and rod frames' first axis).
    #[inline(always)]
    pub fn x_axis(self) -> V3<L> {
        let two = L::splat(2.0);
        V3 {
            x: L::splat(1.0) - two * (self.y * self.y + self.z * self.z),
            y: two * (self.x * self.y + self.w * self.z),
            z: two * (self.x * self.z - self.w * self.y),
        }
    }
    /// Renormalised to unit length: one square root and one division, exact on every target
    /// (a hardware reciprocal estimate differs between SSE, AVX and AVX-512).
    #[inline(always)]
    pub fn normalize(self) -> Self {
        let inv = L::splat(1.0)
            / (self.x * self.x + self.y * self.y + self.z * self.z + self.w * self.w).sqrt();
        Q {
            x: self.x * inv,
            y: self.y * inv,
            z: self.z * inv,
            w: self.w * inv,
        }
    }
    /// `q` on the hemisphere `w >= 0` (same rotation).
    #[inline(always)]
    pub fn positive_w(self) -> Self {
        let flip = self.w.lt(L::zero()).select(L::splat(-1.0), L::splat(1.0));
        Q {
            x: self.x * flip,
            y: self.y * flip,
            z: self.z * flip,
            w: self.w * flip,
        }
    }
    /// The logarithm map (rotation vector, angle in [-pi, pi]) of a unit quaternion, as
    /// [`crate::math::rotation_vector`].
    #[inline(always)]
    pub fn rotation_vector(self) -> V3<L> {
        let q = self.positive_w();
        let s = q.xyz().length();
        let small = s.lt(L::splat(1e-7));
        let angle = L::splat(2.0) * s.atan2(q.w);
        let factor = small.select(L::splat(2.0), angle / s.max(L::splat(1e-7)));
        q.xyz().scale(factor)
    }
    /// [`crate::math::rotate_by_small`]: `q + 0.5 [theta, 0] q`, renormalised.
    #[inline(always)]
    pub fn rotate_by_small(self, theta: V3<L>) -> Self {
        let half = L::splat(0.5);
        let dq = Q {
            x: theta.x,
            y: theta.y,
            z: theta.z,
            w: L::zero(),
        }
        .mul(self);
        Q {
            x: self.x + half * dq.x,
            y: self.y + half * dq.y,
            z: self.z + half * dq.z,
            w: self.w + half * dq.w,
        }
        .normalize()
    }
}

/// A symmetric 3x3 matrix (world inverse inertia), one lane per constraint.
#[derive(Clone, Copy, Debug)]
pub struct SymM3<L> {
    /// Entry (0, 0), one per lane.
    pub xx: L,
    /// Entry (1, 1), one per lane.
    pub yy: L,
    /// Entry (2, 2), one per lane.
    pub zz: L,
    /// Entry (0, 1) = (1, 0), one per lane.
    pub xy: L,
    /// Entry (0, 2) = (2, 0), one per lane.
    pub xz: L,
    /// Entry (1, 2) = (2, 1), one per lane.
    pub yz: L,
}

impl<L: Lane> SymM3<L> {
    /// Per-lane product `self * v`.
    #[inline(always)]
    pub fn mul_vec(&self, v: V3<L>) -> V3<L> {
        V3 {
            x: self.xx * v.x + self.xy * v.y + self.xz * v.z,
            y: self.xy * v.x + self.yy * v.y + self.yz * v.z,
            z: self.xz * v.x + self.yz * v.y + self.zz * v.z,
        }
    }
}
