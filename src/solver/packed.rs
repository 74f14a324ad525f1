//! Rows packed into SIMD lanes, for [`SolverKind::Simd`](super::SolverKind): rods once a
//! substep, joints once a frame, contact points once a detection.
//!
//! A lane kernel reads each row's constants (anchors, frames, normals, friction, limits) in
//! every iteration. Gathered field by field from the rows inside the kernel, they cost little at
//! 8 lanes (hidden behind the kernels' chains of dependent arithmetic) but kept 16 lanes from
//! paying (1.4x slower than 8). Here every batch of `W` rows of a colour is packed into the
//! kernel's lane struct, and the iterations solve the packed batches (Box2D v3 keeps its SIMD
//! contact constraints this way, `b2ContactConstraintSIMD`). What changes from substep to
//! substep is taken in the lanes themselves: the joints' starting twist
//! (`JointLanes::begin_substep`), and the contact points' whole substep, begun, warm-started,
//! solved and given their velocity pass in lanes, then unpacked into the points at the frame's
//! end (`packed_contacts.rs`).
//!
//! A colour's last batch is padded: its empty lanes repeat its first row
//! ([`crate::lanes::padded`]), which computes and writes back exactly what the first lane does,
//! so the whole colour is solved in lanes (a 30-ragdoll scene's colours of 30 rows are two
//! batches of 16 rather than one batch and 14 rows one by one). The overflow colour's rows (which
//! may share bodies) are solved one by one with the scalar kernel, and so are the rods of a
//! group of [`MAX_LANES`] rows of a colour any of whose modes the lane kernel does not cover:
//! groups of the widest width, so which rows the scalar kernel takes does not depend on the
//! width the CPU runs.
//!
//! The batches of a colour chunk run inside [`Lane::dispatch`], compiled for the lane type's
//! instruction set; [`BatchWork`] is what each batch and each row left out of the lanes does.

use super::graph::Colours;
use super::{Row, PARALLEL_MIN_ROWS};
use crate::constraint::ball_socket_lanes::JointLanes;
use crate::constraint::rod_lanes::{self, RodLanes};
use crate::constraint::{JointRow, RodRow};
use crate::contact::lanes::ContactLanes;
use crate::contact::ContactPoint;
use crate::lanes::{F32x16, F32x4, F32x8, Lane, LaneWidth, LaneWork, MAX_LANES};
use crate::solver_body::SharedBodies;
use rayon::prelude::*;
use std::ops::Range;

/// A row kind with a lane kernel.
pub trait LaneRows: Row + Sync + Sized {
    /// The packed form of up to `L::W` rows.
    type Lanes<L: Lane>: Send + Sync + Clone + std::fmt::Debug;
    /// Whether the lane kernel covers these rows (else they are solved one by one).
    fn lane_ready(_rows: &[Self]) -> bool {
        true
    }
    /// Packs one to `L::W` rows of a colour into lanes.
    fn pack<L: Lane>(rows: &[Self]) -> Self::Lanes<L>;
    /// One projection of every packed row.
    fn solve_lanes<L: Lane>(lanes: &mut Self::Lanes<L>, bodies: SharedBodies);
    /// Hands what the iterations accumulated back to the rows.
    fn unpack<L: Lane>(_lanes: &Self::Lanes<L>, _rows: &mut [Self]) {}
}

impl LaneRows for JointRow {
    type Lanes<L: Lane> = JointLanes<L>;
    #[inline(always)]
    fn pack<L: Lane>(rows: &[Self]) -> JointLanes<L> {
        JointLanes::pack(rows)
    }
    #[inline(always)]
    fn solve_lanes<L: Lane>(lanes: &mut JointLanes<L>, bodies: SharedBodies) {
        lanes.solve(bodies)
    }
}

impl LaneRows for RodRow {
    type Lanes<L: Lane> = RodLanes<L>;
    fn lane_ready(rows: &[Self]) -> bool {
        rows.iter().all(rod_lanes::is_default_modes)
    }
    #[inline(always)]
    fn pack<L: Lane>(rows: &[Self]) -> RodLanes<L> {
        RodLanes::pack(rows)
    }
    #[inline(always)]
    fn solve_lanes<L: Lane>(lanes: &mut RodLanes<L>, bodies: SharedBodies) {
        lanes.solve(bodies)
    }
}

impl LaneRows for ContactPoint {
    type Lanes<L: Lane> = ContactLanes<L>;
    #[inline(always)]
    fn pack<L: Lane>(rows: &[Self]) -> ContactLanes<L> {
        ContactLanes::pack(rows)
    }
    #[inline(always)]
    fn solve_lanes<L: Lane>(lanes: &mut ContactLanes<L>, bodies: SharedBodies) {
        lanes.solve(bodies)
    }
    #[inline(always)]
    fn unpack<L: Lane>(lanes: &ContactLanes<L>, rows: &mut [Self]) {
        lanes.unpack(rows)
    }
}

