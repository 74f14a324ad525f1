//! Broad phase: a uniform grid of fat boxes, rebuilt by sorting only when many bodies have moved
//! (Box2D's fat AABBs, over a grid instead of a tree).
//!
//! Each finite body gets its tightest world axis-aligned box ([`Shape::world_half_extents`]: a
//! limb lying down is a long thin box, not the cube around its bounding sphere, which on the
//! 1000-ragdoll rain gave 2.6 times the candidate pairs), grown by the distance it may travel
//! this step and half the contact margin: a pair's two boxes together then reach as far as the
//! narrow phase's reach, margin plus both bodies' travel (a half-space has no box, so its pairs
//! take the whole margin on the body's side). Around it the body keeps a fat box,
//! [`FAT_MARGIN`] larger on every side, which stays put while the tight box stays inside it.
//! Pairs of overlapping fat boxes are kept from step to step; each step reports those whose
//! tight boxes overlap. A body whose tight box leaves its fat box gets a new fat box ("moved"):
//! its grid entries are replaced by the new box's cells, and its pairs are dropped and found
//! again by querying the grid with the new box (each list in one merge pass, which drops the
//! moved bodies' old items, read from a bitset, and merges the new ones in sorted).
//! A settled pile moves a few hundred bodies a step, so its broad phase costs the box updates
//! and the report. Once more than a sixteenth of the bodies move in one step (a falling
//! crowd), or a body wakes, sleeps or joins, the pairs are rebuilt instead: group by group
//! where the bodies come in groups of joined bodies (a crowd of ragdolls, `groups`, which
//! leaves the grid to be entered at the next update), else from the grid, rebuilt, its sweeps
//! on several threads (before, moved bodies were left stale in the grid and tested one by one
//! against each other, and the grid was rebuilt once a sixteenth had moved since the last
//! rebuild: every third or fourth step in the settled rain, 7.5 ms each on one thread; a
//! quarter measured no better on two threads, where the update runs on one):
//!
//! The cell edge is six times the mean largest fat-box half-size of the movable bodies, so a
//! limb covers one to eight cells. On the landing rain 6 rebuilt faster than 4 (24 000 entries
//! against 33 000, and less to sort) and 2 or 3 slower (73 000 and 45 000 entries); over a
//! whole run 4, 6 and 8 were within the noise. (Earlier, 6 and 8 measured slower only because
//! their fewer entries fell below the sort's parallel threshold, which then also held the
//! sweep to one thread.) Every body is entered once per cell its fat box touches, as a
//! `(cell key, body)` entry; sorting the entries groups each cell's bodies, and each group is
//! swept along x (sorted by lower x, each box tested against those starting before it ends, W
//! at a time in lanes). A pair is reported only from the cell that holds the lower corner of
//! the two boxes' overlap, so it is reported once. Boxes covering more than `LARGE_CELLS`
//! (1024) cells are kept apart and tested against every other box each step, which costs
//! `large x n`. Half-spaces are unbounded: each is paired
//! with the dynamic bodies whose tight box, grown by the other half margin, reaches below its
//! plane.
//!
//! Large worlds sort the entries and walk the cells on several threads (each from its own
//! threshold: the sweep is worth splitting from a few thousand entries, the sort only from tens
//! of thousands): the cells are split into chunks at cell boundaries, each chunk's pairs into a
//! reused buffer, in runs by the pair's first body. The kept pairs are sorted by body, each
//! run by two counting passes on its own (`pair_sort::sort_pairs`), so the pairs and their order
//! depend neither on the thread count nor on when the grid was rebuilt (tested).
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
mod groups;
mod joined;
mod moved;
mod pair_sort;
mod rebuild;
mod report;
#[cfg(test)]
mod tests;

use super::collider::{Collider, PARALLEL_BODIES};
use crate::body::BodyKind;
use crate::math::Vec3;
use crate::shape::Shape;
use grid::{Aabb, Bits};
pub use joined::Joined;
use std::time::Instant;

/// How much larger than its tight box (m, each side) a body's fat box is: a body resting or
/// swinging by a few centimetres keeps its fat box, and its pairs, for many steps.
pub const FAT_MARGIN: f32 = 0.02;

/// What the broad phase keeps of a body between steps.
#[derive(Clone, Copy, Debug, Default)]
struct Proxy {
    body: u32,
    /// The body's [`Joined::group`] at the last rebuild.
    group: u32,
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
    /// [`crate::body::Body::moves_this_step`].
    active: bool,
    /// A dynamic body, awake or asleep: something a contact can move or wake.
    dynamic: bool,
}

