//! W-wide lanes for the batched solve (paper §7: "branch-free SIMD code, solving four
//! constraints at once"; Box2D v3's `b2FloatW`, Rapier's SIMD joint groups).
//!
//! [`Lane`] is a float vector of `W` lanes (`wide::f32x4`, `f32x8` or `f32x16`); [`V3`], [`Q`] and
//! [`SymM3`] are glam's `Vec3`, `Quat` and a symmetric 3x3 matrix with one lane per
//! constraint. Branches become masks: compute both sides, [`Lane::select`] per lane.
//! [`BodyLanes`] holds W solver bodies gathered from [`crate::solver_body::SolverBody`]s by index and is scattered
//! back after the batch; the body methods mirror the scalar ones on [`crate::solver_body::SolverBody`].
//! [`exact`] computes what must match the scalar code to the bit (the joints' starting twist).

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};

mod body;
pub mod exact;
mod transpose;
mod vector;

pub use body::{relative_rotation, relative_rotation_across, relative_rotation_block, BodyLanes};
pub use transpose::Transpose4;
pub use vector::{SymM3, Q, V3};

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
    /// Lane `i`'s value, read in place (no copy of the vector).
    fn at(&self, i: usize) -> f32;
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
    /// Per-lane `e^self`.
    fn exp(self) -> Self;
    /// Whether any lane of the mask is set.
    fn any(self) -> bool;
    /// The mask's lanes as bits, lane `i` at bit `i`.
    fn bitmask(self) -> u32;

    /// All lanes zero.
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
}

/// Per-lane logical not of a mask.
#[inline(always)]
pub fn not<L: Lane>(mask: L) -> L {
    mask.select(L::zero(), L::zero().lt(L::splat(1.0)))
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
            fn at(&self, i: usize) -> f32 {
                self.as_array()[i]
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
            fn exp(self) -> Self {
                <$t>::exp(self)
            }
            #[inline(always)]
            fn any(self) -> bool {
                <$t>::any(self)
            }
            #[inline(always)]
            fn bitmask(self) -> u32 {
                <$t>::to_bitmask(self) as u32
            }
        }
    };
}

impl_lane!(wide::f32x4, 4);
impl_lane!(wide::f32x8, 8);
impl_lane!(wide::f32x16, 16);
