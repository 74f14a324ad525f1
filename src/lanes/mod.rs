//! W-wide lanes for the batched solve (paper §7: "branch-free SIMD code, solving four
//! constraints at once"; Box2D v3's `b2FloatW`, Rapier's SIMD joint groups).
//!
//! [`Lane`] is a float vector of `W` lanes; [`V3`], [`Q`] and [`SymM3`] are glam's `Vec3`,
//! `Quat` and a symmetric 3x3 matrix with one lane per constraint. Branches become masks:
//! compute both sides, [`Lane::select`] per lane. [`BodyLanes`] holds W solver bodies gathered
//! from [`crate::solver_body::SolverBody`]s by index and is scattered back after the batch;
//! the body methods mirror the scalar ones on [`crate::solver_body::SolverBody`].
//!
//! # The same bits at every width
//! A lane computes the same operations in the same order whatever the width: each lane
//! operation rounds as IEEE 754 says (no fused multiply-add, no reciprocal estimate), and the
//! transcendental functions are [`maths`]' own, written with those operations. Rows of one
//! colour share no movable body, so how they are cut into batches does not change what each
//! computes: results are bit-identical at 4, 8 and 16 lanes (`tests/it/determinism.rs`).
//!
//! # The width, chosen at run time
//! The build targets the x86-64 baseline, so one binary runs on any x86-64 CPU. The solver asks
//! [`LaneWidth::detect`] for the widest lane type the CPU runs ([`F32x16`] with AVX-512F,
//! [`F32x8`] with AVX2, else [`F32x4`]; the environment variable `RODLAB_LANES` may ask for
//! fewer), and hands each hot loop to [`Lane::dispatch`], which runs it in a function compiled
//! for that instruction set. Everything the loop calls on lanes is `#[inline(always)]`, so it
//! compiles inside that function.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};
use std::sync::OnceLock;

mod body;
pub mod exact;
pub mod maths;
pub mod portable;
mod transpose;
mod vector;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use body::{relative_rotation, relative_rotation_across, relative_rotation_block, BodyLanes};
pub use transpose::Transpose4;
pub use vector::{SymM3, Q, V3};
#[cfg(target_arch = "x86_64")]
pub use x86::{F32x16, F32x4, F32x8};

/// The lane types off x86-64: plain arrays ([`portable`]), only the 4-wide one ever detected.
#[cfg(not(target_arch = "x86_64"))]
pub type F32x4 = portable::Portable<4>;
/// See [`F32x4`].
#[cfg(not(target_arch = "x86_64"))]
pub type F32x8 = portable::Portable<8>;
/// See [`F32x4`].
#[cfg(not(target_arch = "x86_64"))]
pub type F32x16 = portable::Portable<16>;

/// The widest lane type's width; arrays of per-lane data are this long.
pub const MAX_LANES: usize = 16;

/// How many lanes one instruction covers: the lane type the SIMD solver runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum LaneWidth {
    /// [`F32x4`]: SSE2, every x86-64 CPU.
    W4,
    /// [`F32x8`]: AVX2 (x86-64-v3).
    W8,
    /// [`F32x16`]: AVX-512F.
    W16,
}

impl LaneWidth {
    /// Every width, narrowest first.
    pub const ALL: [LaneWidth; 3] = [LaneWidth::W4, LaneWidth::W8, LaneWidth::W16];

    /// Lanes per instruction.
    pub fn lanes(self) -> usize {
        match self {
            LaneWidth::W4 => 4,
            LaneWidth::W8 => 8,
            LaneWidth::W16 => 16,
        }
    }

    /// The width of `lanes` lanes (4, 8 or 16).
    pub fn from_lanes(lanes: usize) -> Option<Self> {
        Self::ALL.into_iter().find(|w| w.lanes() == lanes)
    }

