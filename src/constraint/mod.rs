//! Constraint kinds. Each kind lives in its own file, opens with its maths, and offers the same
//! small set of stages: `prepare` (the user's definition, with its name, flattened into a row
//! the solver stores per kind), `solve(a, b)` on the row (one projection of two
//! [`SolverBody`]s' preview poses) and `violation(a, b)` (the residual measures). The `*_lanes`
//! files solve W rows of a kind at once (paper §7).

pub mod ball_socket;
pub mod ball_socket_lanes;
pub mod damper;
pub mod limits;
mod list;
pub mod parts;
pub mod rod;
pub mod rod_lanes;

pub use ball_socket::{AngularSpring, BallSocket, JointFlavour, JointRow};
pub use damper::{DamperRow, JointDamping};
pub use limits::AngularLimit;
pub use list::Constraints;
pub use rod::{
    BendTwist, LengthCorrection, Rod, RodParams, RodRow, RodState, Stiffness, TwistMode,
};

use crate::body::{Body, BodyId};
use crate::solver_body::SolverBody;

/// Residual of one constraint after a frame's iterations (paper Fig. 8).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Violation {
    /// Positional error (m): distance between joint anchors.
    pub dislocation: f32,
    /// Violation of hard angular constraints (rad).
    pub angular: f32,
}

impl std::ops::AddAssign for Violation {
    fn add_assign(&mut self, rhs: Self) {
        self.dislocation += rhs.dislocation;
        self.angular += rhs.angular;
    }
}

/// A constraint between two bodies, of one of the kinds.
#[derive(Clone, Debug)]
pub enum Constraint {
    /// A ball-and-socket joint, with its optional limit and spring.
    BallSocket(BallSocket),
    /// A rod (paper §5).
    Rod(Rod),
}

impl Constraint {
    /// The constraint's name, used in error messages and recordings.
    pub fn name(&self) -> &str {
        match self {
            Constraint::BallSocket(joint) => &joint.name,
            Constraint::Rod(rod) => &rod.name,
        }
    }

    /// The two bodies it joins, (a, b).
    pub fn bodies(&self) -> (BodyId, BodyId) {
        match self {
            Constraint::BallSocket(joint) => (joint.body_a, joint.body_b),
            Constraint::Rod(rod) => (rod.body_a, rod.body_b),
        }
    }

    /// Whether its two bodies never collide: every constraint but a joint that asks to
    /// (`collide_connected`).
    pub fn keeps_bodies_apart(&self) -> bool {
        !matches!(self, Constraint::BallSocket(joint) if joint.collide_connected)
    }

    /// One projection of this constraint on the bodies' poses, outside a step (tests and tools;
    /// the solver works on rows and [`SolverBody`]s): the poses are the preview, and get the
    /// projection. Limits unwrap their twist against the bodies' orientations.
    pub fn solve(&self, bodies: &mut [Body]) {
        let (ia, ib) = self.bodies();
        let (a, b) = parts::pair_mut(bodies, ia.index(), ib.index());
        let (mut sa, mut sb) = (SolverBody::from_body(a), SolverBody::from_body(b));
        match self {
            Constraint::BallSocket(joint) => {
                let mut row = joint.prepare();
                let start = (a.orientation * row.frame_a, b.orientation * row.frame_b);
                row.start_twist = AngularLimit::start_twist(start.0, start.1);
                row.solve(&mut sa, &mut sb);
            }
            Constraint::Rod(rod) => rod.prepare().solve(&mut sa, &mut sb),
        }
        sa.write_pose(a);
        sb.write_pose(b);
    }

    /// The residual (paper Fig. 8): dislocation (m) and angular violation (rad).
    pub fn violation(&self, bodies: &[Body]) -> Violation {
        let (ia, ib) = self.bodies();
        let (a, b) = (&bodies[ia.index()], &bodies[ib.index()]);
        match self {
            Constraint::BallSocket(joint) => joint.violation(a, b),
            Constraint::Rod(rod) => rod.violation(a, b),
        }
    }

    /// The dislocation alone (m), cheaper than [`Constraint::violation`]: the anchors' gap of
    /// a joint, a rod's length error (eq. 9).
    pub fn dislocation(&self, bodies: &[Body]) -> f32 {
        let (ia, ib) = self.bodies();
        let (a, b) = (&bodies[ia.index()], &bodies[ib.index()]);
        match self {
            Constraint::BallSocket(joint) => {
                let (pa, pb) = joint.world_anchors(a, b);
                (pb - pa).length()
            }
            Constraint::Rod(rod) => rod.state(a, b).length_error.abs(),
        }
    }
}
