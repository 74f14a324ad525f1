//! The grid and the kept pairs after a few bodies got new fat boxes (the settled rain moves
//! 50-90 of its 11 000 bodies a step): their entries and pairs replaced, the rest copied
//! in runs.

use super::grid::{cell_span, for_each_cell, key, merge_kept, Run};
use super::{gaps, BroadPhase, LARGE_CELLS, REBUILD_MOVED};

impl BroadPhase {
    /// The grid and the fat pairs after the bodies in `moved` got new fat boxes: their grid
    /// entries replaced by their new cells, their pairs dropped and found again through the
    /// grid (a pair of two moved bodies from the lower one). Returns false, with the pairs
    /// unchanged, when they should be rebuilt instead: more than [`REBUILD_MOVED`] of the
    /// bodies moved, a box grew too large for the grid, or the moved bodies' pairs pass the
    /// pair budget (the rebuild stops at it).
    pub(super) fn update_moved(&mut self) -> bool {
        if self.moved.len() > (self.proxies.len() / REBUILD_MOVED).max(64) {
            return false;
        }
        let inverse_cell = self.inverse_cell;
        for &m in &self.moved {
            let p = &self.proxies[m as usize];
            if !p.large && cell_span(&p.fat, inverse_cell).2 > LARGE_CELLS {
                return false; // grown too large for the grid
            }
        }
        if self.grid_stale {
            self.enter_entries();
        }
        // the grid: the entries of the moved bodies whose fat boxes changed cells out, their
        // new cells in (one merge; most new fat boxes of a settled pile keep their cells, and
        // then the grid's 30 000 entries are not copied)
        let proxies = &mut self.proxies;
        self.found_entries.clear();
        self.recelled.clear();
        for &m in &self.moved {
            let p = &mut proxies[m as usize];
            if p.large {
                continue; // the large pass tests it every step
            }
            let (lo, hi, _) = cell_span(&p.fat, inverse_cell);
            if (lo, hi) == (p.low_cell, p.high_cell) {
                continue;
            }
            (p.low_cell, p.high_cell) = (lo, hi);
            self.recelled.push(m);
            let found = &mut self.found_entries;
            for_each_cell(lo, hi, |cell| found.push((cell, m)));
        }
        if !self.recelled.is_empty() {
            self.found_entries.sort_unstable();
            self.moved_bits.set(self.proxies.len(), &self.recelled);
            let recelled = &self.moved_bits;
            let (entries, found) = (&self.entries, &self.found_entries);
            let kept = |&(_, i): &(u64, u32)| !recelled.get(i);
            merge_kept(entries, kept, found, &mut self.merged_entries, |_| {});
            std::mem::swap(&mut self.entries, &mut self.merged_entries);
        }
        self.moved_bits.set(self.proxies.len(), &self.moved);
        // the pairs: the moved bodies' dropped, found again in their new cells, the cells
        // looked up in key order, each from where the last was found (a binary search over
        // the grid per cell was a third of this update)
        let proxies = &self.proxies;
        self.queries.clear();
        for &m in &self.moved {
            let a = &proxies[m as usize];
            if a.large {
                continue;
            }
            // its cells, entered just above when they changed
            let queries = &mut self.queries;
            for_each_cell(a.low_cell, a.high_cell, |cell| queries.push((cell, m)));
        }
        self.queries.sort_unstable();
        self.found.clear();
        let mut first = 0;
        for &(cell, m) in &self.queries {
            first = gallop(&self.entries, first, cell);
            let a = &proxies[m as usize];
            for &(k, i) in &self.entries[first..] {
                if k != cell {
                    break;
                }
                let b = &proxies[i as usize];
                // not itself, not a moved body that reports the pair (the lower one), may touch
                // and overlaps: tested together, as most candidates fail one test or another
                let overlap = a.fat.overlaps_all_tested(&b.fat);
                let reported_by_b = b.moved & (i < m);
                if !(overlap & (i != m) & !reported_by_b & a.flags.may_touch(b.flags)) {
                    continue;
                }
                // reported from the cell of the overlap's lower corner only
                let corner = [0, 1, 2].map(|k| a.low_cell[k].max(b.low_cell[k]));
                if key(corner) == cell && !self.joined.contains(a.body, b.body) {
                    self.found.push((m.min(i), m.max(i)));
                }
            }
            if self.found.len() > self.pair_budget {
                return false; // the rebuild stops at the budget
            }
        }
        // kept pairs keep their bounds, found ones start unknown (one merge)
        self.found.sort_unstable();
        let moved = &self.moved_bits;
        let kept = |&(a, b): &(u32, u32)| !(moved.get(a) || moved.get(b));
        let (pairs, bounds) = (&self.fat_pairs, &self.gaps);
        let new_bounds = &mut self.old_gaps;
        new_bounds.clear();
        merge_kept(
            pairs,
            kept,
            &self.found,
            &mut self.merged,
            |run| match run {
                Run::Old(range) => new_bounds.extend_from_slice(&bounds[range]),
                Run::Found => new_bounds.push(gaps::UNKNOWN),
            },
        );
        std::mem::swap(&mut self.fat_pairs, &mut self.merged);
        std::mem::swap(&mut self.gaps, &mut self.old_gaps);
        true
    }
}

/// The first place at or after `from` in the sorted `entries` whose key is not below `cell`:
/// a doubling search from `from`, then a binary search in the last step's span (the cells
/// looked up in key order are mostly near each other).
pub(super) fn gallop(entries: &[(u64, u32)], from: usize, cell: u64) -> usize {
    let mut step = 1;
    while from + step < entries.len() && entries[from + step].0 < cell {
        step *= 2;
    }
    let (low, high) = (from + step / 2, (from + step + 1).min(entries.len()));
    let low = low.min(high);
    low + entries[low..high].partition_point(|&(k, _)| k < cell)
}
