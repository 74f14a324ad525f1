//! Lanes as plain float arrays, for targets without the x86-64 types (and, on x86-64, as the
//! reference the tests hold those to): each operation lane by lane with the scalar operation
//! that rounds the same way, and min, max, compares and selects with the x86 instructions'
//! operand order and masks (all bits set per true lane).

use super::{Lane, LaneWork, Transpose4, MAX_LANES};
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};

/// `N` lanes as an array.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Portable<const N: usize>(pub [f32; N]);

/// All bits set: a true lane of a mask.
const TRUE: f32 = f32::from_bits(u32::MAX);

impl<const N: usize> Portable<N> {
    #[inline(always)]
    fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Portable(self.0.map(f))
    }
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f32, f32) -> f32) -> Self {
        Portable(std::array::from_fn(|i| f(self.0[i], o.0[i])))
    }
    #[inline(always)]
    fn bits(self, o: Self, f: impl Fn(u32, u32) -> u32) -> Self {
        self.zip(o, |a, b| f32::from_bits(f(a.to_bits(), b.to_bits())))
    }
    #[inline(always)]
    fn mask(self, o: Self, f: impl Fn(f32, f32) -> bool) -> Self {
        self.zip(o, |a, b| if f(a, b) { TRUE } else { 0.0 })
    }
}

macro_rules! operator {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> $trait for Portable<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                self.zip(o, |a, b| a $op b)
            }
        }
    };
}

operator!(Add, add, +);
operator!(Sub, sub, -);
operator!(Mul, mul, *);
operator!(Div, div, /);

impl<const N: usize> BitAnd for Portable<N> {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        self.bits(o, |a, b| a & b)
    }
}

impl<const N: usize> BitOr for Portable<N> {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        self.bits(o, |a, b| a | b)
    }
}

impl<const N: usize> Neg for Portable<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<const N: usize> Transpose4 for Portable<N> {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        std::array::from_fn(|j| Portable(std::array::from_fn(|i| rows[i][j])))
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        std::array::from_fn(|i| match i < N {
            true => std::array::from_fn(|j| cols[j].0[i]),
            false => [0.0; 4],
        })
    }
}

impl<const N: usize> Lane for Portable<N> {
    const W: usize = N;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        Portable([x; N])
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        Portable(std::array::from_fn(f))
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        Portable(values[..N].try_into().unwrap())
    }
    #[inline(always)]
    fn at(&self, i: usize) -> f32 {
        self.0[i]
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f32::sqrt)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f32::abs)
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // `maxps`: the second operand unless the first is larger (so on NaN and equal zeros)
        self.zip(o, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        self.zip(o, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        self.mask(o, |a, b| a < b)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self {
        self.mask(o, |a, b| a > b)
    }
    #[inline(always)]
    fn le(self, o: Self) -> Self {
        self.mask(o, |a, b| a <= b)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> Self {
        self.mask(o, |a, b| a == b)
    }
    #[inline(always)]
    fn select(self, t: Self, f: Self) -> Self {
        Portable(std::array::from_fn(|i| {
            let m = self.0[i].to_bits();
            f32::from_bits((m & t.0[i].to_bits()) | (!m & f.0[i].to_bits()))
        }))
    }
    #[inline(always)]
    fn pow2i(self) -> Self {
        self.map(|n| f32::from_bits(((n as i32 + 127) as u32) << 23))
    }
    #[inline(always)]
    fn bitmask(self) -> u32 {
        (0..N).fold(0, |bits, i| bits | (self.0[i].to_bits() >> 31) << i)
    }
    #[inline(always)]
    fn dispatch<K: LaneWork<Self>>(work: K) -> K::Output {
        work.run()
    }
}