impl Flags {
    /// The flags as [`CellBox::code`]'s bits 3 and 4.
    fn code(self) -> u8 {
        (self.active as u8) << 3 | (self.dynamic as u8) << 4
    }

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
    /// [`Proxy::group`].
    group: u32,
    /// Bits 0-2: the box's lowest cell along axis k is this cell's (see `rebuild::cell_pairs`);
    /// bit 3: [`Flags::active`]; bit 4: [`Flags::dynamic`]. Two boxes make a pair here exactly
    /// when their codes together set all five.
    code: u8,
    fat: Aabb,
}

/// More than one in `REBUILD_MOVED` of the bodies getting new fat boxes in a step rebuilds
/// the grid instead of updating it body by body (a falling crowd).
const REBUILD_MOVED: usize = 16;

/// Entries from which the sort runs on several threads.
const PARALLEL_SORT: usize = 32_768;

/// Entries from which the cells are swept on several threads: a sweep costs about 90 ns an
/// entry in the landing rain, far above what splitting it costs.
const PARALLEL_SWEEP: usize = 4096;

/// Entries from which the grid is sorted by counting over its cells ([`grid::sort_entries`]).
const COUNTED_SORT: usize = 4096;

/// The grid's cell edge over the movable bodies' mean largest box half-size (see the module
/// docs).
const CELL_FACTOR: f32 = 6.0;

/// A box covering more than this many cells goes to the large list, tested against every
/// other box. Below it a box is entered in each cell: the rain's walls, stairs and ramps (up
/// to about 150 cells each) cost a few hundred entries instead of a test against all 15 000
/// limbs each.
const LARGE_CELLS: i64 = 1024;

/// Fat pairs an update may make per body, on top of [`MIN_PAIR_BUDGET`]: the landing rain
/// keeps about 10 a body. Bodies that sweep far through a crowd in one step (a time step far too
/// long for their speed) make pairs as the square of their number instead, 86 million for the
/// rain at dt = 1 s: gigabytes, in one step.
const PAIRS_PER_BODY: usize = 64;

/// Fat pairs any update may make (see [`PAIRS_PER_BODY`]).
const MIN_PAIR_BUDGET: usize = 1 << 20;

/// The fat pairs an update among `bodies` bounded bodies may make.
pub fn pair_budget(bodies: usize) -> usize {
    MIN_PAIR_BUDGET + PAIRS_PER_BODY * bodies
}

/// The fat pairs a rebuild may still make, shared by the threads that make them; each takes
/// its pairs in batches, so the budget is passed by at most a batch and a box's pairs a thread.
#[derive(Debug)]
pub(super) struct Budget(std::sync::atomic::AtomicI64);

impl Budget {
    /// Pairs a thread makes before it takes them from the budget.
    pub(super) const BATCH: usize = 4096;

    fn new(pairs: usize) -> Self {
        Budget(std::sync::atomic::AtomicI64::new(pairs as i64))
    }

    /// Takes `pairs` from the budget; false once it is spent.
    pub(super) fn take(&self, pairs: usize) -> bool {
        let pairs = pairs as i64;
        self.0
            .fetch_sub(pairs, std::sync::atomic::Ordering::Relaxed)
            >= pairs
    }

    fn spent(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed) < 0
    }
}

/// One chunk of cells' output, and its scratch copy of a cell's boxes.
#[derive(Clone, Debug, Default)]
struct ChunkPairs {
    /// The pairs by the run of their first index ([`pair_sort::IndexRuns`]).
    runs: Vec<Vec<(u32, u32)>>,
    /// Scratch: a cell's boxes sorted by lower x, and their bounds apart
    /// (padded by a lane width of boxes that meet nothing) for the sweep's lanes.
    group: Vec<CellBox>,
    lanes: CellLanes,
}

impl ChunkPairs {
    /// The pairs whose first index is in run `r`.
    fn run(&self, r: usize) -> &[(u32, u32)] {
        &self.runs[r]
    }
}