/// What a pass over the packed rows does to each batch, and to each row left out of the lanes
/// (implementations mark both `#[inline(always)]`: they run inside [`Lane::dispatch`]).
pub trait BatchWork<T: LaneRows, L: Lane>: Sync {
    /// The work on one packed batch.
    fn batch(&self, lanes: &mut T::Lanes<L>);
    /// The work on one row the lanes do not hold.
    fn row(&self, row: &mut T);
}

/// One projection of every row: the lane kernel, or the scalar one.
struct Solve(SharedBodies);

impl<T: LaneRows, L: Lane> BatchWork<T, L> for Solve {
    #[inline(always)]
    fn batch(&self, lanes: &mut T::Lanes<L>) {
        T::solve_lanes(lanes, self.0)
    }
    #[inline(always)]
    fn row(&self, row: &mut T) {
        let (a, b) = row.bodies();
        // SAFETY: rows of a colour share no movable body and run on disjoint chunks; the
        // overflow colour's rows run on this thread one at a time.
        unsafe {
            self.0.with_pair(
                a,
                b,
                #[inline(always)]
                |a, b| row.solve(a, b),
            )
        };
    }
}

/// One colour of packed rows.
#[derive(Clone, Debug)]
struct PackedColour {
    /// Its batches in [`Packed::batches`], each of `L::W` rows but the last.
    batches: Range<usize>,
    rows: Range<usize>,
    /// The overflow colour: its rows may share bodies, so all are solved one after another.
    overflow: bool,
}

/// One kind's rows in lanes of type `L`, reused from substep to substep.
#[derive(Clone, Debug)]
pub struct Packed<T: LaneRows, L: Lane> {
    /// `None`: a batch the lane kernel does not cover, solved row by row.
    batches: Vec<Option<T::Lanes<L>>>,
    colours: Vec<PackedColour>,
}

impl<T: LaneRows, L: Lane> Default for Packed<T, L> {
    fn default() -> Self {
        Packed {
            batches: Vec::new(),
            colours: Vec::new(),
        }
    }
}

/// Packs one batch in the lane type's instruction set.
struct PackBatch<'a, T> {
    rows: &'a [T],
    ready: bool,
}

impl<T: LaneRows, L: Lane> LaneWork<L> for PackBatch<'_, T> {
    type Output = Option<T::Lanes<L>>;
    #[inline(always)]
    fn run(self) -> Self::Output {
        // (no closure: its body would compile outside the dispatched function)
        match self.ready {
            true => Some(T::pack(self.rows)),
            false => None,
        }
    }
}

/// A run of batches of one colour and their rows, with the work to do on each.
struct RunBatches<'a, T: LaneRows, L: Lane, W> {
    batches: &'a mut [Option<T::Lanes<L>>],
    rows: &'a mut [T],
    work: &'a W,
}

impl<T: LaneRows, L: Lane, W: BatchWork<T, L>> LaneWork<L> for RunBatches<'_, T, L, W> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for (lanes, rows) in self.batches.iter_mut().zip(self.rows.chunks_mut(L::W)) {
            match lanes {
                Some(lanes) => self.work.batch(lanes),
                None => {
                    // (a loop, not a closure: a closure's body would compile outside the
                    // dispatched function)
                    for row in rows {
                        self.work.row(row)
                    }
                }
            }
        }
    }
}

/// Hands a run of batches back to their rows.
struct Unpack<'a, T: LaneRows, L: Lane> {
    batches: &'a [Option<T::Lanes<L>>],
    rows: &'a mut [T],
}

impl<T: LaneRows, L: Lane> LaneWork<L> for Unpack<'_, T, L> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for (batch, rows) in self.batches.iter().zip(self.rows.chunks_mut(L::W)) {
            if let Some(lanes) = batch {
                T::unpack(lanes, rows);
            }
        }
    }
}

