//! The x86-64 lane types, one per instruction set: [`F32x4`] on SSE2 (every x86-64 CPU),
//! [`F32x8`] on AVX2 and [`F32x16`] on AVX-512F.
//!
//! Each operation is one instruction of its set that rounds exactly as IEEE 754 says (add,
//! subtract, multiply, divide, square root), or moves bits (min and max with the same operand
//! order, compares, masks, selects). None is fused or estimated, so a lane gives the same bits
//! at every width. The 8- and 16-lane types are used only inside [`super::Lane::dispatch`] on a
//! CPU that [`super::LaneWidth::detect`] found to have their instruction set; their methods are
//! `#[inline(always)]`, so they compile into the dispatched function with its instructions.

use super::{Lane, LaneWork};
use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};

/// Four lanes in an SSE register.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F32x4(pub(super) __m128);

/// Eight lanes in an AVX register.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F32x8(pub(super) __m256);

/// Sixteen lanes in an AVX-512 register.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct F32x16(pub(super) __m512);

/// The arithmetic and bitwise operators of one lane type, each one intrinsic.
macro_rules! operators {
    ($t:ident, $add:ident, $sub:ident, $mul:ident, $div:ident, $and:expr, $or:expr, $xor:expr) => {
        impl Add for $t {
            type Output = Self;
            #[inline(always)]
            #[allow(unused_unsafe)]
            fn add(self, o: Self) -> Self {
                // SAFETY: the instruction set is this type's (module docs)
                unsafe { $t($add(self.0, o.0)) }
            }
        }
        impl Sub for $t {
            type Output = Self;
            #[inline(always)]
            #[allow(unused_unsafe)]
            fn sub(self, o: Self) -> Self {
                // SAFETY: as in `add`
                unsafe { $t($sub(self.0, o.0)) }
            }
        }
        impl Mul for $t {
            type Output = Self;
            #[inline(always)]
            #[allow(unused_unsafe)]
            fn mul(self, o: Self) -> Self {
                // SAFETY: as in `add`
                unsafe { $t($mul(self.0, o.0)) }
            }
        }
        impl Div for $t {
            type Output = Self;
            #[inline(always)]
            #[allow(unused_unsafe)]
            fn div(self, o: Self) -> Self {
                // SAFETY: as in `add`
                unsafe { $t($div(self.0, o.0)) }
            }
        }
        impl BitAnd for $t {
            type Output = Self;
            #[inline(always)]
            #[allow(unused_unsafe)]
            fn bitand(self, o: Self) -> Self {
                // SAFETY: as in `add`
                unsafe { $t($and(self.0, o.0)) }
            }
        }
        impl BitOr for $t {
            type Output = Self;
            #[inline(always)]
            #[allow(unused_unsafe)]
            fn bitor(self, o: Self) -> Self {
                // SAFETY: as in `add`
                unsafe { $t($or(self.0, o.0)) }
            }
        }
        impl Neg for $t {
            type Output = Self;
            #[inline(always)]
            #[allow(unused_unsafe)]
            fn neg(self) -> Self {
                // SAFETY: as in `add`; the sign bit flipped, as a scalar negation does
                unsafe { $t($xor(self.0, <$t as Lane>::splat(-0.0).0)) }
            }
        }
    };
}

operators!(
    F32x4, _mm_add_ps, _mm_sub_ps, _mm_mul_ps, _mm_div_ps, _mm_and_ps, _mm_or_ps, _mm_xor_ps
);
operators!(
    F32x8,
    _mm256_add_ps,
    _mm256_sub_ps,
    _mm256_mul_ps,
    _mm256_div_ps,
    _mm256_and_ps,
    _mm256_or_ps,
    _mm256_xor_ps
);
operators!(
    F32x16,
    _mm512_add_ps,
    _mm512_sub_ps,
    _mm512_mul_ps,
    _mm512_div_ps,
    and_512,
    or_512,
    xor_512
);

