//! Rows packed into SIMD lanes, for [`SolverKind::Simd`](super::SolverKind): rods once a
//! substep, joints once a frame, contact points once a detection.
//!
//! A lane kernel reads each row's constants (anchors, frames, normals, friction, limits) in
//! every iteration. Gathered field by field from the rows inside the kernel, they cost little at
//! 8 lanes (hidden behind the kernels' chains of dependent arithmetic) but kept 16 lanes from
//! paying (1.4x slower than 8). Here every batch of [`SIMD_WIDTH`] rows of a colour is packed
//! into the kernel's lane struct, and the iterations solve the packed batches (Box2D v3 keeps
//! its SIMD contact constraints this way, `b2ContactConstraintSIMD`). What changes from substep
//! to substep is taken in the lanes themselves: the joints' starting twist
//! (`JointLanes::begin_substep`), and the contact points' whole substep, begun, warm-started,
//! solved and given their velocity pass in lanes, then unpacked into the points at the frame's
//! end (`packed_contacts.rs`).
//!
//! A colour's last batch is padded: its empty lanes repeat its first row
//! ([`crate::lanes::padded`]), which computes and writes back exactly what the first lane does,
//! so the whole colour is solved in lanes (a 30-ragdoll scene's colours of 30 rows are two
//! batches of 16 rather than one batch and 14 rows one by one). The overflow colour's rows (which
//! may share bodies) are solved one by one with the scalar kernel, and so is a batch of rods
//! whose modes the lane kernel does not cover.

use super::graph::Colours;
use super::{Row, PARALLEL_MIN_ROWS};
use crate::constraint::ball_socket_lanes::JointLanes;
use crate::constraint::rod_lanes::{self, RodLanes};
use crate::constraint::{JointRow, RodRow};
use crate::contact::lanes::ContactLanes;
use crate::contact::ContactPoint;
use crate::lanes::{Lane, Wide};
use crate::solver_body::SharedBodies;
use rayon::prelude::*;
use std::ops::Range;

/// The solver's lane width: [`Wide`]'s (16 where the build has AVX-512, 8 with AVX, else 4).
pub const SIMD_WIDTH: usize = <Wide as Lane>::W;

/// A row kind with a lane kernel.
pub trait LaneRows: Row + Sync + Sized {
    /// The packed form of up to [`SIMD_WIDTH`] rows.
    type Lanes: Send + Sync + Clone + std::fmt::Debug;
    /// Whether the lane kernel covers these rows (else they are solved one by one).
    fn lane_ready(_rows: &[Self]) -> bool {
        true
    }
    /// Packs one to [`SIMD_WIDTH`] rows of a colour into lanes.
    fn pack(rows: &[Self]) -> Self::Lanes;
    /// One projection of every packed row.
    fn solve_lanes(lanes: &mut Self::Lanes, bodies: SharedBodies);
    /// Hands what the iterations accumulated back to the rows.
    fn unpack(_lanes: &Self::Lanes, _rows: &mut [Self]) {}
}

impl LaneRows for JointRow {
    type Lanes = JointLanes<Wide>;
    fn pack(rows: &[Self]) -> Self::Lanes {
        JointLanes::pack(rows)
    }
    #[inline]
    fn solve_lanes(lanes: &mut Self::Lanes, bodies: SharedBodies) {
        lanes.solve(bodies)
    }
}

impl LaneRows for RodRow {
    type Lanes = RodLanes<Wide>;
    fn lane_ready(rows: &[Self]) -> bool {
        rows.iter().all(rod_lanes::is_default_modes)
    }
    fn pack(rows: &[Self]) -> Self::Lanes {
        RodLanes::pack(rows)
    }
    #[inline]
    fn solve_lanes(lanes: &mut Self::Lanes, bodies: SharedBodies) {
        lanes.solve(bodies)
    }
}

impl LaneRows for ContactPoint {
    type Lanes = ContactLanes<Wide>;
    fn pack(rows: &[Self]) -> Self::Lanes {
        ContactLanes::pack(rows)
    }
    #[inline]
    fn solve_lanes(lanes: &mut Self::Lanes, bodies: SharedBodies) {
        lanes.solve(bodies)
    }
    fn unpack(lanes: &Self::Lanes, rows: &mut [Self]) {
        lanes.unpack(rows)
    }
}

/// One colour of packed rows.
#[derive(Clone, Debug)]
struct PackedColour {
    /// Its batches in [`Packed::batches`], each of [`SIMD_WIDTH`] rows but the last.
    batches: Range<usize>,
    rows: Range<usize>,
    /// The overflow colour: its rows may share bodies, so all are solved one after another.
    overflow: bool,
}

