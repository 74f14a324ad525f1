//! Rebuilding the grid from every fat box (a falling crowd, or a body that woke, slept or
//! joined): the entries sorted by cell, each cell's boxes swept along x on several threads, the
//! pairs sorted and their gap bounds carried over.

use super::grid::{cell_span, for_each_cell, sort_entries, sort_pairs, KEY_MASK};
use super::{gaps, BroadPhase, CellBox, ChunkPairs, Joined, Proxy};
use super::{CELL_FACTOR, COUNTED_SORT, LARGE_CELLS, PARALLEL_SORT};

impl BroadPhase {
    /// Rebuilds the grid from the fat boxes and finds every fat pair.
    pub(super) fn rebuild(&mut self) {
        self.rebuilds += 1;
        self.enter_cells();
        let threads = rayon::current_num_threads();
        let chunks = if threads > 1 && self.entries.len() >= PARALLEL_SORT {
            4 * threads
        } else {
            1
        };
        self.split_chunks(chunks);
        let proxies = &self.proxies;
        let entries = &self.entries;
        let bounds = &self.bounds;
        let joined = &self.joined;
        if chunks > 1 {
            use rayon::prelude::*;
            self.chunk_pairs[..chunks]
                .par_iter_mut()
                .enumerate()
                .for_each(|(c, out)| {
                    cell_pairs(&entries[bounds[c]..bounds[c + 1]], proxies, joined, out)
                });
        } else {
            cell_pairs(entries, proxies, joined, &mut self.chunk_pairs[0]);
        }
        std::mem::swap(&mut self.fat_pairs, &mut self.old_pairs);
        std::mem::swap(&mut self.gaps, &mut self.old_gaps);
        self.fat_pairs.clear();
        for out in &self.chunk_pairs[..chunks] {
            self.fat_pairs.extend_from_slice(&out.pairs);
        }
        let n = self.proxies.len();
        sort_pairs(&mut self.fat_pairs, n, &mut self.merged, &mut self.counts);
        gaps::carry(
            &self.old_pairs,
            &self.old_gaps,
            &self.fat_pairs,
            &mut self.gaps,
        );
    }

    /// Fresh fat boxes, the cell edge from the movable bodies' sizes, and every small box
    /// entered in each cell it covers (large ones listed apart), sorted by cell.
    fn enter_cells(&mut self) {
        let mut extent_sum = 0.0;
        let mut movable = 0;
        for (proxy, tight) in self.proxies.iter_mut().zip(&self.tight) {
            proxy.fat = tight.fattened();
            if proxy.flags.active || proxy.flags.dynamic {
                let half = (0..3).map(|k| proxy.fat.max[k] - proxy.fat.min[k]);
                extent_sum += 0.5 * half.fold(0.0, f32::max);
                movable += 1;
            }
        }
        let cell = CELL_FACTOR * extent_sum / movable.max(1) as f32;
        let inverse_cell = 1.0 / cell;
        self.inverse_cell = inverse_cell;

        self.large.clear();
        self.entries.clear();
        // the cells the entries lie in, per axis
        let (mut low, mut high) = ([i64::MAX; 3], [i64::MIN; 3]);
        for (index, proxy) in self.proxies.iter_mut().enumerate() {
            let (lo, hi, cells) = cell_span(&proxy.fat, inverse_cell);
            (proxy.low_cell, proxy.high_cell) = (lo, hi);
            proxy.large = cells > LARGE_CELLS;
            if proxy.large {
                self.large.push(index as u32);
                continue;
            }
            for k in 0..3 {
                (low[k], high[k]) = (low[k].min(lo[k]), high[k].max(hi[k]));
            }
            let entries = &mut self.entries;
            for_each_cell(lo, hi, |cell| entries.push((cell, index as u32)));
        }
        // (cell, proxy) entries are unique, so any sort gives the same order: one counting pass
        // over the cells for large worlds (about 33 000 entries in the 1000-ragdoll rain) whose
        // cells are not too spread out, else a comparison sort (parallel when large)
        let (scratch, counts) = (&mut self.merged_entries, &mut self.counts);
        let counted = self.entries.len() >= COUNTED_SORT
            && sort_entries(&mut self.entries, (low, high), scratch, counts);
        if !counted && self.entries.len() >= PARALLEL_SORT && rayon::current_num_threads() > 1 {
            use rayon::slice::ParallelSliceMut;
            self.entries.par_sort_unstable();
        } else if !counted {
            self.entries.sort_unstable();
        }
    }

