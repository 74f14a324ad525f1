//! The grid's geometry: boxes, cell coordinates and keys, the merge of sorted lists, and the
//! moved proxies' bits.

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

    /// [`Self::overlaps`] with all six tests made, for loops where most boxes fail one of them
    /// at random, so a branch per test is mispredicted.
    #[inline]
    pub(super) fn overlaps_all_tested(&self, other: &Aabb) -> bool {
        (0..3).fold(true, |all, k| {
            all & (self.min[k] <= other.max[k]) & (other.min[k] <= self.max[k])
        })
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

/// Each cell coordinate's bits in a [`key`].
pub(super) const KEY_MASK: u64 = (1 << 21) - 1;

/// Packs three cell coordinates (each within +-2^20) into one sortable key.
pub(super) fn key(cell: [i64; 3]) -> u64 {
    let field = |c: i64| c as u64 & KEY_MASK;
    (field(cell[0]) << 42) | (field(cell[1]) << 21) | field(cell[2])
}

/// Calls `each` with the key of every cell `lo..=hi` (per axis), x slowest and z fastest.
#[inline]
pub(super) fn for_each_cell(lo: [i64; 3], hi: [i64; 3], mut each: impl FnMut(u64)) {
    for x in lo[0]..=hi[0] {
        for y in lo[1]..=hi[1] {
            for z in lo[2]..=hi[2] {
                each(key([x, y, z]));
            }
        }
    }
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

/// Where a run of [`merge_kept`]'s output came from.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Run {
    /// The items `old[range]`, in order.
    Old(std::ops::Range<usize>),
    /// One found item.
    Found,
}

/// `out` = the sorted union of the items of the sorted `old` for which `keep` holds and the
/// sorted `found` (disjoint from the kept ones), copied a run at a time: each run of kept
/// items between two dropped ones is copied whole, split only where a found item goes. `runs`
/// is told, in `out`'s order, where each run came from. A settled pile drops and finds a few
/// hundred of its 70 000 pairs a step, so nearly all of the output is a few long copies (an
/// item at a time, with a test and a branch each, it was a twelfth of the settled rain's
/// detection).
pub(super) fn merge_kept<T: Ord + Copy>(
    old: &[T],
    keep: impl Fn(&T) -> bool,
    found: &[T],
    out: &mut Vec<T>,
    mut runs: impl FnMut(Run),
) {
    out.clear();
    out.reserve(old.len() + found.len());
    let mut found = found.iter().peekable();
    let mut start = 0;
    while start < old.len() {
        let end = old[start..]
            .iter()
            .position(|item| !keep(item))
            .map_or(old.len(), |k| start + k);
        // the kept run old[start..end], with the found items that fall inside it; a found item
        // past its last item goes into a later run or after all
        let mut from = start;
        while from < end {
            let at = match found.peek() {
                Some(&&f) if f < old[end - 1] => from + old[from..end].partition_point(|x| *x < f),
                _ => end,
            };
            if at > from {
                out.extend_from_slice(&old[from..at]);
                runs(Run::Old(from..at));
            }
            if at < end {
                out.push(*found.next().expect("peeked"));
                runs(Run::Found);
            }
            from = at;
        }
        start = end + 1;
    }
    for &f in found {
        out.push(f);
        runs(Run::Found);
    }
}

/// `column` = `values`, then `pad` up to `len` (a column of lanes, padded by a lane width of
/// boxes that meet nothing).
pub(super) fn fill_column(
    column: &mut Vec<f32>,
    values: impl Iterator<Item = f32>,
    len: usize,
    pad: f32,
) {
    column.clear();
    column.extend(values);
    column.resize(len, pad);
}

/// Sorts the grid's `(cell key, proxy)` entries as `sort_unstable` would (they are distinct)
/// by one stable counting pass over their cells, numbered in key order, when the cells the
/// entries lie in (`low..=high` per axis) are at most a few per entry; returns false, with
/// nothing done, otherwise. Within a cell the entries must come in proxy order, as
/// `enter_cells` writes them. The landing rain's rebuilds sort 33 000 entries, which took
/// 0.6 ms on two threads with the comparison sort. `scratch` and `counts` are reused storage.
pub(super) fn sort_entries(
    entries: &mut Vec<(u64, u32)>,
    (low, high): ([i64; 3], [i64; 3]),
    scratch: &mut Vec<(u64, u32)>,
    counts: &mut Vec<u32>,
) -> bool {
    let size = |k: usize| (high[k] - low[k] + 1).max(1) as u64;
    let cells = size(0).saturating_mul(size(1)).saturating_mul(size(2));
    if cells > 4 * entries.len() as u64 + 1024 {
        return false;
    }
    // an axis's key field is its cell coordinate masked: a span across 0 is two runs of field
    // values, the non-negative cells first
    let rank = |key: u64, k: usize| {
        let field = key >> (42 - 21 * k) & KEY_MASK;
        let (first, last) = (low[k] as u64 & KEY_MASK, high[k] as u64 & KEY_MASK);
        match (first <= last, field <= last) {
            (true, _) => field - first,
            (false, true) => field,
            (false, false) => field - first + last + 1,
        }
    };
    let cell = |&(key, _): &(u64, u32)| {
        ((rank(key, 0) * size(1) + rank(key, 1)) * size(2) + rank(key, 2)) as usize
    };
    counts.clear();
    counts.resize(cells as usize + 1, 0);
    for entry in entries.iter() {
        counts[cell(entry) + 1] += 1;
    }
    for c in 0..cells as usize {
        counts[c + 1] += counts[c];
    }
    scratch.clear();
    scratch.resize(entries.len(), (0, 0));
    for entry in entries.iter() {
        let at = &mut counts[cell(entry)];
        scratch[*at as usize] = *entry;
        *at += 1;
    }
    std::mem::swap(entries, scratch);
    true
}

/// One bit per proxy: which moved this step (a few hundred of 11 000 in a settled pile), read
/// for every grid entry and pair; 1.4 kB for the rain's bodies, where the proxies' own flags
/// are 0.7 MB apart.
#[derive(Clone, Debug, Default)]
pub(super) struct Bits(Vec<u64>);

impl Bits {
    /// Sets the bits of `indices`, all others clear, for `len` proxies.
    pub(super) fn set(&mut self, len: usize, indices: &[u32]) {
        self.0.clear();
        self.0.resize(len.div_ceil(64), 0);
        for &i in indices {
            self.0[i as usize / 64] |= 1 << (i % 64);
        }
    }

    #[inline]
    pub(super) fn get(&self, i: u32) -> bool {
        self.0[i as usize / 64] >> (i % 64) & 1 != 0
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A xorshift generator of integers below its argument.
    pub(in crate::contact::broadphase) fn xorshift(mut state: u64) -> impl FnMut(u64) -> u64 {
        move |n| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % n
        }
    }

    /// Each output item's source, `Some(i)` for `old[i]`, `None` for a found one.
    fn merge_sources<T: Ord + Copy>(
        old: &[T],
        keep: impl Fn(&T) -> bool,
        found: &[T],
        out: &mut Vec<T>,
    ) -> Vec<Option<usize>> {
        let mut from = Vec::new();
        merge_kept(old, keep, found, out, |run| match run {
            Run::Old(range) => from.extend(range.map(Some)),
            Run::Found => from.push(None),
        });
        from
    }

    #[test]
    fn merge_kept_drops_the_unkept_merges_the_found_and_says_where_each_came_from() {
        let old = [1, 3, 4, 7, 9];
        let mut out = Vec::new();
        let from = merge_sources(&old, |&x| x != 4 && x != 9, &[0, 5, 10, 11], &mut out);
        assert_eq!(out, [0, 1, 3, 5, 7, 10, 11]);
        let (some, none) = (Some, None::<usize>);
        assert_eq!(from, [none, some(0), some(1), none, some(3), none, none]);
        merge_sources(&old, |_| true, &[], &mut out);
        assert_eq!(out, old);
    }

    /// Against the item-by-item merge, on random lists: found items inside runs, between
    /// them, equal to dropped items, before and after all.
    #[test]
    fn merge_kept_in_runs_is_the_item_by_item_merge() {
        let mut next = xorshift(7u64);
        for _ in 0..200 {
            let mut old: Vec<u32> = (0..next(60)).map(|_| next(100) as u32).collect();
            old.sort_unstable();
            old.dedup();
            let dropped = next(7) as u32 + 2;
            let keep = |x: &u32| !x.is_multiple_of(dropped);
            let mut found: Vec<u32> = (0..next(12)).map(|_| next(110) as u32).collect();
            found.retain(|f| !old.iter().any(|o| o == f && keep(o)));
            found.sort_unstable();
            found.dedup();
            let mut expected: Vec<(u32, Option<usize>)> = (old.iter().enumerate())
                .filter(|(_, x)| keep(x))
                .map(|(i, &x)| (x, Some(i)))
                .chain(found.iter().map(|&f| (f, None)))
                .collect();
            expected.sort_unstable_by_key(|&(x, _)| x);
            let mut out = Vec::new();
            let from = merge_sources(&old, keep, &found, &mut out);
            let got: Vec<(u32, Option<usize>)> = out.into_iter().zip(from).collect();
            assert_eq!(
                got, expected,
                "old {old:?} found {found:?} dropping multiples of {dropped}"
            );
        }
    }

    /// Boxes over cells on both sides of 0 on every axis, entered as `enter_cells` enters
    /// them: the counting sort gives the comparison sort's order.
    #[test]
    fn sort_entries_orders_as_the_comparison_sort() {
        let mut next = xorshift(99u64);
        let mut entries = Vec::new();
        let (mut low, mut high) = ([i64::MAX; 3], [i64::MIN; 3]);
        for index in 0..3000u32 {
            let lo = [0, 1, 2].map(|_| next(40) as i64 - 20);
            let hi = lo.map(|c| c + next(3) as i64);
            for k in 0..3 {
                (low[k], high[k]) = (low[k].min(lo[k]), high[k].max(hi[k]));
            }
            for_each_cell(lo, hi, |cell| entries.push((cell, index)));
        }
        let mut sorted = entries.clone();
        sorted.sort_unstable();
        let (mut scratch, mut counts) = (Vec::new(), Vec::new());
        assert!(sort_entries(
            &mut entries,
            (low, high),
            &mut scratch,
            &mut counts
        ));
        assert_eq!(entries, sorted);
        // cells spread far apart: left to the comparison sort
        let far = ([0, 0, 0], [1 << 18, 1 << 18, 0]);
        assert!(!sort_entries(&mut entries, far, &mut scratch, &mut counts));
    }

    #[test]
    fn bits_hold_exactly_the_indices_set() {
        let mut bits = Bits::default();
        bits.set(130, &[0, 63, 64, 129]);
        let set: Vec<u32> = (0..130).filter(|&i| bits.get(i)).collect();
        assert_eq!(set, [0, 63, 64, 129]);
        bits.set(70, &[5]);
        assert_eq!((0..70).filter(|&i| bits.get(i)).count(), 1);
    }
}