/// One kind's rows in lanes, reused from substep to substep.
#[derive(Clone, Debug)]
pub struct Packed<T: LaneRows> {
    /// `None`: a batch the lane kernel does not cover, solved row by row.
    batches: Vec<Option<T::Lanes>>,
    colours: Vec<PackedColour>,
}

impl<T: LaneRows> Default for Packed<T> {
    fn default() -> Self {
        Packed {
            batches: Vec::new(),
            colours: Vec::new(),
        }
    }
}

impl<T: LaneRows> Packed<T> {
    /// Packs every colour of `rows` (coloured as `colours` says) into batches.
    pub fn pack(&mut self, rows: &[T], colours: &Colours, parallel: bool) {
        self.colours.clear();
        let mut count = 0;
        for (colour, range) in colours.ranges() {
            let overflow = colours.is_overflow(colour);
            let batches = if overflow {
                0
            } else {
                range.len().div_ceil(SIMD_WIDTH)
            };
            self.colours.push(PackedColour {
                batches: count..count + batches,
                rows: range,
                overflow,
            });
            count += batches;
        }
        self.batches.clear();
        self.batches.reserve(count);
        for colour in self.colours.iter().filter(|c| !c.overflow) {
            let rows = &rows[colour.rows.clone()];
            let pack = |r: &[T]| T::lane_ready(r).then(|| T::pack(r));
            if parallel && rows.len() >= 2 * PARALLEL_MIN_ROWS {
                self.batches
                    .par_extend(rows.par_chunks(SIMD_WIDTH).map(pack));
            } else {
                self.batches.extend(rows.chunks(SIMD_WIDTH).map(pack));
            }
        }
    }

    /// One sweep over the rows, colour by colour: the packed batches with the lane kernel (on
    /// several threads when a colour is large enough), the overflow colour's rows (and batches
    /// the lane kernel does not cover) with the scalar kernel.
    pub fn solve(&mut self, rows: &mut [T], bodies: SharedBodies, parallel: bool) {
        let one_row = |row: &mut T| {
            let (a, b) = row.bodies();
            // SAFETY: rows of a colour share no movable body and run on disjoint chunks; the
            // overflow colour's rows run on this thread one at a time.
            unsafe { bodies.with_pair(a, b, |a, b| row.solve(a, b)) };
        };
        self.each_colour(
            rows,
            parallel,
            |lanes| T::solve_lanes(lanes, bodies),
            one_row,
        );
    }

    /// Colour by colour, `batch` on each packed batch and `row` on each row left out of the
    /// lanes (the overflow colour's, and those of batches the lane kernel does not cover); a
    /// large colour's batches on several threads, each thread a run of them. Within a colour
    /// the batches and rows share no movable body; colours run in order.
    pub fn each_colour(
        &mut self,
        rows: &mut [T],
        parallel: bool,
        batch: impl Fn(&mut T::Lanes) + Sync,
        row: impl Fn(&mut T) + Sync,
    ) {
        let run = |batches: &mut [Option<T::Lanes>], rows: &mut [T]| {
            for (lanes, rows) in batches.iter_mut().zip(rows.chunks_mut(SIMD_WIDTH)) {
                match lanes {
                    Some(lanes) => batch(lanes),
                    None => rows.iter_mut().for_each(&row),
                }
            }
        };
        for colour in &self.colours {
            let rows = &mut rows[colour.rows.clone()];
            let batches = &mut self.batches[colour.batches.clone()];
            if colour.overflow {
                rows.iter_mut().for_each(&row);
            } else if parallel && rows.len() >= PARALLEL_MIN_ROWS {
                let chunk = batches.len().div_ceil(rayon::current_num_threads());
                batches
                    .par_chunks_mut(chunk)
                    .zip(rows.par_chunks_mut(chunk * SIMD_WIDTH))
                    .for_each(|(b, r)| run(b, r));
            } else {
                run(batches, rows);
            }
        }
    }

    /// Hands what the iterations accumulated in the batches back to the rows (each batch
    /// writes its own rows only, so large colours do it on several threads).
    pub fn unpack(&self, rows: &mut [T], parallel: bool) {
        let unpack = |(batch, rows): (&Option<T::Lanes>, &mut [T])| {
            if let Some(lanes) = batch {
                T::unpack(lanes, rows);
            }
        };
        for colour in &self.colours {
            let batches = &self.batches[colour.batches.clone()];
            let rows = &mut rows[colour.rows.clone()];
            if parallel && rows.len() >= 2 * PARALLEL_MIN_ROWS {
                let pairs = batches.par_iter().zip(rows.par_chunks_mut(SIMD_WIDTH));
                pairs
                    .with_min_len(PARALLEL_MIN_ROWS / SIMD_WIDTH)
                    .for_each(unpack);
            } else {
                batches
                    .iter()
                    .zip(rows.chunks_mut(SIMD_WIDTH))
                    .for_each(unpack);
            }
        }
    }
}
