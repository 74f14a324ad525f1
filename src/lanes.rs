//! W-wide lanes for the batched solve (paper §7: "branch-free SIMD code, solving four
//! constraints at once"; Box2D v3's `b2FloatW`, Rapier's SIMD joint groups).
//!
//! [`Lane`] is a float vector of `W` lanes (`wide::f32x4` or `wide::f32x8`); [`V3`], [`Q`] and
//! [`SymM3`] are glam's `Vec3`, `Quat` and a symmetric 3x3 matrix with one lane per
//! constraint. Branches become masks: compute both sides, [`Lane::select`] per lane.
//! [`BodyLanes`] holds W solver bodies gathered from [`crate::solver_body::SolverBody`]s by index and is scattered
//! back after the batch; the body methods mirror the scalar ones on [`crate::solver_body::SolverBody`].

use crate::math::{Quat, Vec3};
use crate::solver_body::SharedBodies;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};

/// The widest lane type's width (`wide::f32x16`); arrays of per-lane data are this long.
pub const MAX_LANES: usize = 16;

/// The solver's lane type, chosen by measurement (`benches/solver.rs`): `f32x16` where the build
/// has AVX-512, `f32x8` where it has AVX, else `f32x4`. The kernels are bound by their chains of
/// dependent operations more than by their instruction count, so more independent lanes in
/// flight pay: from packed lanes, 16 lanes solve a rod in 0.64 of the time 8 lanes take on the
/// development machine (AMD EPYC, AVX-512). Without AVX an `f32x8` is two 4-wide halves and
/// measured no faster than 4 lanes.
#[cfg(target_feature = "avx512f")]
pub type Wide = wide::f32x16;
/// The solver's lane type on a build with AVX but not AVX-512 (see the AVX-512 case above).
#[cfg(all(target_feature = "avx", not(target_feature = "avx512f")))]
pub type Wide = wide::f32x8;
/// The solver's lane type on a build without AVX (see the AVX-512 case above).
#[cfg(not(target_feature = "avx"))]
pub type Wide = wide::f32x4;

/// Row `i` of a batch of one to `W` rows: lanes past the last row repeat the first. A repeated
/// lane computes exactly what the first lane computes (same row, same bodies), so writing its
/// bodies back twice writes the same values; a colour's last, partial batch is then solved in
/// lanes too, instead of row by row.
#[inline(always)]
pub fn padded<T>(rows: &[T], i: usize) -> &T {
    &rows[if i < rows.len() { i } else { 0 }]
}

/// The two body indices of each of `L::W` lanes' rows (padded as [`padded`]).
#[inline(always)]
pub fn body_indices<L: Lane, T>(
    rows: &[T],
    bodies_of: impl Fn(&T) -> (u32, u32),
) -> ([u32; MAX_LANES], [u32; MAX_LANES]) {
    let (mut a, mut b) = ([0u32; MAX_LANES], [0u32; MAX_LANES]);
    for i in 0..L::W {
        (a[i], b[i]) = bodies_of(padded(rows, i));
        debug_assert_ne!(a[i], b[i], "a constraint needs two distinct bodies");
    }
    (a, b)
}

/// Groups of four floats of `W` records turned into four lanes, and back: the transpose that
/// gathers bodies into lanes (one SSE shuffle network for W = 4).
pub trait Transpose4: Sized {
    /// `out[j]` lane i = `rows[i][j]`, for the first `W` rows.
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4];
    /// `rows[i][j]` = lane i of `cols[j]`.
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES];
}

impl Transpose4 for wide::f32x4 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        wide::f32x4::transpose([
            wide::f32x4::new(*rows[0]),
            wide::f32x4::new(*rows[1]),
            wide::f32x4::new(*rows[2]),
            wide::f32x4::new(*rows[3]),
        ])
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        let t = wide::f32x4::transpose(cols);
        let mut out = [[0.0; 4]; MAX_LANES];
        for (o, v) in out.iter_mut().zip(t) {
            *o = v.to_array();
        }
        out
    }
}

