//! Rigid bodies in maximal coordinates (paper §4): x_i = {p_i, q_i}, the position of the centre
//! of mass and a unit quaternion, with mass m_i and body-space inertia I_i.
//!
//! The body frame is the shape's principal frame, so the body-space inertia is diagonal.
//! The world inverse inertia `R I^-1 R^T` is refreshed whenever the orientation changes (the
//! solver's commit, a teleport). The solver's preview poses live in its own hot array
//! ([`crate::solver_body::SolverBody`]); between steps a body holds its pose alone.

use crate::math::{Mat3, Quat, Vec3};
use crate::shape::Shape;

/// Index of a body in [`crate::world::World::bodies`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub u32);

impl BodyId {
    /// The index as a `usize`, for indexing the world's body list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// How the solver treats a body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyKind {
    /// Moved by forces and constraints.
    Dynamic,
    /// Never moves; infinite mass.
    Fixed,
    /// Moves with its prescribed velocity; infinite mass for constraints.
    Kinematic,
}

/// A rigid body (paper §4): pose, velocities, mass properties and contact material.
///
/// `repr(C)`, with what every substep reads and writes first (pose, velocities, mass and
/// inertia), so the solver's per-body passes touch its first 132 bytes (the 1000-ragdoll rain:
/// 0.96x the time with the compiler's field order). A float follows each `Vec3`, never the
/// kind or the sleep flag (why: [`crate::contact::handover::Handed`]).
#[derive(Clone, Debug)]
#[repr(C)]
pub struct Body {
    /// Unit quaternion q_i turning body space into world space.
    pub orientation: Quat,
    /// World position p_i of the centre of mass (m).
    pub position: Vec3,
    pub(crate) inverse_mass: f32,
    /// Velocity of the centre of mass (m/s, world).
    pub linear_velocity: Vec3,
    /// Angular velocity (rad/s, world axes).
    pub angular_velocity: Vec3,
    pub(crate) inverse_inertia_world: Mat3,
    /// Dynamic, fixed or kinematic.
    pub kind: BodyKind,
    // --- Sleeping (see [`crate::sleep`]) ---
    /// Out of the step until its island wakes: no integration, no rows, immovable to others.
    pub(crate) asleep: bool,
    /// Principal moments of inertia in body space.
    pub inertia: Vec3,
    pub(crate) inverse_inertia_body: Vec3,
    /// External force applied every step until changed (N), on top of gravity.
    pub external_force: Vec3,
    // --- Cold: read once a frame or less ---
    /// Mass m_i (kg); only a dynamic body's is used.
    pub mass: f32,
    /// Collision and mass shape, in body space with the centre of mass at the origin.
    pub shape: Shape,
    /// Coulomb friction coefficients (combined per pair as geometric means).
    pub static_friction: f32,
    /// Sliding friction coefficient mu_d: the cap on friction once the static cone is exceeded.
    pub dynamic_friction: f32,
    /// Coefficient of restitution in [0, 1] (a pair uses the larger of its two).
    pub restitution: f32,
    /// Collision filter: a pair collides if each one's group bits meet the other's mask bits.
    pub collision_group: u32,
    /// Collision filter mask bits, tested against the other body's group bits.
    pub collision_mask: u32,
    /// How long (s) the body's sleep test points have stayed within their spheres.
    pub(crate) still_for: f32,
    /// The sleep test's bounding spheres (centre, radius) of where its three test points have
    /// been in the current window ([`crate::sleep`]).
    pub(crate) sleep_spheres: [(Vec3, f32); 3],
    /// How long (s) the current window of the sleep test has run.
    pub(crate) sleep_window: f32,
    /// The island it fell asleep with (a body index, the island's union-find root).
    pub(crate) sleep_island: u32,
    /// Name, used in error messages and reports.
    pub name: String,
}

impl Body {
    /// A body with the given shape and mass (ignored unless dynamic), at rest at `position`.
    pub fn new(name: impl Into<String>, kind: BodyKind, shape: Shape, mass: f32) -> Self {
        let inertia = shape.principal_inertia(mass);
        let dynamic = kind == BodyKind::Dynamic;
        let mut body = Body {
            name: name.into(),
            kind,
            shape,
            mass,
            inertia,
            position: Vec3::ZERO,
            orientation: Quat::IDENTITY,
            linear_velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
            external_force: Vec3::ZERO,
            static_friction: 0.6,
            dynamic_friction: 0.5,
            restitution: 0.0,
            collision_group: 1,
            collision_mask: u32::MAX,
            inverse_mass: if dynamic { 1.0 / mass } else { 0.0 },
            inverse_inertia_body: if dynamic { inertia.recip() } else { Vec3::ZERO },
            inverse_inertia_world: Mat3::ZERO,
            asleep: false,
            still_for: 0.0,
            sleep_spheres: [(Vec3::ZERO, 0.0); 3],
            sleep_window: 0.0,
            sleep_island: 0,
        };
        body.set_pose(Vec3::ZERO, Quat::IDENTITY);
        body
    }