// AVX-512F has its bitwise operations on integer lanes only (the float ones are AVX-512DQ's)
#[inline(always)]
unsafe fn and_512(a: __m512, b: __m512) -> __m512 {
    _mm512_castsi512_ps(_mm512_and_epi32(
        _mm512_castps_si512(a),
        _mm512_castps_si512(b),
    ))
}
#[inline(always)]
unsafe fn or_512(a: __m512, b: __m512) -> __m512 {
    _mm512_castsi512_ps(_mm512_or_epi32(
        _mm512_castps_si512(a),
        _mm512_castps_si512(b),
    ))
}
#[inline(always)]
unsafe fn xor_512(a: __m512, b: __m512) -> __m512 {
    _mm512_castsi512_ps(_mm512_xor_epi32(
        _mm512_castps_si512(a),
        _mm512_castps_si512(b),
    ))
}
/// A mask register's lanes as float lanes, all bits set where the mask is.
#[inline(always)]
unsafe fn mask_512(k: __mmask16) -> __m512 {
    _mm512_castsi512_ps(_mm512_maskz_set1_epi32(k, -1))
}
/// The lanes of a float mask that are set, as a mask register.
#[inline(always)]
unsafe fn lanes_512(m: __m512) -> __mmask16 {
    let m = _mm512_castps_si512(m);
    _mm512_test_epi32_mask(m, m)
}

/// `2^n` for integer-valued lanes `n` in [-126, 127]: `n + 127` in the exponent bits.
macro_rules! pow2i {
    ($cvt:ident, $add:ident, $set1:ident, $shift:ident, $cast:ident, $n:expr) => {
        $cast($shift::<23>($add($cvt($n), $set1(127))))
    };
}