/// A cell's boxes' lower x, y and z bounds, and their codes, one array each, in the sweep's
/// order.
#[derive(Clone, Debug, Default)]
struct CellLanes {
    /// [`CellBox::code`] as the low bits of a float in [1, 2) (`rebuild::code_lane`), so that
    /// the lanes can test two codes together.
    code: Vec<f32>,
    x_min: Vec<f32>,
    y_min: Vec<f32>,
    y_max: Vec<f32>,
    z_min: Vec<f32>,
    z_max: Vec<f32>,
}

/// Reused storage, so the step does not allocate once warmed up.
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    /// The lane width of the box tests (the pairs are the same at every width).
    pub(crate) lane_width: crate::lanes::LaneWidth,
    proxies: Vec<Proxy>,
    /// Each proxy's tight box this step (apart: the report reads only these).
    tight: Vec<Aabb>,
    half_spaces: Vec<u32>,
    /// Indices into `proxies` of the boxes covering more than [`LARGE_CELLS`] cells.
    large: Vec<u32>,
    /// `(cell key, proxy index)` of the fat boxes at the last rebuild, sorted by key.
    entries: Vec<(u64, u32)>,
    /// The last rebuild went by groups and left `entries` as they were: the next incremental
    /// update enters the fat boxes first.
    grid_stale: bool,
    /// What a rebuild by groups reuses, and whether rebuilds go by the grid only (to test one
    /// against the other).
    groups: groups::Groups,
    grid_only: bool,
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
    /// The contact margin of the last update (m): a half-space's pairs need it all on the
    /// body's side.
    margin: f32,
    /// Rebuilds of the fat pairs so far, by groups or from the grid (a settled world rebuilds
    /// rarely).
    pub rebuilds: u64,
    /// The fat pairs this update may make ([`PAIRS_PER_BODY`]).
    pair_budget: usize,
    /// Updates that stopped at their pair budget so far: each left no pairs at all.
    pub overflows: u64,
    /// Where the last update's time went.
    timing: UpdateTiming,
}

/// Where the broad phase's last [`BroadPhase::update`] spent its wall time (s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UpdateTiming {
    /// Each body's tight box, and a new fat box for those that left theirs.
    pub boxes: f64,
    /// The kept pairs rebuilt (their gap bounds carried over), or brought up to date for the
    /// bodies that moved.
    pub pairs: f64,
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

    /// Rebuilds from the grid only, never group by group (`groups`): the two give the same
    /// pairs in the same order, so this only changes the cost (to compare them).
    pub fn set_grid_only(&mut self, grid_only: bool) {
        self.grid_only = grid_only;
    }

    /// Whether bodies `a` and `b` are never paired ([`Self::set_joined`]).
    pub fn joined(&self, a: u32, b: u32) -> bool {
        self.joined.contains(a, b)
    }

    /// Brings the fat boxes and the kept pairs up to this step's bodies. Returns false when
    /// nothing moves (then there are no pairs).
    ///
    /// Past its pair budget ([`PAIRS_PER_BODY`]) an update stops, keeps no pairs, counts one
    /// more of [`Self::overflows`] and returns false: the run must stop, as its bodies have
    /// exploded out of reach of the method.
    pub fn update(&mut self, bodies: &[Collider], dt: f32, margin: f32) -> bool {
        let start = Instant::now();
        self.timing = UpdateTiming::default();
        let overflows = self.overflows;
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
        self.margin = margin;
        self.pair_budget = pair_budget(self.proxies.len());
        self.tight.resize(self.proxies.len(), Aabb::default());
        let boxes = |(proxy, tight): (&mut Proxy, &mut Aabb)| {
            let body = &bodies[proxy.body as usize];
            // grown by how far the fastest surface point may travel this frame, spin included,
            // and half the margin: two boxes together cover the pair's whole reach (with the whole
            // margin on each, as before, the landing rain tested 11% more pairs and the settled
            // one looked at 16-18% more, for the same points)
            let grow = 0.5 * margin + dt * (body.linear_velocity.length() + body.spin_bound);
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
        let boxes_done = Instant::now();
        self.timing.boxes = (boxes_done - start).as_secs_f64();
        if movable == 0 {
            return false; // nothing moves: no pair can change
        }
        if !rebuild && !self.moved.is_empty() {
            rebuild = !self.update_moved();
        }
        if rebuild {
            self.rebuild();
        }
        self.timing.pairs = boxes_done.elapsed().as_secs_f64();
        self.overflows == overflows
    }

    /// Where the last [`Self::update`]'s time went.
    pub fn timing(&self) -> UpdateTiming {
        self.timing
    }
}