    /// [`Body::set_pose`] in builder form.
    pub fn with_pose(mut self, position: Vec3, orientation: Quat) -> Self {
        self.set_pose(position, orientation);
        self
    }

    /// Teleports the body, waking it (its island wakes next step).
    pub fn set_pose(&mut self, position: Vec3, orientation: Quat) {
        self.asleep = false;
        self.still_for = 0.0;
        self.position = position;
        self.orientation = orientation.normalize();
        self.update_world_inertia();
    }

    /// Changes the mass, scaling the inertia with it.
    pub fn set_mass(&mut self, mass: f32) {
        self.mass = mass;
        self.inertia = self.shape.principal_inertia(mass);
        self.update_inverse_mass();
    }

    /// Sets the principal moments of inertia (kg m^2, along the body's axes), for a body whose
    /// mass is not spread as its shape's.
    pub fn set_inertia(&mut self, inertia: Vec3) {
        self.inertia = inertia;
        self.update_inverse_mass();
    }

    /// Makes the body dynamic, kinematic or fixed, its inverse mass and inertia with it (a
    /// clip's kinematic bodies handed to physics, [`crate::playback`]).
    pub fn set_kind(&mut self, kind: BodyKind) {
        self.kind = kind;
        self.asleep = false;
        self.still_for = 0.0;
        self.update_inverse_mass();
    }

    /// The inverse mass and inertia from the mass, the inertia and the kind (zero unless
    /// dynamic).
    fn update_inverse_mass(&mut self) {
        let dynamic = self.kind == BodyKind::Dynamic;
        self.inverse_mass = if dynamic { 1.0 / self.mass } else { 0.0 };
        self.inverse_inertia_body = match dynamic {
            true => self.inertia.recip(),
            false => Vec3::ZERO,
        };
        self.update_world_inertia();
    }

    /// Whether the body is dynamic (asleep or awake).
    pub fn is_dynamic(&self) -> bool {
        self.kind == BodyKind::Dynamic
    }

    /// How long (s) the body has passed the sleep test ([`crate::sleep`]); 0 while it moves.
    pub fn still_for(&self) -> f32 {
        self.still_for
    }

    /// Whether the body is asleep (see [`crate::sleep`]); only dynamic bodies sleep.
    pub fn is_asleep(&self) -> bool {
        self.asleep
    }

    /// A dynamic body that is awake: the solver moves it.
    pub fn is_awake_dynamic(&self) -> bool {
        self.kind == BodyKind::Dynamic && !self.asleep
    }

    /// Moves this step: an awake dynamic body, or a kinematic body with a velocity. What the
    /// broad phase pairs, and what wakes a sleeping island it reaches.
    pub fn moves_this_step(&self) -> bool {
        self.is_awake_dynamic()
            || (self.kind == BodyKind::Kinematic
                && (self.linear_velocity != Vec3::ZERO || self.angular_velocity != Vec3::ZERO))
    }

    /// 1 / m (1/kg); zero unless dynamic.
    pub fn inverse_mass(&self) -> f32 {
        self.inverse_mass
    }

    /// World inverse inertia `R I^-1 R^T` (1/(kg m^2)) at the current orientation; zero unless
    /// dynamic.
    pub fn inverse_inertia_world(&self) -> Mat3 {
        self.inverse_inertia_world
    }

    /// World inertia tensor `R I R^T` at the current orientation.
    pub fn inertia_world(&self) -> Mat3 {
        let r = Mat3::from_quat(self.orientation);
        r * Mat3::from_diagonal(self.inertia) * r.transpose()
    }

    /// Recomputes `R I^-1 R^T` from the orientation.
    #[inline(always)]
    pub(crate) fn update_world_inertia(&mut self) {
        let r = Mat3::from_quat(self.orientation);
        self.inverse_inertia_world =
            r * Mat3::from_diagonal(self.inverse_inertia_body) * r.transpose();
    }

    /// Linear momentum `m v` (kg m/s).
    pub fn linear_momentum(&self) -> Vec3 {
        self.mass * self.linear_velocity
    }