impl Transpose4 for wide::f32x8 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        let low: [wide::f32x4; 4] = Transpose4::transpose4(rows);
        let high: [wide::f32x4; 4] =
            Transpose4::transpose4(std::array::from_fn(|i| rows[(i + 4) % MAX_LANES]));
        std::array::from_fn(|j| {
            let (l, h) = (low[j].to_array(), high[j].to_array());
            wide::f32x8::new([l[0], l[1], l[2], l[3], h[0], h[1], h[2], h[3]])
        })
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        // each half of the eight lanes through the 4-wide shuffle network
        let cols = cols.map(|c| c.to_array());
        let half = |h: usize| -> [wide::f32x4; 4] {
            std::array::from_fn(|j| {
                let c = &cols[j];
                wide::f32x4::new([c[4 * h], c[4 * h + 1], c[4 * h + 2], c[4 * h + 3]])
            })
        };
        let (low, high) = (
            <wide::f32x4 as Transpose4>::untranspose4(half(0)),
            <wide::f32x4 as Transpose4>::untranspose4(half(1)),
        );
        std::array::from_fn(|i| if i < 4 { low[i] } else { high[i - 4] })
    }
}

/// A float vector of `W` lanes. Comparisons return masks (all bits set per true lane).
pub trait Lane:
    Transpose4
    + Copy
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
{
    /// Number of lanes.
    const W: usize;
    /// All lanes set to `x`.
    fn splat(x: f32) -> Self;
    /// Lane `i` from `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// Lane `i`'s value.
    fn lane(self, i: usize) -> f32;
    /// Per-lane square root.
    fn sqrt(self) -> Self;
    /// `1 / sqrt(self)` from the hardware estimate (12 bits) and one Newton step (about 22).
    fn recip_sqrt_newton(self) -> Self;
    /// Per-lane absolute value.
    fn abs(self) -> Self;
    /// Per-lane maximum.
    fn max(self, o: Self) -> Self;
    /// Per-lane minimum.
    fn min(self, o: Self) -> Self;
    /// Mask of the lanes where `self < o`.
    fn lt(self, o: Self) -> Self;
    /// Mask of the lanes where `self > o`.
    fn gt(self, o: Self) -> Self;
    /// Mask of the lanes where `self <= o`.
    fn le(self, o: Self) -> Self;
    /// Per lane: `t` where the mask `self` is set, else `f`.
    fn select(self, t: Self, f: Self) -> Self;
    /// Per-lane `atan2(self, x)` (rad), `self` being y.
    fn atan2(self, x: Self) -> Self;
    /// Per-lane sine and cosine of `self` (rad).
    fn sin_cos(self) -> (Self, Self);
    /// Whether any lane of the mask is set.
    fn any(self) -> bool;

    /// All lanes zero.
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
}

