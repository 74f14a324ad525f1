//! Constraint kinds. Each kind lives in its own file, opens with its maths, and offers the same
//! small set of functions: `solve(a, b)` (one projection of the preview poses) and
//! `violation(a, b)` (the residual measures). [`Constraint`] dispatches with one `match`.

pub mod ball_socket;
pub mod limits;
pub mod parts;
pub mod rod;

pub use ball_socket::{AngularSpring, BallSocket, JointFlavour};
pub use limits::AngularLimit;
pub use rod::{LengthCorrection, Rod, RodState, TwistMode};

use crate::body::{Body, BodyId};

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

#[derive(Clone, Debug)]
pub enum Constraint {
    BallSocket(BallSocket),
    Rod(Rod),
}

impl Constraint {
    pub fn name(&self) -> &str {
        match self {
            Constraint::BallSocket(joint) => &joint.name,
            Constraint::Rod(rod) => &rod.name,
        }
    }

    pub fn bodies(&self) -> (BodyId, BodyId) {
        match self {
            Constraint::BallSocket(joint) => (joint.body_a, joint.body_b),
            Constraint::Rod(rod) => (rod.body_a, rod.body_b),
        }
    }

    /// One projection of this constraint on the preview poses.
    #[inline]
    pub fn solve(&self, bodies: &mut [Body]) {
        let (ia, ib) = self.bodies();
        let (a, b) = parts::pair_mut(bodies, ia.index(), ib.index());
        match self {
            Constraint::BallSocket(joint) => joint.solve(a, b),
            Constraint::Rod(rod) => rod.solve(a, b),
        }
    }

    pub fn violation(&self, bodies: &[Body]) -> Violation {
        let (ia, ib) = self.bodies();
        let (a, b) = (&bodies[ia.index()], &bodies[ib.index()]);
        match self {
            Constraint::BallSocket(joint) => joint.violation(a, b),
            Constraint::Rod(rod) => rod.violation(a, b),
        }
    }
}
