//! Broad phase: a uniform grid rebuilt each step by sorting.
//!
//! Each finite body gets an axis-aligned box around its bounding sphere, grown by the distance
//! it may travel this step and the contact margin. The cell size is four times the mean box
//! half-size of the movable bodies (measured 10-20% faster than twice), so a limb covers one
//! to eight cells. Every body is entered once per cell its box touches, as a `(cell key, body)`
//! entry; sorting the entries groups each cell's bodies, and the boxes of each group are tested
//! pairwise. A pair is reported only from
//! the cell that holds the lower corner of the two boxes' overlap, so it is reported once.
//! Boxes much larger than a cell (static world pieces) are kept apart and tested against every
//! other box, which costs `large x n`. Half-spaces are unbounded and are paired with every
//! dynamic body.
//!
//! Large worlds sort the entries and walk the cells on several threads: the cells are split into
//! chunks at cell boundaries, each chunk's pairs into a reused buffer, replayed in cell order,
//! so the pairs and their order do not depend on the thread count (tested).
//!
//! Cost: a sort of about `8 n` entries plus the pairs in each cell, so it grows about linearly
//! with the number of bodies for any layout where bodies do not all crowd into a few cells
//! (see the `contact_detection` benchmark). A one-axis sweep, which this replaced, grows as
//! `n^1.5` on a square floor of ragdolls.

use crate::body::{Body, BodyKind};
use crate::shape::Shape;

#[derive(Clone, Copy, Debug, Default)]
struct Proxy {
    body: u32,
    dynamic: bool,
    min: [f32; 3],
    max: [f32; 3],
}

impl Proxy {
    fn overlaps(&self, other: &Proxy) -> bool {
        (0..3).all(|k| self.min[k] <= other.max[k] && other.min[k] <= self.max[k])
    }
}

/// Entries from which the sort runs on several threads.
const PARALLEL_SORT: usize = 32_768;

/// A box spanning more than this many cells on an axis goes to the large list.
const LARGE_CELLS: f32 = 4.0;

/// Reused storage, so the step does not allocate once warmed up.
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    proxies: Vec<Proxy>,
    half_spaces: Vec<u32>,
    /// Indices into `proxies` of the boxes larger than [`LARGE_CELLS`] cells.
    large: Vec<u32>,
    /// `(cell key, proxy index)`, sorted by key.
    entries: Vec<(u64, u32)>,
    /// Where each chunk of `entries` starts (at a cell boundary), and each chunk's pairs.
    bounds: Vec<usize>,
    chunk_pairs: Vec<Vec<(u32, u32)>>,
}

/// The cell index of coordinate `x`: floor without a libm call (x86-64's baseline has no
/// rounding instruction, and `floorf` was a tenth of detection).
#[inline]
fn cell_of(x: f32, inverse_cell: f32) -> i64 {
    let scaled = x * inverse_cell;
    let truncated = scaled as i64;
    truncated - ((truncated as f32) > scaled) as i64
}

/// Packs three cell coordinates (each within +-2^20) into one sortable key.
fn key(cell: [i64; 3]) -> u64 {
    const MASK: i64 = (1 << 21) - 1;
    (((cell[0] & MASK) as u64) << 42) | (((cell[1] & MASK) as u64) << 21) | (cell[2] & MASK) as u64
}

