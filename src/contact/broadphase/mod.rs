//! Broad phase: a uniform grid of fat boxes, rebuilt by sorting only when many bodies have moved
//! (Box2D's fat AABBs, over a grid instead of a tree).
//!
//! Each finite body gets its tightest world axis-aligned box ([`Shape::world_half_extents`]: a
//! limb lying down is a long thin box, not the cube around its bounding sphere, which on the
//! 1000-ragdoll rain gave 2.6 times the candidate pairs), grown by the distance it may travel
//! this step and the contact margin. Around it the body keeps a fat box, [`FAT_MARGIN`] larger
//! on every side, which stays put while the tight box stays inside it. Pairs of overlapping fat
//! boxes are kept from step to step; each step reports those whose tight boxes overlap. A body
//! whose tight box leaves its fat box gets a new fat box ("moved"): its grid entries are
//! replaced by the new box's cells, and its pairs are dropped and found again by querying the
//! grid with the new box (each list in one merge pass, which drops the moved bodies' old items,
//! read from a bitset, and merges the new ones in sorted).
//! A settled pile moves a few hundred bodies a step, so its broad phase costs the box updates
//! and the report. Once more than a sixteenth of the bodies move in one step (a falling
//! crowd), or a body wakes, sleeps or joins, the grid is rebuilt instead, its sweeps on several
//! threads (before, moved bodies were left stale in the grid and tested one by one against
//! each other, and the grid was rebuilt once a sixteenth had moved since the last rebuild:
//! every third or fourth step in the settled rain, 7.5 ms each on one thread; a quarter
//! measured no better on two threads, where the update runs on one):
//!
//! The cell edge is four times the mean largest fat-box half-size of the movable bodies (2, 3,
//! 6 and 8 times were measured slower on the rain), so a limb covers one to eight cells. Every
//! body is entered once per cell its fat box touches, as a `(cell key, body)` entry; sorting
//! the entries groups each cell's bodies, and each group is swept along x (sorted by lower x,
//! each box tested against those starting before it ends). A pair is reported only from the
//! cell that holds the lower corner of the two boxes' overlap, so it is reported once. Boxes
//! covering more than `LARGE_CELLS` (1024) cells are kept apart and tested against every
//! other box each step, which costs `large x n`. Half-spaces are unbounded: each is paired
//! with the dynamic bodies whose tight box reaches below its plane.
//!
//! Large worlds sort the entries and walk the cells on several threads: the cells are split into
//! chunks at cell boundaries, each chunk's pairs into a reused buffer. The kept pairs are sorted
//! by body (two counting passes, `grid::sort_pairs`), so the pairs and their order depend
//! neither on the thread count nor on when the grid was rebuilt (tested).
//!
//! Cost of a rebuild: a sort of about `8 n` entries plus the pairs in each cell, so it grows
//! about linearly with the number of bodies for any layout where bodies do not all crowd into
//! a few cells (see the `contact_detection` benchmark). A one-axis sweep, which this replaced,
//! grows as `n^1.5` on a square floor of ragdolls.
//!
//! Each kept pair also carries a lower bound on its shapes' distance ([`gaps`]), so the narrow
//! phase can skip pairs whose boxes overlap but whose shapes are proven out of reach.

pub mod gaps;
mod grid;
mod joined;
mod report;
#[cfg(test)]
mod tests;

use super::collider::{Collider, PARALLEL_BODIES};
use crate::body::BodyKind;
use crate::math::Vec3;
use crate::shape::Shape;
use grid::{cell_span, key, merge_kept, sort_entries, sort_pairs, Aabb, Bits, Run, KEY_MASK};
pub use joined::Joined;

/// How much larger than its tight box (m, each side) a body's fat box is: a body resting or
/// swinging by a few centimetres keeps its fat box, and its pairs, for many steps.
pub const FAT_MARGIN: f32 = 0.02;

