//! PLACEHOLDER: RodRow rows W at a time. Solves lane by lane with the scalar kernel until the
//! branch-free SIMD kernel lands.

use crate::solver::body::SharedBodies;

pub fn solve_batch(rows: &mut [super::RodRow], bodies: SharedBodies) {
    for row in rows {
        let (a, b) = crate::solver::RowBodies::bodies(row);
        // SAFETY: the batch's rows share no movable body.
        unsafe { bodies.with_pair(a, b, |a, b| row.solve(a, b)) };
    }
}

/// PLACEHOLDER: `L::W` rows, lane by lane.
pub fn solve_lanes<L: crate::solver::lanes::Lane>(
    rows: &mut [super::RodRow],
    bodies: SharedBodies,
) {
    solve_batch(rows, bodies)
}