impl BroadPhase {
    /// Calls `pair(a, b)` for every candidate pair (a < b in the world's order for finite pairs;
    /// the half-space first for half-space pairs). At least one body of each pair is dynamic.
    pub fn find_pairs(
        &mut self,
        bodies: &[Body],
        dt: f32,
        margin: f32,
        mut pair: impl FnMut(u32, u32),
    ) {
        if self.proxies.len() + self.half_spaces.len() != bodies.len() {
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
        }
        let mut reach_sum = 0.0;
        let mut movable = 0;
        for proxy in &mut self.proxies {
            let body = &bodies[proxy.body as usize];
            let reach = body.shape.bounding_radius() + margin + dt * body.linear_velocity.length();
            let p = body.position.to_array();
            for k in 0..3 {
                proxy.min[k] = p[k] - reach;
                proxy.max[k] = p[k] + reach;
            }
            proxy.dynamic = body.kind == BodyKind::Dynamic;
            if body.kind != BodyKind::Fixed {
                reach_sum += reach;
                movable += 1;
            }
        }
        if movable == 0 {
            return; // nothing moves: no pair can change
        }
        let cell = 4.0 * reach_sum / movable as f32;
        let inverse_cell = 1.0 / cell;

        self.large.clear();
        self.entries.clear();
        for (index, proxy) in self.proxies.iter().enumerate() {
            let span = (0..3)
                .map(|k| proxy.max[k] - proxy.min[k])
                .fold(0.0, f32::max);
            if span > LARGE_CELLS * cell {
                self.large.push(index as u32);
                continue;
            }
            let lo = proxy.min.map(|x| cell_of(x, inverse_cell));
            let hi = proxy.max.map(|x| cell_of(x, inverse_cell));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        self.entries.push((key([x, y, z]), index as u32));
                    }
                }
            }
        }
        // (cell, proxy) entries are unique, so any sort gives the same order: a parallel one for
        // large worlds (about 100 000 entries at 1000 ragdolls)
        if self.entries.len() >= PARALLEL_SORT && rayon::current_num_threads() > 1 {
            use rayon::slice::ParallelSliceMut;
            self.entries.par_sort_unstable();
        } else {
            self.entries.sort_unstable();
        }

        let proxies = &self.proxies;
        let candidate = |a: &Proxy, b: &Proxy| (a.dynamic || b.dynamic) && a.overlaps(b);
        // The cells' pairs, in sorted-cell order. Large worlds split the entries into chunks at
        // cell boundaries, each into its own reused buffer, replayed in order: the same pairs
        // in the same order for any thread count.
        let cells_pairs = |entries: &[(u64, u32)], out: &mut Vec<(u32, u32)>| {
            out.clear();
            let mut start = 0;
            while start < entries.len() {
                let cell_key = entries[start].0;
                let mut end = start + 1;
                while end < entries.len() && entries[end].0 == cell_key {
                    end += 1;
                }
                let group = &entries[start..end];
                for (i, &(_, first)) in group.iter().enumerate() {
                    let a = &proxies[first as usize];
                    for &(_, second) in &group[i + 1..] {
                        let b = &proxies[second as usize];
                        if !candidate(a, b) {
                            continue;
                        }
                        // the overlap's lower corner decides the one cell that reports the pair
                        let corner =
                            [0, 1, 2].map(|k| cell_of(a.min[k].max(b.min[k]), inverse_cell));
                        if key(corner) == cell_key {
                            out.push((a.body.min(b.body), a.body.max(b.body)));
                        }
                    }
                }
                start = end;
            }
        };
        let threads = rayon::current_num_threads();
        let chunks = if threads > 1 && self.entries.len() >= PARALLEL_SORT {
            4 * threads
        } else {
            1
        };
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
            self.chunk_pairs.resize_with(chunks, Vec::new);
        }
        let entries = &self.entries;
        let bounds = &self.bounds;
        if chunks > 1 {
            use rayon::prelude::*;
            self.chunk_pairs[..chunks]
                .par_iter_mut()
                .enumerate()
                .for_each(|(c, out)| cells_pairs(&entries[bounds[c]..bounds[c + 1]], out));
        } else {
            cells_pairs(entries, &mut self.chunk_pairs[0]);
        }
        for out in &self.chunk_pairs[..chunks] {
            for &(a, b) in out {
                pair(a, b);
            }
        }
        for (i, &large) in self.large.iter().enumerate() {
            let a = &proxies[large as usize];
            for (index, b) in proxies.iter().enumerate() {
                // large-large pairs once, from the earlier of the two in `large`
                let other_large = self.large.binary_search(&(index as u32));
                if index as u32 == large || other_large.is_ok_and(|j| j <= i) {
                    continue;
                }
                if candidate(a, b) {
                    pair(a.body.min(b.body), a.body.max(b.body));
                }
            }
        }
        for &plane in &self.half_spaces {
            for proxy in self.proxies.iter().filter(|p| p.dynamic) {
                pair(plane, proxy.body);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Quat, Vec3};

    fn ball(x: f32, y: f32, z: f32, radius: f32, kind: BodyKind) -> Body {
        Body::new("b", kind, Shape::Sphere { radius }, 1.0)
            .with_pose(Vec3::new(x, y, z), Quat::IDENTITY)
    }

    /// Every pair the grid reports is an overlapping pair of boxes, reported once, and no
    /// overlapping pair with a dynamic body is missed (against the all-pairs answer).
    #[test]
    fn grid_finds_exactly_the_overlapping_pairs() {
        let mut bodies = Vec::new();
        let mut seed = 12345u32;
        let mut random = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32
        };
        for i in 0..300 {
            let kind = if i % 7 == 0 {
                BodyKind::Fixed
            } else {
                BodyKind::Dynamic
            };
            let radius = if i % 50 == 0 {
                3.0
            } else {
                0.05 + 0.3 * random()
            };
            bodies.push(ball(
                8.0 * random() - 4.0,
                4.0 * random(),
                8.0 * random() - 4.0,
                radius,
                kind,
            ));
        }
        let mut found = Vec::new();
        BroadPhase::default().find_pairs(&bodies, 1.0 / 60.0, 0.02, |a, b| found.push((a, b)));
        let count = found.len();
        found.sort_unstable();
        found.dedup();
        assert_eq!(found.len(), count, "a pair was reported twice");
        let mut expected = Vec::new();
        for a in 0..bodies.len() {
            for b in a + 1..bodies.len() {
                let (p, q) = (&bodies[a], &bodies[b]);
                let reach = |body: &Body| body.shape.bounding_radius() + 0.02;
                let apart = (p.position - q.position).abs().max_element() > reach(p) + reach(q);
                let dynamic = p.kind == BodyKind::Dynamic || q.kind == BodyKind::Dynamic;
                if !apart && dynamic {
                    expected.push((a as u32, b as u32));
                }
            }
        }
        assert!(!expected.is_empty());
        assert_eq!(found, expected);
    }

    /// A world large enough for the parallel sort and chunked cells: the same pairs in the
    /// same order on one thread and on two.
    #[test]
    fn chunked_cells_give_the_same_pairs_on_any_thread_count() {
        let mut seed = 777u32;
        let mut random = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32
        };
        let bodies: Vec<Body> = (0..12000)
            .map(|_| {
                let (x, y, z) = (40.0 * random(), 2.0 * random(), 40.0 * random());
                ball(x, y, z, 0.1 + 0.2 * random(), BodyKind::Dynamic)
            })
            .collect();
        let pairs = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut found = Vec::new();
                let mut broad = BroadPhase::default();
                broad.find_pairs(&bodies, 1.0 / 60.0, 0.02, |a, b| found.push((a, b)));
                assert!(
                    broad.entries.len() >= PARALLEL_SORT,
                    "{}",
                    broad.entries.len()
                );
                found
            })
        };
        let (one, two) = (pairs(1), pairs(2));
        assert!(one.len() > 1000, "{} pairs", one.len());
        assert_eq!(one, two);
        let mut unique = one.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), one.len(), "a pair was reported twice");
    }
}
