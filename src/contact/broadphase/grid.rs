//! The grid's geometry: boxes, cell coordinates and keys, and the merge of sorted pair lists.

use super::FAT_MARGIN;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Aabb {
    pub(super) min: [f32; 3],
    pub(super) max: [f32; 3],
}

impl Aabb {
    pub(super) fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.min[k] <= other.max[k] && other.min[k] <= self.max[k])
    }

    /// Whether `inner` is inside this box, and this box not much larger (a body that landed
    /// after a fast fall would otherwise keep the fat box its speed gave it).
    pub(super) fn holds_snugly(&self, inner: &Aabb) -> bool {
        const LOOSE: f32 = 4.0 * FAT_MARGIN;
        (0..3).all(|k| {
            let (below, above) = (inner.min[k] - self.min[k], self.max[k] - inner.max[k]);
            (0.0..=LOOSE).contains(&below) && (0.0..=LOOSE).contains(&above)
        })
    }

    /// The fat box around this tight one.
    pub(super) fn fattened(&self) -> Aabb {
        Aabb {
            min: self.min.map(|x| x - FAT_MARGIN),
            max: self.max.map(|x| x + FAT_MARGIN),
        }
    }
}

/// The cell index of coordinate `x`: floor without a libm call (x86-64's baseline has no
/// rounding instruction, and `floorf` was a tenth of detection).
#[inline]
pub(super) fn cell_of(x: f32, inverse_cell: f32) -> i64 {
    let scaled = x * inverse_cell;
    let truncated = scaled as i64;
    truncated - ((truncated as f32) > scaled) as i64
}

/// Packs three cell coordinates (each within +-2^20) into one sortable key.
pub(super) fn key(cell: [i64; 3]) -> u64 {
    const MASK: i64 = (1 << 21) - 1;
    (((cell[0] & MASK) as u64) << 42) | (((cell[1] & MASK) as u64) << 21) | (cell[2] & MASK) as u64
}

/// The cells a box covers, per axis, and how many.
pub(super) fn cell_span(aabb: &Aabb, inverse_cell: f32) -> ([i64; 3], [i64; 3], i64) {
    let lo = aabb.min.map(|x| cell_of(x, inverse_cell));
    let hi = aabb.max.map(|x| cell_of(x, inverse_cell));
    let cells = (0..3).fold(1i64, |n, k| {
        n.saturating_mul(hi[k].saturating_sub(lo[k]).saturating_add(1))
    });
    (lo, hi, cells)
}

/// `out` = the sorted union of the sorted, disjoint `kept` and `found`.
pub(super) fn merge_sorted<T: Ord + Copy>(kept: &[T], found: &[T], out: &mut Vec<T>) {
    out.clear();
    out.reserve(kept.len() + found.len());
    let (mut i, mut j) = (0, 0);
    while i < kept.len() && j < found.len() {
        if kept[i] < found[j] {
            out.push(kept[i]);
            i += 1;
        } else {
            out.push(found[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&kept[i..]);
    out.extend_from_slice(&found[j..]);
}
