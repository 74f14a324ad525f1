//! The transpose that gathers bodies into lanes and scatters them back: groups of four floats
//! of `W` records turned into four lanes, and back.
//!
//! Pure data movement, so every path gives the same bits. With AVX-512 (16 lanes) and AVX (8
//! lanes) the whole transpose stays in registers: each register takes one record's four floats
//! per 128-bit block (records `i, i + 4, i + 8, i + 12`), and the 4 x 4 shuffle network, which
//! works within each block, leaves record `4k + j` in lane `4k + j`. Without them the network runs
//! on 4-wide pieces assembled through memory; on AVX-512 that path wrote 4-float pieces to the
//! stack and read them back as 16-float registers (a load that no single store can forward), and
//! gathering and scattering a joint's two bodies cost about 10 ns at 16 lanes, more than the cheap
//! joint's own arithmetic (`benches/solver.rs`).

use super::MAX_LANES;

/// Groups of four floats of `W` records turned into four lanes, and back.
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

/// The 4 x 4 network on 4-wide pieces, `blocks` pieces of four records: the portable path.
#[cfg_attr(
    all(target_arch = "x86_64", target_feature = "avx512f"),
    allow(dead_code)
)]
#[inline(always)]
fn transpose_blocks<const N: usize>(rows: [&[f32; 4]; MAX_LANES], blocks: usize) -> [[f32; N]; 4] {
    let mut out = [[0.0f32; N]; 4];
    for k in 0..blocks {
        let part: [wide::f32x4; 4] =
            Transpose4::transpose4(std::array::from_fn(|i| rows[(i + 4 * k) % MAX_LANES]));
        for (j, column) in out.iter_mut().enumerate() {
            column[4 * k..4 * k + 4].copy_from_slice(&part[j].to_array());
        }
    }
    out
}

