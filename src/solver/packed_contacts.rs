//! The contact points' substep on their packed lanes, for the SIMD solver: packed once a
//! detection, then each substep begun, warm-started, solved and given its velocity pass in
//! lanes, and unpacked into the points when the frame (or, detecting every substep, the
//! substep) ends. The overflow colour's points, which may share bodies, run the scalar code
//! one by one, in their colour's turn. Also the joints' substep start, on their lanes.

use super::body::{SharedBodies, SolverBody};
use super::packed::{BatchWork, Packed};
use crate::body::Body;
use crate::constraint::ball_socket_lanes::JointLanes;
use crate::constraint::JointRow;
use crate::contact::lanes::ContactLanes;
use crate::contact::{ContactPoint, SubstepStart};
use crate::lanes::Lane;
use crate::solver_body::SharedSlice;

/// Step 3.2 for the contacts ([`ContactPoint::begin_substep`]).
struct Begin<'a> {
    bodies: &'a [Body],
    start: &'a SubstepStart,
}

impl<L: Lane> BatchWork<ContactPoint, L> for Begin<'_> {
    #[inline(always)]
    fn batch(&self, lanes: &mut ContactLanes<L>) {
        lanes.begin_substep(self.bodies, self.start)
    }
    #[inline(always)]
    fn row(&self, point: &mut ContactPoint) {
        point.begin_substep(self.bodies, self.start)
    }
}

/// Step 3.2's warm start ([`crate::contact::Contacts::warm_start`]).
struct WarmStart {
    bodies: SharedBodies,
    fraction: f32,
    impact_speed: f32,
}

impl<L: Lane> BatchWork<ContactPoint, L> for WarmStart {
    #[inline(always)]
    fn batch(&self, lanes: &mut ContactLanes<L>) {
        lanes.warm_start(self.bodies, self.fraction, self.impact_speed)
    }
    #[inline(always)]
    fn row(&self, point: &mut ContactPoint) {
        let (a, b) = (point.body_a.0, point.body_b.0);
        let (fraction, impact_speed) = (self.fraction, self.impact_speed);
        // SAFETY: rows of a colour share no movable body; the overflow colour runs on this
        // thread
        unsafe {
            self.bodies.with_pair(
                a,
                b,
                #[inline(always)]
                |a, b| point.warm_start(a, b, fraction, impact_speed),
            )
        }
    }
}

/// Step 3.6 ([`crate::contact::Contacts::velocity_pass`]).
struct VelocityPass {
    bodies: SharedSlice<Body>,
    threshold: f32,
}

impl<L: Lane> BatchWork<ContactPoint, L> for VelocityPass {
    #[inline(always)]
    fn batch(&self, lanes: &mut ContactLanes<L>) {
        // SAFETY: within a colour no two points share an awake dynamic body, the only bodies
        // written; the overflow colour runs on this thread one point at a time.
        unsafe { lanes.velocity_pass(self.bodies, self.threshold) }
    }
    #[inline(always)]
    fn row(&self, point: &mut ContactPoint) {
        // SAFETY: as in `batch`
        unsafe { point.velocity_pass(self.bodies, self.threshold) }
    }
}

impl<L: Lane> Packed<ContactPoint, L> {
    /// Step 3.2 for the contacts: each point's substep constants and reset impulses
    /// ([`ContactPoint::begin_substep`]), from the bodies' poses at the substep's start.
    pub fn begin_substep(
        &mut self,
        points: &mut [ContactPoint],
        bodies: &[Body],
        start: &SubstepStart,
        parallel: bool,
    ) {
        self.each_colour(points, parallel, &Begin { bodies, start });
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
        let work = WarmStart {
            bodies: SharedBodies::new(bodies),
            fraction,
            impact_speed,
        };
        self.each_colour(points, parallel, &work);
    }

    /// Step 3.6, the contacts' velocity pass ([`crate::contact::Contacts::velocity_pass`]).
    pub fn velocity_pass(
        &mut self,
        points: &mut [ContactPoint],
        bodies: &mut [Body],
        threshold: f32,
        parallel: bool,
    ) {
        let work = VelocityPass {
            bodies: SharedSlice::new(bodies),
            threshold,
        };
        self.each_colour(points, parallel, &work);
    }
}

/// Step 3.2 for the joints: the limits' starting twist, in the lanes packed once a frame.
struct BeginJoints<'a>(&'a [Body]);

impl<L: Lane> BatchWork<JointRow, L> for BeginJoints<'_> {
    #[inline(always)]
    fn batch(&self, lanes: &mut JointLanes<L>) {
        lanes.begin_substep(self.0)
    }
    #[inline(always)]
    fn row(&self, row: &mut JointRow) {
        row.begin_substep(self.0)
    }
}

impl<L: Lane> Packed<JointRow, L> {
    /// Step 3.2 for the joints ([`JointRow::begin_substep`]).
    pub fn begin_substep(&mut self, rows: &mut [JointRow], bodies: &[Body], parallel: bool) {
        self.each_colour(rows, parallel, &BeginJoints(bodies));
    }
}