    /// Angular momentum about the world origin: `I w + p x m v`.
    pub fn angular_momentum(&self) -> Vec3 {
        self.inertia_world() * self.angular_velocity + self.position.cross(self.linear_momentum())
    }

    /// Kinetic energy, translational plus rotational (J); zero unless dynamic.
    pub fn kinetic_energy(&self) -> f32 {
        if !self.is_dynamic() {
            return 0.0;
        }
        0.5 * self.mass * self.linear_velocity.length_squared()
            + 0.5
                * self
                    .angular_velocity
                    .dot(self.inertia_world() * self.angular_velocity)
    }

    /// Potential energy in a uniform field `gravity` (zero at the origin).
    pub fn potential_energy(&self, gravity: Vec3) -> f32 {
        if !self.is_dynamic() {
            return 0.0;
        }
        -self.mass * gravity.dot(self.position)
    }

    /// An upper bound (m/s) on the speed of any point of the body's shape: `|v| + |w x r|` at
    /// the furthest reach, with a capsule's spin about its own axis reaching only its radius.
    /// The measure of "at rest": a limb twitching about its long axis moves its surface at
    /// `w r`, a limb swinging moves its ends at `w (h + r)`.
    pub fn max_point_speed(&self) -> f32 {
        let w = self.angular_velocity;
        let spin = match self.shape {
            Shape::Sphere { radius } => w.length() * radius,
            Shape::Capsule {
                half_height,
                radius,
                ..
            } => {
                let (along, across) = self.spin_about_and_across_axis();
                across * (half_height + radius) + along * radius
            }
            Shape::Cuboid { half_extents } => w.length() * half_extents.length(),
            Shape::HalfSpace => 0.0,
        };
        self.linear_velocity.length() + spin
    }

    /// Angular speed (rad/s) about a capsule's own axis and across it; for other shapes all of
    /// it counts as across.
    pub fn spin_about_and_across_axis(&self) -> (f32, f32) {
        let w = self.angular_velocity;
        let along = match self.shape {
            Shape::Capsule { axis, .. } => (self.orientation * axis.unit()).dot(w),
            _ => 0.0,
        };
        (
            along.abs(),
            (w.length_squared() - along * along).max(0.0).sqrt(),
        )
    }

    /// A cheap bound on how fast spin moves a surface point (m/s): `|w|` times the shape's
    /// bounding radius, 0 for a body that does not turn (for speculative contact reach).
    #[inline]
    pub fn spin_speed_bound(&self) -> f32 {
        let w = self.angular_velocity.length_squared();
        match w > 0.0 {
            true => w.sqrt() * self.shape.bounding_radius(),
            false => 0.0,
        }
    }

    /// The sleep test's points at the current pose: the centre of mass and the ends of the
    /// shape's two longest half extents ([`Shape::sleep_test_offsets`]).
    pub fn sleep_test_points(&self) -> [Vec3; 3] {
        let [a, b] = self.shape.sleep_test_offsets();
        let turn = |p: Vec3| self.position + self.orientation * p;
        [self.position, turn(a), turn(b)]
    }

    /// World position of a body-space point at the current pose.
    pub fn world_point(&self, local: Vec3) -> Vec3 {
        self.position + self.orientation * local
    }

    /// Applies a velocity impulse `impulse` (N s) at world offset `r`: dv = P / m,
    /// dw = I^-1 (r x P), with the inverse inertia at the current orientation.
    pub(crate) fn apply_velocity_impulse(&mut self, impulse: Vec3, r: Vec3) {
        self.linear_velocity += impulse * self.inverse_mass;
        self.angular_velocity += self.inverse_inertia_world * r.cross(impulse);
    }

    /// Generalised inverse mass for a positional correction along unit `n` at offset `r`.
    #[inline]
    pub(crate) fn positional_inverse_mass(&self, r: Vec3, n: Vec3) -> f32 {
        let rn = r.cross(n);
        self.inverse_mass + rn.dot(self.inverse_inertia_world * rn)
    }
}

const _: () = assert!(std::mem::size_of::<Body>() == 256);

#[cfg(test)]
mod tests {
    use super::*;

    /// What follows each `Vec3` of the hot part is a float (a scalar, a vector or the inertia
    /// matrix), never the kind or the sleep flag ([`Body`]'s field order).
    #[test]
    fn a_float_follows_each_vector() {
        crate::math::assert_float_follows!(Body:
            position => inverse_mass,
            linear_velocity => angular_velocity,
            angular_velocity => inverse_inertia_world,
            inertia => inverse_inertia_body,
            inverse_inertia_body => external_force,
            external_force => mass,
        );
    }
}
