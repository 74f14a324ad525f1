//! The transpose that gathers bodies into lanes and scatters them back: groups of four floats
//! of `W` records turned into four lanes, and back. Pure data movement, so every lane type
//! gives the same bits; each implements it with its own shuffles (the x86-64 types below, the
//! portable arrays in `portable.rs`).

use super::MAX_LANES;
#[cfg(target_arch = "x86_64")]
use super::{F32x16, F32x4, F32x8};
#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

/// Groups of four floats of `W` records turned into four lanes, and back.
pub trait Transpose4: Sized {
    /// `out[j]` lane i = `rows[i][j]`, for the first `W` rows.
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4];
    /// `rows[i][j]` = lane i of `cols[j]`.
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES];
}

/// The 4 x 4 transpose within each 128-bit block of four registers (its own inverse):
/// `unpack*_ps` pairs the rows' floats, `unpack*_pd` their pairs.
#[cfg(target_arch = "x86_64")]
macro_rules! block_network {
    ($name:ident, $reg:ty, $lo_ps:ident, $hi_ps:ident, $lo_pd:ident, $hi_pd:ident, $ps_pd:ident, $pd_ps:ident) => {
        #[inline(always)]
        #[allow(unused_unsafe)]
        unsafe fn $name([r0, r1, r2, r3]: [$reg; 4]) -> [$reg; 4] {
            let (t0, t1) = ($lo_ps(r0, r1), $hi_ps(r0, r1));
            let (t2, t3) = ($lo_ps(r2, r3), $hi_ps(r2, r3));
            let (t0, t1, t2, t3) = ($ps_pd(t0), $ps_pd(t1), $ps_pd(t2), $ps_pd(t3));
            [
                $pd_ps($lo_pd(t0, t2)),
                $pd_ps($hi_pd(t0, t2)),
                $pd_ps($lo_pd(t1, t3)),
                $pd_ps($hi_pd(t1, t3)),
            ]
        }
    };
}

#[cfg(target_arch = "x86_64")]
block_network!(
    network_128,
    __m128,
    _mm_unpacklo_ps,
    _mm_unpackhi_ps,
    _mm_unpacklo_pd,
    _mm_unpackhi_pd,
    _mm_castps_pd,
    _mm_castpd_ps
);
#[cfg(target_arch = "x86_64")]
block_network!(
    network_256,
    __m256,
    _mm256_unpacklo_ps,
    _mm256_unpackhi_ps,
    _mm256_unpacklo_pd,
    _mm256_unpackhi_pd,
    _mm256_castps_pd,
    _mm256_castpd_ps
);
#[cfg(target_arch = "x86_64")]
block_network!(
    network_512,
    __m512,
    _mm512_unpacklo_ps,
    _mm512_unpackhi_ps,
    _mm512_unpacklo_pd,
    _mm512_unpackhi_pd,
    _mm512_castps_pd,
    _mm512_castpd_ps
);

// On x86-64 the whole transpose stays in registers: each register takes one record's four floats per
// 128-bit block (records `i, i + 4, i + 8, i + 12`), and the network, which works within each
// block, leaves record `4k + j` in lane `4k + j`. Assembling 4-float pieces through memory
// instead made gathering and scattering a joint's two bodies cost more than the cheap joint's
// own arithmetic at 16 lanes (a 16-float load that no single store can forward).

#[cfg(target_arch = "x86_64")]
impl Transpose4 for F32x4 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        // SAFETY: each row is four readable floats
        unsafe {
            let row = |i: usize| _mm_loadu_ps(rows[i].as_ptr());
            network_128([row(0), row(1), row(2), row(3)]).map(F32x4)
        }
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        let mut out = [[0.0f32; 4]; MAX_LANES];
        // SAFETY: the stores write into `out`, four floats per record
        unsafe {
            let r = network_128(cols.map(|c| c.0));
            for (j, v) in r.into_iter().enumerate() {
                _mm_storeu_ps(out[j].as_mut_ptr(), v);
            }
        }
        out
    }
}

