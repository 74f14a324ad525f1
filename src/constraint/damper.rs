//! Joint damping and joint friction across a ball-and-socket joint or a rod: a rotational
//! dashpot, the torque `tau = -k w_rel` against the two bodies' relative angular velocity (`k`
//! in N m s/rad, the scene's `joint_damping`), and Coulomb friction, a torque of at most `T`
//! (N m, the scene's `joint_friction`) against any relative turn, as a ragdoll's muscles would
//! hold a limb (Jolt's `mMaxFrictionTorque`; the Horizon Zero Dawn ragdoll ships 2.5 and 5 N m).
//!
//! Position-level form. Over a substep of `h` the dashpot's angular impulse `k w_rel h` would
//! turn the free pair by `h k w(n)` of their relative turn, with `w(n) = n . (I_a^-1 + I_b^-1) n`
//! the pair's inverse inertia along the relative spin `n = w_rel / |w_rel|`. So each substep a
//! damper row is a soft spring toward the relative orientation `q_a^-1 q_b` the substep started
//! with, which removes that fraction of the turn away from it, spread over the iterations:
//! relaxation `1 - (1 - min(h k w(n), 1))^(1 / iterations)` per iteration. The rows are solved
//! in the sweep, before the joints and rods, so the point constraints project the turn onto
//! what each joint allows: a limb hinged at its end slows at `k / (2 I_pivot)`, the damped
//! pendulum's rate (`tests/it/pendulum.rs`), and a pair keeps its total angular momentum
//! (`tests/it/conservation.rs`).
//!
//! Friction. Over a substep the friction torque's angular impulse is at most `T h`, which turns
//! the pair by at most `I^-1 T h^2` (position level). Each iteration the row asks for the whole
//! turn back to the substep's starting relative orientation, the 3 x 3 block
//! `L = (I_a^-1 + I_b^-1)^-1 e` (one row along `e` would spin a limb about its long axis, as in
//! [`super::parts::relative_rotation_across`]), and keeps the substep's accumulated impulse
//! within the ball `|L| <= T h^2` (Box2D's friction clamp): a joint whose bodies' torques stay
//! under `T` sticks, one driven harder slides with the torque `T` against it. A dashpot only
//! slows a swinging limb exponentially, and a leg hanging over a step swung for tens of seconds
//! at a dashpot that still let the pile fall (0.2 N m s/rad); friction stops it within a swing
//! or two (`tests/it/pendulum.rs`).
//!
//! Why not simpler: damping a fixed fraction of the free pair's relative spin, as an angular
//! impulse after the sweep or as this spring with a fixed relaxation, is a dashpot of
//! `k = c I_cm`; the point constraint turns the damped spin back into swing, and a hanging limb
//! slowed at `I_cm / I_pivot` of the intended rate (0.23 for a uniform limb hinged at its end, a
//! fortieth for a ball on a string).
//!
//! Stages as every kind: [`DamperRow::prepare`] (a joint's or rod's body pair),
//! [`DamperRow::begin_substep`] (rest and relaxation from the substep's starting poses),
//! [`DamperRow::solve`]. Dampers have no residual: a dashpot is never violated. The rows exist
//! only when the scene asks for damping, so the paper's method pays nothing for them.

use super::parts::relative_rotation;
use super::Constraint;
use crate::body::Body;
use crate::math::{powf, rotation_vector, Quat, Vec3};
use crate::solver_body::SolverBody;

/// The dashpot's coefficient, the friction torque and the substep they are solved over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointDamping {
    /// Torque per relative angular velocity (N m s/rad); 0: none.
    pub coefficient: f32,
    /// The most torque friction holds a joint with (N m); 0: none.
    pub friction: f32,
    /// Substep (s) and iterations per substep.
    pub h: f32,
    /// Solver iterations per substep, over which each substep's relaxation is spread.
    pub iterations: u32,
}

/// A damper as the solver stores it: a body pair and this substep's spring.
#[derive(Clone, Copy, Debug)]
pub struct DamperRow {
    /// Index of body a in the world's bodies.
    pub body_a: u32,
    /// Index of body b in the world's bodies.
    pub body_b: u32,
    /// Fraction of the turn away from `rest` removed per iteration (0: nothing this substep).
    pub relaxation: f32,
    /// Relative orientation `q_a^-1 q_b` at the substep's start.
    pub rest: Quat,
    /// The most angular impulse friction gives this substep, `T h^2` (kg m^2 rad; 0: none).
    pub friction_bound: f32,
    /// Friction's angular impulse on body b this substep (a takes the opposite).
    pub friction_impulse: Vec3,
}

impl DamperRow {
    /// The prepare stage: a damper across a joint's or rod's two bodies.
    pub fn prepare(constraint: &Constraint) -> Self {
        let (a, b) = constraint.bodies();
        DamperRow {
            body_a: a.0,
            body_b: b.0,
            relaxation: 0.0,
            rest: Quat::IDENTITY,
            friction_bound: 0.0,
            friction_impulse: Vec3::ZERO,
        }
    }

    /// Per-substep constants from the bodies' poses and velocities at the substep's start (see
    /// the module docs); an immovable body (fixed or asleep) takes no turn.
    pub fn begin_substep(&mut self, bodies: &[Body], damping: JointDamping) {
        let (a, b) = (&bodies[self.body_a as usize], &bodies[self.body_b as usize]);
        self.rest = (a.orientation.inverse() * b.orientation).normalize();
        self.relaxation = 0.0;
        self.friction_bound = damping.friction * damping.h * damping.h;
        self.friction_impulse = Vec3::ZERO;
        let relative = b.angular_velocity - a.angular_velocity;
        let speed = relative.length();
        if !(speed > 0.0 && damping.coefficient > 0.0) {
            return;
        }
        let axis = relative / speed;
        let inverse_inertia = |body: &Body| match body.is_awake_dynamic() {
            true => axis.dot(body.inverse_inertia_world() * axis),
            false => 0.0,
        };
        let per_substep =
            damping.h * damping.coefficient * (inverse_inertia(a) + inverse_inertia(b));
        if per_substep > 0.0 {
            let per_iteration = 1.0 / damping.iterations.max(1) as f32;
            self.relaxation = 1.0 - powf(1.0 - per_substep.min(1.0), per_iteration);
        }
    }

    /// One projection: removes `relaxation` of the rotation `q_a q_rest q_b^-1`, then as much
    /// of what is left as friction's bound allows (module docs).
    #[inline(always)]
    pub fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        if self.relaxation > 0.0 {
            let error = rotation_vector(a.orientation * self.rest * b.orientation.inverse());
            relative_rotation(a, b, self.relaxation * error);
        }
        if self.friction_bound > 0.0 {
            let error = rotation_vector(a.orientation * self.rest * b.orientation.inverse());
            // immovable bodies (fixed, asleep) have a zero inverse inertia in the hot array
            let k = a.inverse_inertia + b.inverse_inertia;
            let det = k.determinant();
            if !(det > 1e-20) {
                return;
            }
            let wanted = self.friction_impulse + k.inverse() * error;
            let length = wanted.length();
            let total = match length > self.friction_bound {
                true => wanted * (self.friction_bound / length),
                false => wanted,
            };
            let step = total - self.friction_impulse;
            self.friction_impulse = total;
            a.apply_angular_impulse(-step);
            b.apply_angular_impulse(step);
        }
    }
}