/// The inverse of [`transpose_blocks`].
#[cfg_attr(
    all(target_arch = "x86_64", target_feature = "avx512f"),
    allow(dead_code)
)]
#[inline(always)]
fn untranspose_blocks<const N: usize>(cols: [[f32; N]; 4], blocks: usize) -> [[f32; 4]; MAX_LANES] {
    let mut out = [[0.0; 4]; MAX_LANES];
    for k in 0..blocks {
        let quarter: [wide::f32x4; 4] = std::array::from_fn(|j| {
            let c = &cols[j];
            wide::f32x4::new([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
        });
        let t = <wide::f32x4 as Transpose4>::untranspose4(quarter);
        out[4 * k..4 * k + 4].copy_from_slice(&t[..4]);
    }
    out
}

/// The 4 x 4 transpose within each 128-bit block of four registers (its own inverse), for one
/// register width: `unpack*_ps` pairs the rows' floats, `unpack*_pd` their pairs.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
macro_rules! block_network {
    ($name:ident, $reg:ty, $lo_ps:ident, $hi_ps:ident, $lo_pd:ident, $hi_pd:ident, $ps_pd:ident, $pd_ps:ident) => {
        #[inline(always)]
        unsafe fn $name([r0, r1, r2, r3]: [$reg; 4]) -> [$reg; 4] {
            use std::arch::x86_64::*;
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

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
block_network!(
    network_256,
    std::arch::x86_64::__m256,
    _mm256_unpacklo_ps,
    _mm256_unpackhi_ps,
    _mm256_unpacklo_pd,
    _mm256_unpackhi_pd,
    _mm256_castps_pd,
    _mm256_castpd_ps
);

#[cfg(all(target_arch = "x86_64", target_feature = "avx512f"))]
block_network!(
    network_512,
    std::arch::x86_64::__m512,
    _mm512_unpacklo_ps,
    _mm512_unpackhi_ps,
    _mm512_unpacklo_pd,
    _mm512_unpackhi_pd,
    _mm512_castps_pd,
    _mm512_castpd_ps
);

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
impl Transpose4 for wide::f32x8 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        use std::arch::x86_64::*;
        // SAFETY: AVX is enabled at compile time; each row is four readable floats, and an
        // f32x8 is a plain 32-byte vector of eight f32.
        unsafe {
            let row = |i: usize| {
                let low = _mm256_castps128_ps256(_mm_loadu_ps(rows[i].as_ptr()));
                _mm256_insertf128_ps::<1>(low, _mm_loadu_ps(rows[i + 4].as_ptr()))
            };
            network_256([row(0), row(1), row(2), row(3)])
                .map(|v| std::mem::transmute::<__m256, wide::f32x8>(v))
        }
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        use std::arch::x86_64::*;
        // SAFETY: as in `transpose4`; the stores write into `out`, 4 floats per record.
        unsafe {
            // record j (block 0) and j + 4 (block 1) in r_j
            let r = network_256(cols.map(|c| std::mem::transmute::<wide::f32x8, __m256>(c)));
            let mut out = [[0.0f32; 4]; MAX_LANES];
            for (j, v) in r.into_iter().enumerate() {
                _mm_storeu_ps(out[j].as_mut_ptr(), _mm256_castps256_ps128(v));
                _mm_storeu_ps(out[j + 4].as_mut_ptr(), _mm256_extractf128_ps::<1>(v));
            }
            out
        }
    }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
impl Transpose4 for wide::f32x8 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        transpose_blocks::<8>(rows, 2).map(wide::f32x8::new)
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        untranspose_blocks(cols.map(|c| c.to_array()), 2)
    }
}

#[cfg(all(target_arch = "x86_64", target_feature = "avx512f"))]
impl Transpose4 for wide::f32x16 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        use std::arch::x86_64::*;
        // SAFETY: AVX-512F is enabled at compile time; each row is four readable floats, and an
        // f32x16 is a plain 64-byte vector of sixteen f32.
        unsafe {
            let load = |i: usize| _mm_loadu_ps(rows[i].as_ptr());
            let row = |i: usize| {
                let v = _mm512_castps128_ps512(load(i));
                let v = _mm512_insertf32x4::<1>(v, load(i + 4));
                let v = _mm512_insertf32x4::<2>(v, load(i + 8));
                _mm512_insertf32x4::<3>(v, load(i + 12))
            };
            network_512([row(0), row(1), row(2), row(3)])
                .map(|v| std::mem::transmute::<__m512, wide::f32x16>(v))
        }
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        use std::arch::x86_64::*;
        // SAFETY: as in `transpose4`; the stores write into `out`, 4 floats per record.
        unsafe {
            // record 4k + j in block k of r_j
            let r = network_512(cols.map(|c| std::mem::transmute::<wide::f32x16, __m512>(c)));
            let mut out = [[0.0f32; 4]; MAX_LANES];
            for (j, v) in r.into_iter().enumerate() {
                _mm_storeu_ps(out[j].as_mut_ptr(), _mm512_castps512_ps128(v));
                _mm_storeu_ps(out[j + 4].as_mut_ptr(), _mm512_extractf32x4_ps::<1>(v));
                _mm_storeu_ps(out[j + 8].as_mut_ptr(), _mm512_extractf32x4_ps::<2>(v));
                _mm_storeu_ps(out[j + 12].as_mut_ptr(), _mm512_extractf32x4_ps::<3>(v));
            }
            out
        }
    }
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx512f")))]
impl Transpose4 for wide::f32x16 {
    #[inline(always)]
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4] {
        transpose_blocks::<16>(rows, 4).map(wide::f32x16::new)
    }
    #[inline(always)]
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES] {
        untranspose_blocks(cols.map(|c| c.to_array()), 4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every width's transpose against its definition, and back to the records, bit for bit
    /// (with signed zeros and NaN payloads, which a float path could change).
    fn round_trip<L: Transpose4 + Copy>(width: usize, lanes: impl Fn(L) -> Vec<f32>) {
        let specials = [-0.0f32, f32::from_bits(0x7fc0_1234), f32::INFINITY, 1e-42];
        let records: [[f32; 4]; MAX_LANES] = std::array::from_fn(|i| {
            std::array::from_fn(|j| match (i * 4 + j) % 11 {
                k @ 0..=3 => specials[k],
                k => (i * 4 + j) as f32 * 0.37 - k as f32,
            })
        });
        let columns = L::transpose4(std::array::from_fn(|i| &records[i]));
        for (j, column) in columns.iter().enumerate() {
            let got = lanes(*column);
            for i in 0..width {
                assert_eq!(
                    got[i].to_bits(),
                    records[i][j].to_bits(),
                    "record {i} field {j}"
                );
            }
        }
        let back = L::untranspose4(columns);
        for i in 0..width {
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
        round_trip::<wide::f32x4>(4, |v| v.to_array().to_vec());
        round_trip::<wide::f32x8>(8, |v| v.to_array().to_vec());
        round_trip::<wide::f32x16>(16, |v| v.to_array().to_vec());
        // the portable network too, whatever this build uses
        let records: [[f32; 4]; MAX_LANES] =
            std::array::from_fn(|i| std::array::from_fn(|j| (i * 4 + j) as f32));
        let columns = transpose_blocks::<16>(std::array::from_fn(|i| &records[i]), 4);
        assert!((0..16).all(|i| (0..4).all(|j| columns[j][i] == records[i][j])));
        assert_eq!(untranspose_blocks(columns, 4), records);
    }
}