#[cfg(target_arch = "x86_64")]
impl Transpose4 for F32x8 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        // SAFETY: the CPU runs this lane type's instructions (`x86.rs`); each row is four readable floats
        unsafe {
            let row = |i: usize| {
                let low = _mm256_castps128_ps256(_mm_loadu_ps(rows[i].as_ptr()));
                _mm256_insertf128_ps::<1>(low, _mm_loadu_ps(rows[i + 4].as_ptr()))
            };
            network_256([row(0), row(1), row(2), row(3)]).map(F32x8)
        }
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        let mut out = [[0.0f32; 4]; MAX_LANES];
        // SAFETY: as in `transpose4`; the stores write into `out`, four floats per record
        unsafe {
            // record j (block 0) and j + 4 (block 1) in r_j
            let r = network_256(cols.map(|c| c.0));
            for (j, v) in r.into_iter().enumerate() {
                _mm_storeu_ps(out[j].as_mut_ptr(), _mm256_castps256_ps128(v));
                _mm_storeu_ps(out[j + 4].as_mut_ptr(), _mm256_extractf128_ps::<1>(v));
            }
        }
        out
    }
}

#[cfg(target_arch = "x86_64")]
impl Transpose4 for F32x16 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        // SAFETY: the CPU runs this lane type's instructions (`x86.rs`); each row is four readable floats
        unsafe {
            let load = |i: usize| _mm_loadu_ps(rows[i].as_ptr());
            let row = |i: usize| {
                let v = _mm512_castps128_ps512(load(i));
                let v = _mm512_insertf32x4::<1>(v, load(i + 4));
                let v = _mm512_insertf32x4::<2>(v, load(i + 8));
                _mm512_insertf32x4::<3>(v, load(i + 12))
            };
            network_512([row(0), row(1), row(2), row(3)]).map(F32x16)
        }
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        let mut out = [[0.0f32; 4]; MAX_LANES];
        // SAFETY: as in `transpose4`; the stores write into `out`, four floats per record
        unsafe {
            // record 4k + j in block k of r_j
            let r = network_512(cols.map(|c| c.0));
            for (j, v) in r.into_iter().enumerate() {
                _mm_storeu_ps(out[j].as_mut_ptr(), _mm512_castps512_ps128(v));
                _mm_storeu_ps(out[j + 4].as_mut_ptr(), _mm512_extractf32x4_ps::<1>(v));
                _mm_storeu_ps(out[j + 8].as_mut_ptr(), _mm512_extractf32x4_ps::<2>(v));
                _mm_storeu_ps(out[j + 12].as_mut_ptr(), _mm512_extractf32x4_ps::<3>(v));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::{portable::Portable, F32x16, F32x4, F32x8, Lane, LaneWidth};
    use super::*;

    /// A width's transpose against its definition, and back to the records, bit for bit (with
    /// signed zeros and NaN payloads, which a float path could change).
    fn round_trip<L: Lane>() {
        let specials = [-0.0f32, f32::from_bits(0x7fc0_1234), f32::INFINITY, 1e-42];
        let records: [[f32; 4]; MAX_LANES] = std::array::from_fn(|i| {
            std::array::from_fn(|j| match (i * 4 + j) % 11 {
                k @ 0..=3 => specials[k],
                k => (i * 4 + j) as f32 * 0.37 - k as f32,
            })
        });
        let columns = L::transpose4(std::array::from_fn(|i| &records[i]));
        for (j, column) in columns.iter().enumerate() {
            for (i, record) in records.iter().enumerate().take(L::W) {
                let got = column.at(i);
                assert_eq!(got.to_bits(), record[j].to_bits(), "record {i} field {j}");
            }
        }
        let back = L::untranspose4(columns);
        for i in 0..L::W {
            let same = (0..4).all(|j| back[i][j].to_bits() == records[i][j].to_bits());
            assert!(
                same,
                "record {i} back: {:?} against {:?}",
                back[i], records[i]
            );
        }
    }

    #[test]
    fn the_transposes_move_every_record_to_its_lane_and_back_bit_for_bit() {
        round_trip::<F32x4>();
        if LaneWidth::W8.is_available() {
            round_trip::<F32x8>();
        }
        if LaneWidth::W16.is_available() {
            round_trip::<F32x16>();
        }
        round_trip::<Portable<4>>();
        round_trip::<Portable<16>>();
    }
}
