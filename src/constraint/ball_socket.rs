//! Ball-and-socket joint: two body-space anchors held at one world point, with optional
//! swing-twist (or hinge) limits and an optional soft angular spring.
//!
//! Point constraint: `C = (p_b + R_b a_b) - (p_a + R_a a_a) = 0` (3 rows).
//! Jacobian per body i: `J_i = [+-E, -+[r_i]]` with `r_i = R_i a_i`, so the inverse
//! effective mass is `K = sum_i (1/m_i E - [r_i] I_i^-1 [r_i])`.
//!
//! Two flavours ([`JointFlavour`]):
//! - `Cheap`: one scalar row along the current error direction `n = C / |C|`, weight
//!   `w = sum_i 1/m_i + (r_i x n) . I_i^-1 (r_i x n)`; the three rows' coupling is ignored, so a
//!   chain converges slowly (the paper's §8 kind).
//! - `Exact`: the 3x3 block `P = K^-1 C`; a hinge limit's two rows also as one block
//!   ([`super::limits`]).
//!
//! Soft spring toward the rest relative orientation `q_rest = q_a^-1 q_b` taken at creation
//! (§6: instantiated at the transition pose): each iteration removes the fraction `relaxation`
//! of the rotation `q_a q_rest q_b^-1`, the same relaxation-factor idea as the rod's alpha_b.
//!
//! A spring with relaxation 1 is a hard angular target (the paper's "internal torque
//! constraints" of §8) and its error counts as angular violation.
//!
//! Solve order per iteration: spring, limits, point, so the dislocation is the freshest.
//!
//! Stages: [`BallSocket::prepare`] flattens the joint into a [`JointRow`] (body indices, no
//! name) once per frame; [`JointRow::begin_substep`] takes the limit's starting twist;
//! [`JointRow::solve`] projects the preview poses each iteration; [`BallSocket::violation`]
//! measures. `ball_socket_lanes.rs` is the same solve on W joints at once.

use super::limits::AngularLimit;
use super::parts::{point_along_error, point_block, relative_rotation};
use super::Violation;
use crate::body::{Body, BodyId};
use crate::math::{rotation_vector, Quat, Vec3};
use crate::solver_body::SolverBody;

/// How the point part is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum JointFlavour {
    /// One scalar row along the current error direction; ignores the rows' coupling, so chains
    /// converge slowly (§8).
    Cheap,
    /// The full 3x3 block `P = K^-1 C`, and a hinge's axes aligned as one 2x2 block.
    #[default]
    Exact,
}

impl std::fmt::Display for JointFlavour {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            JointFlavour::Cheap => "cheap",
            JointFlavour::Exact => "exact",
        })
    }
}

/// Soft angular spring toward a rest relative orientation, taken at the transition pose (§6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngularSpring {
    /// Fraction of the angular error removed per iteration, in [0, 1].
    pub relaxation: f32,
    /// Rest relative orientation `q_a^-1 q_b`.
    pub rest: Quat,
}

/// A ball-and-socket joint between two bodies, with an optional angular limit and spring.
#[derive(Clone, Debug)]
pub struct BallSocket {
    /// Name, for failure reports and recordings.
    pub name: String,
    /// First body.
    pub body_a: BodyId,
    /// Second body.
    pub body_b: BodyId,
    /// Anchor in body a's space (m, from its centre of mass).
    pub local_anchor_a: Vec3,
    /// Anchor in body b's space (m, from its centre of mass).
    pub local_anchor_b: Vec3,
    /// Joint frame in each body; its x axis is the twist or hinge axis.
    pub local_frame_a: Quat,
    /// Joint frame in body b (see `local_frame_a`).
    pub local_frame_b: Quat,
    /// How the point part is solved.
    pub flavour: JointFlavour,
    /// Optional swing-twist (or hinge) limit on the joint frames.
    pub limit: Option<AngularLimit>,
    /// Optional soft spring toward the rest relative orientation.
    pub spring: Option<AngularSpring>,
    /// Whether the two bodies may collide with each other (off for ragdoll neighbours).
    pub collide_connected: bool,
}

impl BallSocket {
    /// A joint at world point `anchor` whose frame is `frame` (world rotation; x = twist axis),
    /// both taken from the bodies' current poses.
    pub fn at_world_anchor(
        name: impl Into<String>,
        bodies: &[Body],
        body_a: BodyId,
        body_b: BodyId,
        anchor: Vec3,
        frame: Quat,
    ) -> Self {
        let (a, b) = (&bodies[body_a.index()], &bodies[body_b.index()]);
        let (qa_inv, qb_inv) = (a.orientation.inverse(), b.orientation.inverse());
        BallSocket {
            name: name.into(),
            body_a,
            body_b,
            local_anchor_a: qa_inv * (anchor - a.position),
            local_anchor_b: qb_inv * (anchor - b.position),
            local_frame_a: (qa_inv * frame).normalize(),
            local_frame_b: (qb_inv * frame).normalize(),
            flavour: JointFlavour::Exact,
            limit: None,
            spring: None,
            collide_connected: false,
        }
    }

