//! Rebuilding the fat pairs from every fat box (a falling crowd, or a body that woke, slept or
//! joined): group by group where that applies (`groups`), else from the grid, its entries
//! sorted by cell, each cell's boxes swept along x on several threads and the pairs sorted;
//! then the gap bounds carried over.

use super::grid::{cell_span, fill_column, for_each_cell, sort_entries, KEY_MASK};
use super::pair_sort::{sort_pairs, IndexRuns};
use super::{gaps, BroadPhase, Budget, CellBox, CellLanes, ChunkPairs, Joined, Proxy};
use super::{CELL_FACTOR, COUNTED_SORT, LARGE_CELLS, PARALLEL_SORT, PARALLEL_SWEEP};
use crate::lanes::{Lane, LaneWidth, LaneWork, MAX_LANES};
use crate::with_lane_type;

impl BroadPhase {
    /// Refreshes every fat box and finds every fat pair: by groups where the bodies come in
    /// groups ([`BroadPhase::rebuild_by_groups`]), else from a rebuilt grid.
    pub(super) fn rebuild(&mut self) {
        self.rebuilds += 1;
        self.refresh_boxes();
        std::mem::swap(&mut self.fat_pairs, &mut self.old_pairs);
        std::mem::swap(&mut self.gaps, &mut self.old_gaps);
        let budget = Budget::new(self.pair_budget);
        self.grid_stale = !self.grid_only && self.rebuild_by_groups(&budget);
        if !self.grid_stale {
            self.enter_entries();
            self.sweep_cells(&budget);
        }
        if budget.spent() {
            // no pairs, and the next update rebuilds them
            self.fat_pairs.clear();
            self.overflows += 1;
            self.joined_changed = true;
        }
        gaps::carry(
            &self.old_pairs,
            &self.old_gaps,
            &self.fat_pairs,
            &mut self.gaps,
        );
    }

    /// The fat pairs from the grid: each cell's boxes swept on several threads, the pairs
    /// sorted.
    fn sweep_cells(&mut self, budget: &Budget) {
        let threads = rayon::current_num_threads();
        let chunks = if threads > 1 && self.entries.len() >= PARALLEL_SWEEP {
            4 * threads
        } else {
            1
        };
        self.split_chunks(chunks);
        // the sweeps hand their pairs over in runs by first index, so that each run is sorted
        // on its own, on several threads where the sweeps ran on several
        let runs = IndexRuns::new(self.proxies.len(), if chunks > 1 { 4 * threads } else { 1 });
        let proxies = &self.proxies;
        let entries = &self.entries;
        let bounds = &self.bounds;
        let joined = &self.joined;
        let width = self.lane_width;
        if chunks > 1 {
            use rayon::prelude::*;
            self.chunk_pairs[..chunks]
                .par_iter_mut()
                .enumerate()
                .for_each(|(c, out)| {
                    let entries = &entries[bounds[c]..bounds[c + 1]];
                    cell_pairs(width, entries, proxies, joined, (runs, budget), out)
                });
        } else {
            let out = &mut self.chunk_pairs[0];
            cell_pairs(width, entries, proxies, joined, (runs, budget), out);
        }
        if budget.spent() {
            return;
        }
        let parts = &self.chunk_pairs[..chunks];
        let sorted = (&mut self.fat_pairs, &mut self.merged);
        sort_pairs(parts, ChunkPairs::run, runs, sorted, &mut self.counts);
    }