/// What the broad phase keeps of a body between steps.
#[derive(Clone, Copy, Debug, Default)]
struct Proxy {
    body: u32,
    flags: Flags,
    /// Kept out of the grid (covers more than [`LARGE_CELLS`] cells at the last rebuild).
    large: bool,
    /// Its fat box changed this step.
    moved: bool,
    /// The fat box, which contains this step's tight box.
    fat: Aabb,
    /// The cells of the fat box's lower and upper corners, as entered in the grid.
    low_cell: [i64; 3],
    high_cell: [i64; 3],
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Flags {
    /// [`Body::moves_this_step`].
    active: bool,
    /// A dynamic body, awake or asleep: something a contact can move or wake.
    dynamic: bool,
}

impl Flags {
    /// A pair needs a body that moves and a body that can be moved or woken: no pairs inside
    /// a sleeping island or between sleeping and static bodies.
    fn may_touch(self, other: Flags) -> bool {
        (self.active || other.active) && (self.dynamic || other.dynamic)
    }
}

/// A fat box in a cell's sweep: compact, so a crowded cell's boxes stay in cache.
#[derive(Clone, Copy, Debug)]
struct CellBox {
    index: u32,
    body: u32,
    flags: Flags,
    /// Bit k: the box's lowest cell along axis k is this cell's (see [`cell_pairs`]).
    starts_here: u8,
    fat: Aabb,
}

/// More than one in `REBUILD_MOVED` of the bodies getting new fat boxes in a step rebuilds
/// the grid instead of updating it body by body (a falling crowd).
const REBUILD_MOVED: usize = 16;

/// Entries from which the sort runs on several threads.
const PARALLEL_SORT: usize = 32_768;

/// Entries from which the grid is sorted by counting over its cells ([`sort_entries`]).
const COUNTED_SORT: usize = 4096;

/// The grid's cell edge over the movable bodies' mean largest box half-size (measured on the
/// 1000-ragdoll rain: 3 to 6 within a few per cent of each other).
const CELL_FACTOR: f32 = 4.0;

/// A box covering more than this many cells goes to the large list, tested against every
/// other box. Below it a box is entered in each cell: the rain's walls, stairs and ramps (up
/// to about 150 cells each) cost a few hundred entries instead of a test against all 15 000
/// limbs each.
const LARGE_CELLS: i64 = 1024;

/// One chunk of cells' output, and its scratch copy of a cell's boxes.
#[derive(Clone, Debug, Default)]
struct ChunkPairs {
    pairs: Vec<(u32, u32)>,
    /// Scratch: the second bodies of one box's pairs in a cell.
    bodies: Vec<u32>,
    group: Vec<CellBox>,
}

/// Reused storage, so the step does not allocate once warmed up.
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    proxies: Vec<Proxy>,
    /// Each proxy's tight box this step (apart: the report reads only these).
    tight: Vec<Aabb>,
    half_spaces: Vec<u32>,
    /// Indices into `proxies` of the boxes covering more than [`LARGE_CELLS`] cells.
    large: Vec<u32>,
    /// `(cell key, proxy index)` of the fat boxes at the last rebuild, sorted by key.
    entries: Vec<(u64, u32)>,
    /// The cell edge's inverse at the last rebuild.
    inverse_cell: f32,
    /// Where each chunk of `entries` starts (at a cell boundary), and each chunk's pairs.
    bounds: Vec<usize>,
    chunk_pairs: Vec<ChunkPairs>,
    /// Proxy index pairs (lower first) of overlapping fat boxes that may touch, sorted.
    fat_pairs: Vec<(u32, u32)>,
    /// Each fat pair's lower bound on its shapes' distance ([`gaps`]).
    gaps: Vec<f32>,
    /// Scratch: the fat pairs and bounds before a rebuild or merge, to carry the bounds over.
    old_pairs: Vec<(u32, u32)>,
    old_gaps: Vec<f32>,
    /// Scratch: the pairs found for the bodies moved this step, and the merge (also the pair
    /// sort's); the pair sort's counts.
    found: Vec<(u32, u32)>,
    merged: Vec<(u32, u32)>,
    counts: Vec<u32>,
    /// Proxies moved this step (ascending), and as bits; those of them whose fat boxes changed
    /// cells.
    moved: Vec<u32>,
    recelled: Vec<u32>,
    moved_bits: Bits,
    /// Scratch: the moved proxies' new grid entries, and the merge.
    found_entries: Vec<(u64, u32)>,
    /// Scratch: the cells the moved proxies' fat boxes cover, `(cell key, proxy)`, sorted.
    queries: Vec<(u64, u32)>,
    merged_entries: Vec<(u64, u32)>,
    /// Body pairs never paired ([`Joined`]), and whether they changed since the last rebuild.
    joined: Joined,
    joined_changed: bool,
    /// Grid rebuilds so far (a settled world rebuilds rarely).
    pub rebuilds: u64,
}

impl BroadPhase {
    /// Calls `pair(a, b)` for every candidate pair (a < b in the world's order for finite pairs;
    /// the half-space first for half-space pairs). At least one body of each pair is dynamic,
    /// and one moves (awake dynamic, or kinematic with a velocity). The same as [`Self::update`],
    /// then [`Self::report_kept`] over all kept pairs and [`Self::report_others`].
    pub fn find_pairs(
        &mut self,
        bodies: &[Collider],
        dt: f32,
        margin: f32,
        mut pair: impl FnMut(u32, u32),
    ) {
        if self.update(bodies, dt, margin) {
            self.report_kept(0..self.kept_len(), &mut pair);
            self.report_others(bodies, &mut pair);
        }
    }

    /// Sets the body pairs that are never paired (joined by a joint or rod); the next
    /// [`Self::update`] rebuilds the kept pairs without them.
    pub fn set_joined(&mut self, joined: Joined) {
        self.joined = joined;
        self.joined_changed = true;
    }

    /// Whether bodies `a` and `b` are never paired ([`Self::set_joined`]).
    pub fn joined(&self, a: u32, b: u32) -> bool {
        self.joined.contains(a, b)
    }