macro_rules! impl_lane {
    ($t:ty, $w:expr) => {
        impl Lane for $t {
            const W: usize = $w;
            #[inline(always)]
            fn splat(x: f32) -> Self {
                <$t>::splat(x)
            }
            #[inline(always)]
            fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
                let mut a = [0.0f32; $w];
                for (i, x) in a.iter_mut().enumerate() {
                    *x = f(i);
                }
                <$t>::new(a)
            }
            #[inline(always)]
            fn lane(self, i: usize) -> f32 {
                self.to_array()[i]
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn recip_sqrt_newton(self) -> Self {
                let y = <$t>::recip_sqrt(self);
                y * (<$t>::splat(1.5) - <$t>::splat(0.5) * self * y * y)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn max(self, o: Self) -> Self {
                <$t>::max(self, o)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                <$t>::min(self, o)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> Self {
                self.simd_lt(o)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> Self {
                self.simd_gt(o)
            }
            #[inline(always)]
            fn le(self, o: Self) -> Self {
                self.simd_le(o)
            }
            #[inline(always)]
            fn select(self, t: Self, f: Self) -> Self {
                <$t>::select(self, t, f)
            }
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                <$t>::atan2(self, x)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                <$t>::sin_cos(self)
            }
            #[inline(always)]
            fn any(self) -> bool {
                <$t>::any(self)
            }
        }
    };
}

impl_lane!(wide::f32x4, 4);
impl_lane!(wide::f32x8, 8);
impl_lane!(wide::f32x16, 16);

impl Transpose4 for wide::f32x16 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        let part = |k: usize| -> [wide::f32x4; 4] {
            Transpose4::transpose4(std::array::from_fn(|i| rows[(i + 4 * k) % MAX_LANES]))
        };
        let parts = [part(0), part(1), part(2), part(3)];
        std::array::from_fn(|j| {
            let mut a = [0.0f32; 16];
            for k in 0..4 {
                a[4 * k..4 * k + 4].copy_from_slice(&parts[k][j].to_array());
            }
            wide::f32x16::new(a)
        })
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        let cols = cols.map(|c| c.to_array());
        let mut out = [[0.0; 4]; MAX_LANES];
        for k in 0..4 {
            let quarter: [wide::f32x4; 4] = std::array::from_fn(|j| {
                let c = &cols[j];
                wide::f32x4::new([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
            });
            let t = <wide::f32x4 as Transpose4>::untranspose4(quarter);
            out[4 * k..4 * k + 4].copy_from_slice(&t[..4]);
        }
        out
    }
}

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
        Vec3::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
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
        Quat::from_xyzw(
            self.x.lane(i),
            self.y.lane(i),
            self.z.lane(i),
            self.w.lane(i),
        )
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
    /// Renormalised to unit length by a Newton-refined inverse square root (for near-unit inputs).
    #[inline(always)]
    pub fn normalize(self) -> Self {
        // the quaternions renormalised here are within a small turn of unit length, so the
        // Newton-refined estimate is as good as a square root and a division, and cheaper
        let inv = (self.x * self.x + self.y * self.y + self.z * self.z + self.w * self.w)
            .recip_sqrt_newton();
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

/// W solver bodies, one per lane, gathered by index.
#[derive(Clone, Copy, Debug)]
pub struct BodyLanes<L> {
    /// Preview position p* (m).
    pub position: V3<L>,
    /// Preview orientation q*.
    pub orientation: Q<L>,
    /// Orientation predicted at the substep's start, before any correction.
    pub predicted: Q<L>,
    /// Sum of the rotation vectors applied this substep (rad); `orientation` is `predicted` turned
    /// by it.
    pub rotation_correction: V3<L>,
    /// Inverse mass (1/kg); zero for immovable bodies.
    pub inverse_mass: L,
    /// World inverse inertia (1/(kg m^2)).
    pub inverse_inertia: SymM3<L>,
}

impl<L: Lane> BodyLanes<L> {
    /// Gathers body `index[i]` into lane i.
    ///
    /// # Safety
    /// No other thread may be writing those bodies (see [`SharedBodies`]).
    #[inline(always)]
    pub unsafe fn gather(bodies: SharedBodies, index: &[u32]) -> Self {
        // straight from the bodies' memory: no copies, one load per group of four floats
        // only the first W entries are read: the rest repeat body 0 without another lookup
        let first = bodies.quads(index[0]);
        let quads: [&[[f32; 4]; 6]; MAX_LANES] = std::array::from_fn(|i| {
            if i < L::W {
                bodies.quads(index[i])
            } else {
                first
            }
        });
        // group k of every body, transposed: four fields in lanes
        let group = |k: usize| L::transpose4(std::array::from_fn(|i| &quads[i][k]));
        let [qx, qy, qz, qw] = group(0);
        let [px, py, pz, pw] = group(1);
        let [x, y, z, inverse_mass] = group(2);
        let [cx, cy, cz, xx] = group(3);
        // column-major Mat3 of a symmetric matrix: (x_axis.y, x_axis.z, y_axis.x, y_axis.y)
        let [xy, xz, _, yy] = group(4);
        // (y_axis.z, z_axis.x, z_axis.y, z_axis.z)
        let [yz, _, _, zz] = group(5);
        BodyLanes {
            position: V3 { x, y, z },
            orientation: Q {
                x: qx,
                y: qy,
                z: qz,
                w: qw,
            },
            predicted: Q {
                x: px,
                y: py,
                z: pz,
                w: pw,
            },
            rotation_correction: V3 {
                x: cx,
                y: cy,
                z: cz,
            },
            inverse_mass,
            inverse_inertia: SymM3 {
                xx,
                yy,
                zz,
                xy,
                xz,
                yz,
            },
        }
    }

    /// Writes the moving parts (pose and correction) back to body `index[i]`, skipping
    /// immovable bodies: static bodies may repeat an index across lanes, and never change.
    ///
    /// # Safety
    /// The movable bodies among `index` must be this batch's alone (see [`SharedBodies`]).
    #[inline(always)]
    pub unsafe fn scatter(&self, bodies: SharedBodies, index: &[u32]) {
        let o = self.orientation;
        let orientation = L::untranspose4([o.x, o.y, o.z, o.w]);
        let p = self.position;
        let position = L::untranspose4([p.x, p.y, p.z, self.inverse_mass]);
        let c = self.rotation_correction;
        let correction = L::untranspose4([c.x, c.y, c.z, self.inverse_inertia.xx]);
        for (i, &k) in index.iter().enumerate().take(L::W) {
            // the gathered inverse mass, not a reload: immovable lanes are skipped
            if self.inverse_mass.lane(i) == 0.0 {
                continue;
            }
            let quads = bodies.get_mut(k).as_quads_mut();
            quads[0] = orientation[i];
            // the 4th floats are the body's own inverse mass and inertia entry, unchanged
            quads[2] = position[i];
            quads[3] = correction[i];
        }
    }

    #[inline(always)]
    fn rotate_preview(&mut self, dtheta: V3<L>) {
        self.rotation_correction = self.rotation_correction + dtheta;
        self.orientation = self.predicted.rotate_by_small(self.rotation_correction);
    }

    /// `SolverBody::apply_positional_impulse` per lane.
    #[inline(always)]
    pub fn apply_positional_impulse(&mut self, impulse: V3<L>, r: V3<L>) {
        self.position = self.position + impulse.scale(self.inverse_mass);
        let dtheta = self.inverse_inertia.mul_vec(r.cross(impulse));
        self.rotate_preview(dtheta);
    }

    /// `SolverBody::apply_linear_impulse` per lane.
    #[inline(always)]
    pub fn apply_linear_impulse(&mut self, impulse: V3<L>) {
        self.position = self.position + impulse.scale(self.inverse_mass);
    }

    /// `SolverBody::apply_angular_impulse` per lane.
    #[inline(always)]
    pub fn apply_angular_impulse(&mut self, l: V3<L>) {
        let dtheta = self.inverse_inertia.mul_vec(l);
        self.rotate_preview(dtheta);
    }

    /// `SolverBody::positional_inverse_mass` per lane: `1/m + (r x n) . I^-1 (r x n)`.
    #[inline(always)]
    pub fn positional_inverse_mass(&self, r: V3<L>, n: V3<L>) -> L {
        let rn = r.cross(n);
        self.inverse_mass + rn.dot(self.inverse_inertia.mul_vec(rn))
    }

    /// `SolverBody::angular_inverse_mass` per lane: `g . I^-1 g`.
    #[inline(always)]
    pub fn angular_inverse_mass(&self, g: V3<L>) -> L {
        g.dot(self.inverse_inertia.mul_vec(g))
    }
}