    /// Whether this CPU runs this width's instructions.
    pub fn is_available(self) -> bool {
        match self {
            LaneWidth::W4 => true,
            #[cfg(target_arch = "x86_64")]
            LaneWidth::W8 => x86_64_v3(),
            #[cfg(target_arch = "x86_64")]
            LaneWidth::W16 => x86_64_v3() && std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The widths this CPU runs, narrowest first.
    pub fn available() -> impl Iterator<Item = LaneWidth> {
        Self::ALL.into_iter().filter(|w| w.is_available())
    }

    /// The widest width this CPU runs, or the one `RODLAB_LANES` (4, 8 or 16) asks for if the
    /// CPU runs it (else a warning, once, and the widest). Read once per process.
    pub fn detect() -> LaneWidth {
        static DETECTED: OnceLock<LaneWidth> = OnceLock::new();
        *DETECTED.get_or_init(|| {
            let widest = Self::available().last().unwrap_or(LaneWidth::W4);
            let Ok(asked) = std::env::var("RODLAB_LANES") else {
                return widest;
            };
            let width = asked.trim().parse().ok().and_then(Self::from_lanes);
            match width {
                Some(width) if width.is_available() => width,
                _ => {
                    let lanes = widest.lanes();
                    eprintln!(
                        "RODLAB_LANES={asked}: this CPU runs 4{} lanes; using {lanes}",
                        match widest {
                            LaneWidth::W4 => "",
                            LaneWidth::W8 => " or 8",
                            LaneWidth::W16 => ", 8 or 16",
                        }
                    );
                    widest
                }
            }
        })
    }
}

impl Default for LaneWidth {
    /// [`LaneWidth::detect`]'s.
    fn default() -> Self {
        LaneWidth::detect()
    }
}

/// Whether the CPU has x86-64-v3's instructions (AVX2, FMA, BMI1 and 2, LZCNT, POPCNT), which
/// the 8- and 16-lane functions are compiled with (none of them fuses a multiply and an add
/// the code writes apart: Rust never contracts them).
#[cfg(target_arch = "x86_64")]
fn x86_64_v3() -> bool {
    use std::arch::is_x86_feature_detected as has;
    has!("avx2") && has!("fma") && has!("bmi1") && has!("bmi2") && has!("lzcnt") && has!("popcnt")
}

/// Work run on one lane type in a function compiled for its instruction set
/// ([`Lane::dispatch`]). Implementations mark `run` `#[inline(always)]`, so the work, and
/// every `#[inline(always)]` lane operation in it, compiles inside that function.
pub trait LaneWork<L: Lane> {
    /// What the work returns.
    type Output;
    /// Does the work.
    fn run(self) -> Self::Output;
}

/// Calls `$body` with the type name `$L` bound to `$width`'s lane type.
#[macro_export]
macro_rules! with_lane_type {
    ($width:expr, $L:ident => $body:expr) => {
        match $width {
            $crate::lanes::LaneWidth::W4 => {
                type $L = $crate::lanes::F32x4;
                $body
            }
            $crate::lanes::LaneWidth::W8 => {
                type $L = $crate::lanes::F32x8;
                $body
            }
            $crate::lanes::LaneWidth::W16 => {
                type $L = $crate::lanes::F32x16;
                $body
            }
        }
    };
}

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
    + std::fmt::Debug
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
    /// This lane type's width.
    fn width() -> LaneWidth {
        LaneWidth::from_lanes(Self::W).unwrap_or(LaneWidth::W4)
    }
    /// All lanes set to `x`.
    fn splat(x: f32) -> Self;
    /// Lane `i` from `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// The first `W` floats of `values` (which holds at least `W`).
    fn load(values: &[f32]) -> Self;
    /// Lane `i`'s value, read in place (no copy of the vector).
    fn at(&self, i: usize) -> f32;
    /// Per-lane square root (correctly rounded).
    fn sqrt(self) -> Self;
    /// Per-lane absolute value.
    fn abs(self) -> Self;
    /// Per-lane maximum: `o` unless `self > o` (so `o` on NaN and on equal zeros).
    fn max(self, o: Self) -> Self;
    /// Per-lane minimum: `o` unless `self < o`.
    fn min(self, o: Self) -> Self;
    /// Mask of the lanes where `self < o`.
    fn lt(self, o: Self) -> Self;
    /// Mask of the lanes where `self > o`.
    fn gt(self, o: Self) -> Self;
    /// Mask of the lanes where `self <= o`.
    fn le(self, o: Self) -> Self;
    /// Mask of the lanes where `self == o`.
    fn eq(self, o: Self) -> Self;
    /// Per lane: `t` where the mask `self` is set, else `f`.
    fn select(self, t: Self, f: Self) -> Self;
    /// Per lane `2^n` for whole-numbered lanes `n` in [-126, 127].
    fn pow2i(self) -> Self;
    /// The mask's lanes as bits, lane `i` at bit `i`.
    fn bitmask(self) -> u32;
    /// Runs `work` in a function compiled for this lane type's instruction set.
    fn dispatch<K: LaneWork<Self>>(work: K) -> K::Output;

    /// Lane `i`'s value.
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self.at(i)
    }
    /// Whether any lane of the mask is set.
    #[inline(always)]
    fn any(self) -> bool {
        self.bitmask() != 0
    }
    /// All lanes zero.
    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }
    /// Per-lane `atan2(self, x)` (rad), `self` being y: [`maths::atan2`].
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        maths::atan2(self, x)
    }
    /// Per-lane sine and cosine of `self` (rad): [`maths::sin_cos`].
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        maths::sin_cos(self)
    }
    /// Per-lane `e^self`: [`maths::exp`].
    #[inline(always)]
    fn exp(self) -> Self {
        maths::exp(self)
    }
    /// Appends `[a, base + k]` to `out` for each set bit `k` of `bits` (below `W`), in order:
    /// the broad phase's pairs from a mask of lanes (a lane type may store them with its own
    /// instructions, with no branch per pair).
    #[inline(always)]
    fn push_pairs(out: &mut Vec<[u32; 2]>, a: u32, base: u32, bits: u32) {
        let mut bits = bits;
        while bits != 0 {
            out.push([a, base + bits.trailing_zeros()]);
            bits &= bits - 1;
        }
    }
}

/// Per-lane logical not of a mask.
#[inline(always)]
pub fn not<L: Lane>(mask: L) -> L {
    mask.select(L::zero(), L::zero().lt(L::splat(1.0)))
}