    /// Brings the fat boxes and the kept pairs up to this step's bodies. Returns false when
    /// nothing moves (then there are no pairs).
    pub fn update(&mut self, bodies: &[Collider], dt: f32, margin: f32) -> bool {
        let mut rebuild = std::mem::take(&mut self.joined_changed);
        if self.proxies.len() + self.half_spaces.len() != bodies.len() {
            self.fat_pairs.clear(); // indices into the old proxies: their bounds mean nothing now
            self.gaps.clear();
            self.proxies.clear();
            self.half_spaces.clear();
            for (i, body) in bodies.iter().enumerate() {
                if matches!(body.shape, Shape::HalfSpace) {
                    self.half_spaces.push(i as u32);
                } else {
                    self.proxies.push(Proxy {
                        body: i as u32,
                        ..Default::default()
                    });
                }
            }
            rebuild = true;
        }
        self.tight.resize(self.proxies.len(), Aabb::default());
        let boxes = |(proxy, tight): (&mut Proxy, &mut Aabb)| {
            let body = &bodies[proxy.body as usize];
            // grown by how far the fastest surface point may travel this frame, spin included
            let grow = margin + dt * (body.linear_velocity.length() + body.spin_bound);
            let half = body.world_half_extents() + Vec3::splat(grow);
            *tight = Aabb {
                min: (body.position - half).to_array(),
                max: (body.position + half).to_array(),
            };
            let flags = Flags {
                active: body.moves,
                dynamic: body.kind == BodyKind::Dynamic,
            };
            // a body that wakes or sleeps changes which pairs may touch
            let changed = flags != proxy.flags;
            proxy.flags = flags;
            proxy.moved = !proxy.fat.holds_snugly(tight);
            if proxy.moved {
                proxy.fat = tight.fattened();
            }
            (changed, (body.kind != BodyKind::Fixed) as usize)
        };
        let either = |(c, m): (bool, usize), (d, n): (bool, usize)| (c || d, m + n);
        let parallel = self.proxies.len() >= PARALLEL_BODIES && rayon::current_num_threads() > 1;
        let (changed, movable) = if parallel {
            use rayon::prelude::*;
            let each = self.proxies.par_iter_mut().zip(&mut self.tight);
            each.map(boxes).reduce(|| (false, 0), either)
        } else {
            let each = self.proxies.iter_mut().zip(&mut self.tight);
            each.map(boxes).fold((false, 0), either)
        };
        rebuild |= changed;
        self.moved.clear();
        let moved = (0..).zip(&self.proxies).filter(|(_, p)| p.moved);
        self.moved.extend(moved.map(|(i, _)| i));
        if movable == 0 {
            return false; // nothing moves: no pair can change
        }
        if !rebuild && !self.moved.is_empty() {
            rebuild = !self.update_moved();
        }
        if rebuild {
            self.rebuild();
        }
        true
    }

    /// The grid and the fat pairs after the bodies in `moved` got new fat boxes: their grid
    /// entries replaced by their new cells, their pairs dropped and found again through the
    /// grid (a pair of two moved bodies from the lower one). Returns false, with nothing
    /// changed, when the grid should be rebuilt instead: more than [`REBUILD_MOVED`] of the
    /// bodies moved, or a box grew too large for the grid.
    fn update_moved(&mut self) -> bool {
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
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        self.found_entries.push((key([x, y, z]), m));
                    }
                }
            }
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
            let (lo, hi, _) = cell_span(&a.fat, inverse_cell);
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        self.queries.push((key([x, y, z]), m));
                    }
                }
            }
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
                // itself, or a moved body that reports the pair (the lower one)
                if i == m || (b.moved && i < m) {
                    continue;
                }
                if !a.flags.may_touch(b.flags) || !a.fat.overlaps(&b.fat) {
                    continue;
                }
                // reported from the cell of the overlap's lower corner only
                let corner = [0, 1, 2].map(|k| a.low_cell[k].max(b.low_cell[k]));
                if key(corner) == cell && !self.joined.contains(a.body, b.body) {
                    self.found.push((m.min(i), m.max(i)));
                }
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

    /// Rebuilds the grid from the fat boxes and finds every fat pair.
    fn rebuild(&mut self) {
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
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        self.entries.push((key([x, y, z]), index as u32));
                    }
                }
            }
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

/// The first place at or after `from` in the sorted `entries` whose key is not below `cell`:
/// a doubling search from `from`, then a binary search in the last step's span (the cells
/// looked up in key order are mostly near each other).
fn gallop(entries: &[(u64, u32)], from: usize, cell: u64) -> usize {
    let mut step = 1;
    while from + step < entries.len() && entries[from + step].0 < cell {
        step *= 2;
    }
    let (low, high) = (from + step / 2, (from + step + 1).min(entries.len()));
    let low = low.min(high);
    low + entries[low..high].partition_point(|&(k, _)| k < cell)
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