    /// Fresh fat boxes, their groups, the cell edge from the movable bodies' sizes, and each
    /// box's cells (those covering too many listed as large).
    pub(super) fn refresh_boxes(&mut self) {
        let mut extent_sum = 0.0;
        let mut movable = 0;
        for (proxy, tight) in self.proxies.iter_mut().zip(&self.tight) {
            proxy.fat = tight.fattened();
            proxy.group = self.joined.group(proxy.body);
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
        for (index, proxy) in self.proxies.iter_mut().enumerate() {
            let (lo, hi, cells) = cell_span(&proxy.fat, inverse_cell);
            (proxy.low_cell, proxy.high_cell) = (lo, hi);
            proxy.large = cells > LARGE_CELLS;
            if proxy.large {
                self.large.push(index as u32);
            }
        }
    }

    /// Every small box entered in each cell it covered at the last [`Self::refresh_boxes`],
    /// sorted by cell.
    pub(super) fn enter_entries(&mut self) {
        self.grid_stale = false;
        self.entries.clear();
        // the cells the entries lie in, per axis
        let (mut low, mut high) = ([i64::MAX; 3], [i64::MIN; 3]);
        for (index, proxy) in self.proxies.iter().enumerate() {
            if proxy.large {
                continue;
            }
            let (lo, hi) = (proxy.low_cell, proxy.high_cell);
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
///
/// A box meets the boxes after it in the sweep that start before it ends along x (sorted by
/// lower x, so they overlap it along x). Those are tested W at a time in lanes: along x (the
/// first lane that starts beyond the box ends the sweep), along y and z, and the cell and flag
/// test ([`CellLanes::meeting`]). The few that pass go on to the joined filter, which looks a
/// pair up only when its bodies share a [`Joined::group`]. One candidate at a time, after a
/// binary search for the last, with every test computed to keep the loop free of branches no
/// predictor learns, the sweep cost about 8 ns per candidate. Per rebuild of the landing
/// rain's grid (rod, perf samples of the broad phase alone), the cell and flag test
/// in lanes took 14% off the sweep, and the group test about 15% more.
fn cell_pairs(
    width: LaneWidth,
    entries: &[(u64, u32)],
    proxies: &[Proxy],
    joined: &Joined,
    (runs, budget): (IndexRuns, &Budget),
    out: &mut ChunkPairs,
) {
    let work = CellPairs {
        entries,
        proxies,
        joined,
        runs,
        budget,
        out,
    };
    with_lane_type!(width, L => L::dispatch(work))
}

/// [`cell_pairs`]' arguments, run in one lane type.
struct CellPairs<'a> {
    entries: &'a [(u64, u32)],
    proxies: &'a [Proxy],
    joined: &'a Joined,
    runs: IndexRuns,
    budget: &'a Budget,
    out: &'a mut ChunkPairs,
}

impl<L: Lane> LaneWork<L> for CellPairs<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        cell_pairs_in::<L>(self)
    }
}

/// [`cell_pairs`] in lanes of `L`.
#[inline(always)]
fn cell_pairs_in<L: Lane>(work: CellPairs) {
    let (entries, proxies, joined) = (work.entries, work.proxies, work.joined);
    let (runs, budget, out) = (work.runs, work.budget, work.out);
    // (grown, never shrunk: the runs' lists keep their storage from rebuild to rebuild)
    if out.runs.len() < runs.count() {
        out.runs.resize_with(runs.count(), Vec::new);
    }
    out.runs[..runs.count()].iter_mut().for_each(Vec::clear);
    let mut unpaid = 0;
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
            let starts_here = (0..3).fold(0, |bits, k| bits | ((low[k] == here[k]) as u8) << k);
            CellBox {
                index,
                body: p.body,
                group: p.group,
                code: starts_here | p.flags.code(),
                fat: p.fat,
            }
        }));
        // the cell's boxes by their lower x, swept: a box meets only those that start
        // before it ends (a pile puts up to 80 boxes in a cell; testing all pairs was
        // most of the broad phase)
        group.sort_unstable_by(|a, b| a.fat.min[0].total_cmp(&b.fat.min[0]));
        out.lanes.fill(group);
        for (i, a) in group.iter().enumerate() {
            out.lanes.meeting::<L>(i, a.fat.max[0], |j| {
                let b = &group[j];
                // (only bodies of one group can be joined: a crowd's pairs skip the lookup)
                if a.group != b.group || !joined.contains(a.body, b.body) {
                    let (low, high) = (a.index.min(b.index), a.index.max(b.index));
                    out.runs[runs.of(low)].push((low, high));
                    unpaid += 1;
                }
            });
            if unpaid >= Budget::BATCH && !budget.take(std::mem::take(&mut unpaid)) {
                return;
            }
        }
        start = end;
    }
    budget.take(unpaid);
}