    /// Adds a spring whose rest pose is the bodies' current relative orientation.
    pub fn with_spring(mut self, bodies: &[Body], relaxation: f32) -> Self {
        let (a, b) = (&bodies[self.body_a.index()], &bodies[self.body_b.index()]);
        self.spring = Some(AngularSpring {
            relaxation,
            rest: (a.orientation.inverse() * b.orientation).normalize(),
        });
        self
    }

    /// Adds a swing-twist (or hinge) limit on the joint frames.
    pub fn with_limit(mut self, limit: AngularLimit) -> Self {
        self.limit = Some(limit);
        self
    }

    /// Sets how the point part is solved.
    pub fn with_flavour(mut self, flavour: JointFlavour) -> Self {
        self.flavour = flavour;
        self
    }

    /// The prepare stage: the joint as the solver stores it.
    pub fn prepare(&self) -> JointRow {
        JointRow {
            body_a: self.body_a.0,
            body_b: self.body_b.0,
            anchor_a: self.local_anchor_a,
            anchor_b: self.local_anchor_b,
            frame_a: self.local_frame_a,
            frame_b: self.local_frame_b,
            limit: self.limit,
            start_twist: 0.0,
            spring: self.spring,
            flavour: self.flavour,
        }
    }

    /// World anchor points (a, b) at the preview pose (equal to the pose after a step).
    pub fn world_anchors(&self, a: &Body, b: &Body) -> (Vec3, Vec3) {
        (
            a.world_point(self.local_anchor_a),
            b.world_point(self.local_anchor_b),
        )
    }

    /// Residual at the preview poses: anchor gap (m) and angular error (rad) of the limit and of a
    /// hard (relaxation 1) spring.
    pub fn violation(&self, a: &Body, b: &Body) -> Violation {
        let (pa, pb) = self.world_anchors(a, b);
        let mut angular = self.limit.map_or(0.0, |limit| {
            limit.violation(
                a.orientation * self.local_frame_a,
                b.orientation * self.local_frame_b,
            )
        });
        if let Some(spring) = self.spring.filter(|s| s.relaxation >= 1.0) {
            // A spring with relaxation 1 is a hard angular target: its error counts.
            let error = a.orientation * spring.rest * b.orientation.inverse();
            angular += rotation_vector(error).length();
        }
        Violation {
            dislocation: (pb - pa).length(),
            angular,
        }
    }
}

/// A ball-and-socket joint as the solver stores it (hot data: indices, no name).
#[derive(Clone, Copy, Debug)]
pub struct JointRow {
    /// Index of body a in the world's bodies.
    pub body_a: u32,
    /// Index of body b in the world's bodies.
    pub body_b: u32,
    /// Anchor in body a's space (m).
    pub anchor_a: Vec3,
    /// Anchor in body b's space (m).
    pub anchor_b: Vec3,
    /// Joint frame in body a; x is the twist or hinge axis.
    pub frame_a: Quat,
    /// Joint frame in body b; x is the twist or hinge axis.
    pub frame_b: Quat,
    /// Optional swing-twist (or hinge) limit on the joint frames.
    pub limit: Option<AngularLimit>,
    /// Twist of the joint frames at the substep's start (limits unwrap against it).
    pub start_twist: f32,
    /// Optional soft spring toward the rest relative orientation.
    pub spring: Option<AngularSpring>,
    /// How the point part is solved.
    pub flavour: JointFlavour,
}

impl JointRow {
    /// Per-substep constants, from the bodies' poses at the substep's start.
    pub fn begin_substep(&mut self, bodies: &[Body]) {
        if self.limit.is_some() {
            let (a, b) = (&bodies[self.body_a as usize], &bodies[self.body_b as usize]);
            self.start_twist = AngularLimit::start_twist(
                a.orientation * self.frame_a,
                b.orientation * self.frame_b,
            );
        }
    }

    /// One projection of the preview poses: spring, limits, then the point.
    #[inline(always)]
    pub fn solve(&self, a: &mut SolverBody, b: &mut SolverBody) {
        if let Some(spring) = self.spring {
            let target_b = a.orientation * spring.rest;
            let error = rotation_vector(target_b * b.orientation.inverse());
            relative_rotation(a, b, spring.relaxation * error);
        }
        if let Some(limit) = self.limit {
            let hinge_block = self.flavour == JointFlavour::Exact;
            limit.solve(
                a,
                b,
                self.frame_a,
                self.frame_b,
                self.start_twist,
                hinge_block,
            );
        }
        let ra = a.orientation * self.anchor_a;
        let rb = b.orientation * self.anchor_b;
        let d = (b.position + rb) - (a.position + ra);
        match self.flavour {
            JointFlavour::Cheap => point_along_error(a, b, ra, rb, d, 1.0),
            JointFlavour::Exact => point_block(a, b, ra, rb, d, 1.0),
        }
    }
}