impl Lane for F32x4 {
    const W: usize = 4;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_set1_ps(x)) }
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        let a: [f32; 4] = std::array::from_fn(&mut f);
        // SAFETY: four readable floats
        F32x4(unsafe { _mm_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        assert!(values.len() >= 4);
        // SAFETY: module docs; 4 readable floats
        F32x4(unsafe { _mm_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn at(&self, i: usize) -> f32 {
        // SAFETY: the register is four floats
        unsafe { std::mem::transmute::<__m128, [f32; 4]>(self.0)[i] }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_sqrt_ps(self.0)) }
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_andnot_ps(_mm_set1_ps(-0.0), self.0)) }
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_max_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_min_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_cmplt_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_cmpgt_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn le(self, o: Self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_cmple_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn eq(self, o: Self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { F32x4(_mm_cmpeq_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn select(self, t: Self, f: Self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe {
            // SSE2 has no blend: both sides masked and joined (the masks are all or no bits)
            F32x4(_mm_or_ps(
                _mm_and_ps(self.0, t.0),
                _mm_andnot_ps(self.0, f.0),
            ))
        }
    }
    #[inline(always)]
    fn pow2i(self) -> Self {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe {
            F32x4(pow2i!(
                _mm_cvtps_epi32,
                _mm_add_epi32,
                _mm_set1_epi32,
                _mm_slli_epi32,
                _mm_castsi128_ps,
                self.0
            ))
        }
    }
    #[inline(always)]
    fn bitmask(self) -> u32 {
        // SAFETY: SSE2 is every x86-64 CPU's
        unsafe { _mm_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn dispatch<K: LaneWork<Self>>(work: K) -> K::Output {
        // SSE2 is every x86-64 build's own
        work.run()
    }
}

impl Lane for F32x8 {
    const W: usize = 8;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        let a: [f32; 8] = std::array::from_fn(&mut f);
        // SAFETY: module docs; eight readable floats
        F32x8(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        assert!(values.len() >= 8);
        // SAFETY: module docs; 8 readable floats
        F32x8(unsafe { _mm256_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn at(&self, i: usize) -> f32 {
        // SAFETY: the register is eight floats
        unsafe { std::mem::transmute::<__m256, [f32; 8]>(self.0)[i] }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_max_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_min_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn le(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn eq(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, o.0) })
    }
    #[inline(always)]
    fn select(self, t: Self, f: Self) -> Self {
        // SAFETY: module docs
        F32x8(unsafe { _mm256_blendv_ps(f.0, t.0, self.0) })
    }
    #[inline(always)]
    fn pow2i(self) -> Self {
        // SAFETY: module docs (AVX2 for the integer lanes)
        F32x8(unsafe {
            pow2i!(
                _mm256_cvtps_epi32,
                _mm256_add_epi32,
                _mm256_set1_epi32,
                _mm256_slli_epi32,
                _mm256_castsi256_ps,
                self.0
            )
        })
    }
    #[inline(always)]
    fn bitmask(self) -> u32 {
        // SAFETY: module docs
        unsafe { _mm256_movemask_ps(self.0) as u32 }
    }
    #[inline(always)]
    fn dispatch<K: LaneWork<Self>>(work: K) -> K::Output {
        #[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
        unsafe fn run<K: LaneWork<F32x8>>(work: K) -> K::Output {
            work.run()
        }
        debug_assert!(super::LaneWidth::W8.is_available());
        // SAFETY: this type is only made on a CPU with AVX2 (module docs)
        unsafe { run(work) }
    }
}

impl Lane for F32x16 {
    const W: usize = 16;
    #[inline(always)]
    fn splat(x: f32) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { _mm512_set1_ps(x) })
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        let a: [f32; 16] = std::array::from_fn(&mut f);
        // SAFETY: module docs; sixteen readable floats
        F32x16(unsafe { _mm512_loadu_ps(a.as_ptr()) })
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        assert!(values.len() >= 16);
        // SAFETY: module docs; 16 readable floats
        F32x16(unsafe { _mm512_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn at(&self, i: usize) -> f32 {
        // SAFETY: the register is sixteen floats
        unsafe { std::mem::transmute::<__m512, [f32; 16]>(self.0)[i] }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { _mm512_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { _mm512_abs_ps(self.0) })
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { _mm512_max_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { _mm512_min_ps(self.0, o.0) })
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { mask_512(_mm512_cmp_ps_mask::<_CMP_LT_OQ>(self.0, o.0)) })
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { mask_512(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(self.0, o.0)) })
    }
    #[inline(always)]
    fn le(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { mask_512(_mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, o.0)) })
    }
    #[inline(always)]
    fn eq(self, o: Self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { mask_512(_mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, o.0)) })
    }
    #[inline(always)]
    fn select(self, t: Self, f: Self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe { _mm512_mask_blend_ps(lanes_512(self.0), f.0, t.0) })
    }
    #[inline(always)]
    fn pow2i(self) -> Self {
        // SAFETY: module docs
        F32x16(unsafe {
            pow2i!(
                _mm512_cvtps_epi32,
                _mm512_add_epi32,
                _mm512_set1_epi32,
                _mm512_slli_epi32,
                _mm512_castsi512_ps,
                self.0
            )
        })
    }
    #[inline(always)]
    fn bitmask(self) -> u32 {
        // SAFETY: module docs
        unsafe { lanes_512(self.0) as u32 }
    }
    /// The pairs compressed in registers and stored whole, with no branch per bit (one,
    /// mispredicted as often as not, would be most of the broad phase's rebuild).
    #[inline(always)]
    fn push_pairs(out: &mut Vec<[u32; 2]>, a: u32, base: u32, bits: u32) {
        out.reserve(16);
        let len = out.len();
        // each pair as one u64: `a` in the low half (the array's first, on this little-endian
        // target), `base + k` in the high half
        let pair = |k: i64| ((base as i64 + k) << 32) | a as i64;
        // SAFETY: module docs; `reserve` made room for 16 pairs past `len`; each store writes 8
        // u64s (8 pairs' bytes, `[u32; 2]` having no padding) from where the last one's pairs
        // end, so the first `count_ones` past `len` are the pairs set, written.
        unsafe {
            let to = out.as_mut_ptr().add(len) as *mut __m512i;
            let low = _mm512_set_epi64(
                pair(7),
                pair(6),
                pair(5),
                pair(4),
                pair(3),
                pair(2),
                pair(1),
                pair(0),
            );
            let high = _mm512_add_epi64(low, _mm512_set1_epi64(8 << 32));
            let low_bits = bits as u8;
            _mm512_storeu_si512(to, _mm512_maskz_compress_epi64(low_bits, low));
            let next = (to as *mut [u32; 2]).add(low_bits.count_ones() as usize);
            let high_bits = (bits >> 8) as u8;
            _mm512_storeu_si512(
                next as *mut __m512i,
                _mm512_maskz_compress_epi64(high_bits, high),
            );
            out.set_len(len + bits.count_ones() as usize);
        }
    }
    #[inline(always)]
    fn dispatch<K: LaneWork<Self>>(work: K) -> K::Output {
        #[target_feature(enable = "avx512f,avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
        unsafe fn run<K: LaneWork<F32x16>>(work: K) -> K::Output {
            work.run()
        }
        debug_assert!(super::LaneWidth::W16.is_available());
        // SAFETY: this type is only made on a CPU with AVX-512F (module docs)
        unsafe { run(work) }
    }
}
