//! The sweep over a kind's rows, colour by colour (scalar or from packed lanes, on several
//! threads when a colour is large), and the [`Row`] trait it solves through.

use super::body::{SharedBodies, SolverBody};
use super::graph::Colours;
use super::packed::{self, Packed};
use super::PARALLEL_MIN_ROWS;
use crate::constraint::{DamperRow, JointRow, RodRow};
use crate::contact::ContactPoint;
use crate::lanes::{Lane, LaneWidth, LaneWork};
use crate::with_lane_type;
use rayon::prelude::*;

/// One sweep over a kind's rows, colour by colour: from their packed lanes with the SIMD solver
/// ([`packed::Packed::solve`]), else one row at a time with the scalar kernel (the reference).
/// Rows of a colour are independent, so a large colour is split into chunks across threads;
/// the overflow colour is always sequential.
pub(super) fn sweep<T: packed::LaneRows, L: Lane>(
    rows: &mut [T],
    colours: &Colours,
    lanes: Option<&mut Packed<T, L>>,
    bodies: SharedBodies,
    parallel: bool,
) {
    if let Some(lanes) = lanes {
        return lanes.solve(rows, bodies, parallel);
    }
    solve_colours(L::width(), rows, colours, bodies, parallel);
}

/// The scalar sweep of [`sweep`] (also the dampers', which have no lane kernel). The rows run
/// in a function compiled for the instructions of `width`'s lanes (their maths is scalar, but
/// the wider instruction set's encodings and registers serve it too: 0.8x the time of the
/// x86-64 baseline's code on the cheap joint, `benches/solver.rs`).
pub(super) fn solve_colours<T: Row>(
    width: LaneWidth,
    rows: &mut [T],
    colours: &Colours,
    bodies: SharedBodies,
    parallel: bool,
) {
    let run =
        |rows: &mut [T]| with_lane_type!(width, L => L::dispatch(ScalarRows { rows, bodies }));
    for (colour, range) in colours.ranges() {
        let rows = &mut rows[range];
        if parallel && !colours.is_overflow(colour) && rows.len() >= PARALLEL_MIN_ROWS {
            let chunk = rows.len().div_ceil(rayon::current_num_threads());
            rows.par_chunks_mut(chunk).for_each(run);
        } else {
            run(rows);
        }
    }
}

/// A run of rows solved one after another by the scalar kernel.
pub struct ScalarRows<'a, T> {
    /// The rows; the movable bodies of any two of them are the same only if they run in this
    /// order (one colour's rows share none; the overflow colour's run here one at a time).
    pub rows: &'a mut [T],
    /// The bodies they move.
    pub bodies: SharedBodies,
}

impl<T: Row, L: Lane> LaneWork<L> for ScalarRows<'_, T> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for row in self.rows.iter_mut() {
            let (a, b) = row.bodies();
            // SAFETY: rows of a colour share no movable body, and chunks of a colour are
            // disjoint; the overflow colour runs on one thread.
            unsafe {
                self.bodies.with_pair(
                    a,
                    b,
                    #[inline(always)]
                    |a, b| row.solve(a, b),
                )
            };
        }
    }
}

/// A row kind as the solver sweeps it: its two bodies and its scalar kernel (one projection).
pub trait Row: Send {
    /// Indices of the row's two bodies, (a, b).
    fn bodies(&self) -> (u32, u32);
    /// One projection of the row on its two bodies.
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody);
}

impl Row for JointRow {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a, self.body_b)
    }
    #[inline(always)]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        JointRow::solve(self, a, b)
    }
}

impl Row for DamperRow {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a, self.body_b)
    }
    #[inline(always)]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        DamperRow::solve(self, a, b)
    }
}

impl Row for RodRow {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a, self.body_b)
    }
    #[inline(always)]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        RodRow::solve(self, a, b)
    }
}

impl Row for ContactPoint {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a.0, self.body_b.0)
    }
    #[inline(always)]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        ContactPoint::solve(self, a, b)
    }
}