/// [`CellBox::code`]'s five bits.
pub(super) const ALL_CODE_BITS: u8 = 0b11111;

/// [`CellBox::code`]'s cell bits for a box that starts in every cell (a pair outside the grid).
pub(super) const IN_EVERY_CELL: u8 = 0b111;

/// `code` as the low mantissa bits of a float in [1, 2): the bitwise or of two such floats is
/// the float of the two codes' or, and it is [`ALL_CODE_BITS`]'s float exactly when it is at
/// least that (no code's float is larger).
#[inline]
pub(super) fn code_lane(code: u8) -> f32 {
    f32::from_bits(1.0f32.to_bits() | code as u32)
}

impl CellLanes {
    /// The sorted `group`'s bounds, then a lane width of boxes that meet nothing.
    pub(super) fn fill(&mut self, group: &[CellBox]) {
        let padded = group.len() + MAX_LANES;
        let column = |v: &mut Vec<f32>, bound: &dyn Fn(&CellBox) -> f32, pad: f32| {
            fill_column(v, group.iter().map(bound), padded, pad)
        };
        column(&mut self.x_min, &|b| b.fat.min[0], f32::INFINITY);
        column(&mut self.y_min, &|b| b.fat.min[1], f32::INFINITY);
        column(&mut self.y_max, &|b| b.fat.max[1], f32::NEG_INFINITY);
        column(&mut self.z_min, &|b| b.fat.min[2], f32::INFINITY);
        column(&mut self.z_max, &|b| b.fat.max[2], f32::NEG_INFINITY);
        column(&mut self.code, &|b| code_lane(b.code), code_lane(0));
    }

    /// Calls `meet(j)`, in order, for each box `j` after box `a` that starts along x before
    /// `a_ends` (where box `a` ends), overlaps box `a` along y and z, and makes a pair here
    /// with it: the pair is reported from the one cell holding the overlap's lower corner (per
    /// axis the larger of the two lowest cells, which is this cell's exactly when one of the
    /// boxes starts here, as both reach it), and it needs a body that moves and one that can be
    /// moved or woken. Their codes together set all five bits ([`CellBox::code`]); tested in
    /// the lanes, as a branch per box it was mispredicted about every other time.
    #[inline(always)]
    pub(super) fn meeting<L: Lane>(&self, a: usize, a_ends: f32, mut meet: impl FnMut(usize)) {
        let x_max = L::splat(a_ends);
        let (y_min, y_max) = (L::splat(self.y_min[a]), L::splat(self.y_max[a]));
        let (z_min, z_max) = (L::splat(self.z_min[a]), L::splat(self.z_max[a]));
        let (code, all_codes) = (L::splat(self.code[a]), L::splat(code_lane(ALL_CODE_BITS)));
        let all = u32::MAX >> (32 - L::W);
        let mut base = a + 1;
        loop {
            // sorted by lower x: the lanes that start in time are a prefix
            let started = L::load(&self.x_min[base..]).le(x_max).bitmask();
            let overlap = L::load(&self.y_min[base..]).le(y_max)
                & y_min.le(L::load(&self.y_max[base..]))
                & L::load(&self.z_min[base..]).le(z_max)
                & z_min.le(L::load(&self.z_max[base..]))
                & all_codes.le(L::load(&self.code[base..]) | code);
            let mut bits = overlap.bitmask() & started;
            while bits != 0 {
                meet(base + bits.trailing_zeros() as usize);
                bits &= bits - 1;
            }
            if started != all {
                return;
            }
            base += L::W;
        }
    }
}
