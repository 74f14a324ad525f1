//! The transpose that gathers bodies into lanes and scatters them back: groups of four floats
//! of `W` records turned into four lanes, and back. Pure data movement, so every lane type
//! gives the same bits; each implements it with its own shuffles.

use super::MAX_LANES;

/// Groups of four floats of `W` records turned into four lanes, and back.
pub trait Transpose4: Sized {
    /// `out[j]` lane i = `rows[i][j]`, for the first `W` rows.
    fn transpose4(rows: [&[f32; 4]; MAX_LANES]) -> [Self; 4];
    /// `rows[i][j]` = lane i of `cols[j]`.
    fn untranspose4(cols: [Self; 4]) -> [[f32; 4]; MAX_LANES];
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