impl<T: LaneRows, L: Lane> Packed<T, L> {
    /// Packs every colour of `rows` (coloured as `colours` says) into batches of `L::W`.
    pub fn pack(&mut self, rows: &[T], colours: &Colours, parallel: bool) {
        self.colours.clear();
        let mut count = 0;
        for (colour, range) in colours.ranges() {
            let overflow = colours.is_overflow(colour);
            let batches = if overflow {
                0
            } else {
                range.len().div_ceil(L::W)
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
            // the lane kernel's cover is decided per group of the widest width
            let pack = |(k, batch): (usize, &[T])| {
                let start = k * L::W / MAX_LANES * MAX_LANES;
                let group = &rows[start..(start + MAX_LANES).min(rows.len())];
                let ready = T::lane_ready(group);
                L::dispatch(PackBatch { rows: batch, ready })
            };
            if parallel && rows.len() >= 2 * PARALLEL_MIN_ROWS {
                let batches = rows.par_chunks(L::W).enumerate().map(pack);
                self.batches.par_extend(batches);
            } else {
                self.batches.extend(rows.chunks(L::W).enumerate().map(pack));
            }
        }
    }

    /// One sweep over the rows, colour by colour: the packed batches with the lane kernel (on
    /// several threads when a colour is large enough), the overflow colour's rows (and batches
    /// the lane kernel does not cover) with the scalar kernel.
    pub fn solve(&mut self, rows: &mut [T], bodies: SharedBodies, parallel: bool) {
        self.each_colour(rows, parallel, &Solve(bodies));
    }

    /// Colour by colour, `work` on each packed batch and on each row left out of the lanes
    /// (the overflow colour's, and those of batches the lane kernel does not cover); a large
    /// colour's batches on several threads, each thread a run of them. Within a colour the
    /// batches and rows share no movable body; colours run in order.
    pub fn each_colour<W: BatchWork<T, L>>(&mut self, rows: &mut [T], parallel: bool, work: &W) {
        let run = |batches: &mut [Option<T::Lanes<L>>], rows: &mut [T]| {
            L::dispatch(RunBatches {
                batches,
                rows,
                work,
            })
        };
        for colour in &self.colours {
            let rows = &mut rows[colour.rows.clone()];
            let batches = &mut self.batches[colour.batches.clone()];
            if colour.overflow {
                rows.iter_mut().for_each(|row| work.row(row));
            } else if parallel && rows.len() >= PARALLEL_MIN_ROWS {
                let chunk = batches.len().div_ceil(rayon::current_num_threads());
                batches
                    .par_chunks_mut(chunk)
                    .zip(rows.par_chunks_mut(chunk * L::W))
                    .for_each(|(b, r)| run(b, r));
            } else {
                run(batches, rows);
            }
        }
    }

    /// Hands what the iterations accumulated in the batches back to the rows (each batch
    /// writes its own rows only, so large colours do it on several threads).
    pub fn unpack(&self, rows: &mut [T], parallel: bool) {
        for colour in &self.colours {
            let batches = &self.batches[colour.batches.clone()];
            let rows = &mut rows[colour.rows.clone()];
            if parallel && rows.len() >= 2 * PARALLEL_MIN_ROWS {
                let per_task = (PARALLEL_MIN_ROWS / L::W).max(1);
                let tasks = batches.par_chunks(per_task);
                tasks
                    .zip(rows.par_chunks_mut(per_task * L::W))
                    .for_each(|(batches, rows)| L::dispatch(Unpack { batches, rows }));
            } else {
                L::dispatch(Unpack { batches, rows });
            }
        }
    }
}

/// The three row kinds in lanes of one type.
#[derive(Clone, Debug)]
pub struct Packs<L: Lane> {
    /// Joints, packed once a frame.
    pub joints: Packed<JointRow, L>,
    /// Rods, packed once a substep.
    pub rods: Packed<RodRow, L>,
    /// Contact points, packed once a detection.
    pub contacts: Packed<ContactPoint, L>,
}

impl<L: Lane> Default for Packs<L> {
    fn default() -> Self {
        Packs {
            joints: Packed::default(),
            rods: Packed::default(),
            contacts: Packed::default(),
        }
    }
}

/// [`Packs`] in the lane type of the width the solver runs.
#[derive(Clone, Debug)]
pub enum WidthPacks {
    /// 4 lanes.
    W4(Packs<F32x4>),
    /// 8 lanes.
    W8(Packs<F32x8>),
    /// 16 lanes.
    W16(Packs<F32x16>),
}

impl WidthPacks {
    /// Empty packs of `width`.
    pub fn new(width: LaneWidth) -> Self {
        match width {
            LaneWidth::W4 => WidthPacks::W4(Packs::default()),
            LaneWidth::W8 => WidthPacks::W8(Packs::default()),
            LaneWidth::W16 => WidthPacks::W16(Packs::default()),
        }
    }

    /// Their width.
    pub fn width(&self) -> LaneWidth {
        match self {
            WidthPacks::W4(_) => LaneWidth::W4,
            WidthPacks::W8(_) => LaneWidth::W8,
            WidthPacks::W16(_) => LaneWidth::W16,
        }
    }
}

impl Default for WidthPacks {
    fn default() -> Self {
        WidthPacks::new(LaneWidth::detect())
    }
}

/// Calls `$body` with `$packs` bound to the [`Packs`] of a [`WidthPacks`] (`&mut`), whatever
/// its lane type.
macro_rules! with_packs {
    ($width_packs:expr, $packs:ident => $body:expr) => {
        match $width_packs {
            $crate::solver::packed::WidthPacks::W4($packs) => $body,
            $crate::solver::packed::WidthPacks::W8($packs) => $body,
            $crate::solver::packed::WidthPacks::W16($packs) => $body,
        }
    };
}
pub(crate) use with_packs;