    /// Splits the sorted entries into `chunks` runs at cell boundaries, a pair buffer each.
    fn split_chunks(&mut self, chunks: usize) {
        // chunk boundaries moved forward to the next cell start
        self.bounds.clear();
        self.bounds.push(0);
        for c in 1..chunks {
            let mut at = (self.entries.len() * c / chunks).max(*self.bounds.last().unwrap());
            while at > 0 && at < self.entries.len() && self.entries[at].0 == self.entries[at - 1].0
            {
                at += 1;
            }
            self.bounds.push(at);
        }
        self.bounds.push(self.entries.len());
        if self.chunk_pairs.len() < chunks {
            self.chunk_pairs.resize_with(chunks, ChunkPairs::default);
        }
    }
}

/// The pairs of one run of `entries` (whole cells): each cell's boxes swept along x, each
/// overlapping pair not `joined` reported by the cell holding its overlap's lower corner.
fn cell_pairs(entries: &[(u64, u32)], proxies: &[Proxy], joined: &Joined, out: &mut ChunkPairs) {
    out.pairs.clear();
    let mut start = 0;
    while start < entries.len() {
        let cell_key = entries[start].0;
        let mut end = start + 1;
        while end < entries.len() && entries[end].0 == cell_key {
            end += 1;
        }
        // the cell's coordinates as the key holds them (each masked to 21 bits)
        let here = [42, 21, 0].map(|shift| (cell_key >> shift) & KEY_MASK);
        let group = &mut out.group;
        group.clear();
        group.extend(entries[start..end].iter().map(|&(_, index)| {
            let p = &proxies[index as usize];
            let low = p.low_cell.map(|c| c as u64 & KEY_MASK);
            CellBox {
                index,
                body: p.body,
                flags: p.flags,
                starts_here: (0..3).fold(0, |bits, k| bits | ((low[k] == here[k]) as u8) << k),
                fat: p.fat,
            }
        }));
        // the cell's boxes by their lower x, swept: a box meets only those that start
        // before it ends (a pile puts up to 80 boxes in a cell; testing all pairs was
        // most of the broad phase)
        group.sort_unstable_by(|a, b| a.fat.min[0].total_cmp(&b.fat.min[0]));
        for (i, a) in group.iter().enumerate() {
            // the boxes that start before a ends, each written as a pair and kept (the length
            // moved on) where it is one: without a branch per box, whose outcome no predictor
            // learns (half the rain's landing-frame broad phase went on mispredictions)
            let rest = &group[i + 1..];
            let reach = rest.partition_point(|b| b.fat.min[0] <= a.fat.max[0]);
            let first = out.pairs.len();
            out.pairs.resize(first + reach, (0, 0));
            out.bodies.resize(reach, 0);
            let mut kept = 0;
            for b in &rest[..reach] {
                // reported from the one cell holding the overlap's lower corner: per axis the
                // larger of the two lowest cells, which is this cell's exactly when one of the
                // boxes starts here (both reach it)
                let here = a.starts_here | b.starts_here == 0b111;
                let pair = here & a.flags.may_touch(b.flags) & a.fat.overlaps_branchless(&b.fat);
                out.pairs[first + kept] = (a.index.min(b.index), a.index.max(b.index));
                out.bodies[kept] = b.body;
                kept += pair as usize;
            }
            // the joined ones out (a handful)
            let mut written = first;
            for k in 0..kept {
                if !joined.contains(a.body, out.bodies[k]) {
                    out.pairs[written] = out.pairs[first + k];
                    written += 1;
                }
            }
            out.pairs.truncate(written);
        }
        start = end;
    }
}
