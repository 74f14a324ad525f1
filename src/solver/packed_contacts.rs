//! The contact points' substep on their packed lanes, for the SIMD solver: packed once a
//! detection, then each substep begun, warm-started, solved and given its velocity pass in
//! lanes, and unpacked into the points when the frame (or, detecting every substep, the
//! substep) ends. The overflow colour's points, which may share bodies, run the scalar code
//! one by one, in their colour's turn.

use super::body::{SharedBodies, SolverBody};
use super::packed::Packed;
use crate::body::Body;
use crate::contact::{ContactPoint, SubstepStart};
use crate::solver_body::SharedSlice;

impl Packed<ContactPoint> {
    /// Step 3.2 for the contacts: each point's substep constants and reset impulses
    /// ([`ContactPoint::begin_substep`]), from the bodies' poses at the substep's start.
    pub fn begin_substep(
        &mut self,
        points: &mut [ContactPoint],
        bodies: &[Body],
        start: &SubstepStart,
        parallel: bool,
    ) {
        self.each_colour(
            points,
            parallel,
            |lanes| lanes.begin_substep(bodies, start),
            |point| point.begin_substep(bodies, start),
        );
    }

    /// Step 3.2's warm start ([`crate::contact::Contacts::warm_start`]), colour by colour, so
    /// each body takes its points' impulses in the points' order, as the scalar pass does.
    pub fn warm_start(
        &mut self,
        points: &mut [ContactPoint],
        bodies: &mut [SolverBody],
        fraction: f32,
        impact_speed: f32,
        parallel: bool,
    ) {
        let shared = SharedBodies::new(bodies);
        self.each_colour(
            points,
            parallel,
            |lanes| lanes.warm_start(shared, fraction, impact_speed),
            |point| {
                let (a, b) = (point.body_a.0, point.body_b.0);
                // SAFETY: rows of a colour share no movable body; the overflow colour runs on
                // this thread
                unsafe {
                    shared.with_pair(a, b, |a, b| point.warm_start(a, b, fraction, impact_speed))
                }
            },
        );
    }

    /// Step 3.6, the contacts' velocity pass ([`crate::contact::Contacts::velocity_pass`]).
    pub fn velocity_pass(
        &mut self,
        points: &mut [ContactPoint],
        bodies: &mut [Body],
        threshold: f32,
        parallel: bool,
    ) {
        let shared = SharedSlice::new(bodies);
        // SAFETY: within a colour no two points share an awake dynamic body, the only bodies
        // written; the overflow colour runs on this thread one point at a time.
        self.each_colour(
            points,
            parallel,
            |lanes| unsafe { lanes.velocity_pass(shared, threshold) },
            |point| unsafe { point.velocity_pass(shared, threshold) },
        );
    }
}
