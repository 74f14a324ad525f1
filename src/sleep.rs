//! Sleeping: islands of bodies that have stayed still are taken out of the step (Box2D's solver
//! sets, Rapier's islands), so a settled pile costs almost nothing.
//!
//! Once a frame, after the solver (step 5 of [`crate::solver`]'s order), when the scene turns
//! sleeping on:
//! 1. **Wake.** A sleeping island wakes when something awake reaches it: a contact point or a
//!    joint or rod between one of its bodies and an awake dynamic body or a moving kinematic
//!    body, or a force, a velocity or a teleport given to one of its bodies by the user
//!    ([`Body::set_pose`] wakes the body itself; its joints and contacts wake the rest).
//! 2. **Timers.** Every awake dynamic body counts how long its fastest surface point has stayed
//!    under [`SLEEP_SPEED`]; a faster frame resets the count.
//! 3. **Islands.** Union-find over the awake dynamic bodies, joined by every joint, rod and
//!    contact point between two of them (fixed and kinematic bodies join nothing: a floor does
//!    not tie the whole pile into one island).
//! 4. **Sleep.** An island all of whose bodies have been still for [`TIME_TO_SLEEP`] falls
//!    asleep: velocities zeroed, poses kept.
//!
//! A sleeping body is immovable to the solver: it is not integrated, its joints and rods with
//! other sleeping or fixed bodies make no rows, and the broad phase reports no pair unless an
//! awake dynamic body or a moving kinematic body is in it. What remains per sleeping body is its
//! broad-phase entry and these per-frame checks.

use crate::body::{Body, BodyId};
use crate::constraint::Constraint;
use crate::contact::Contacts;
use crate::math::Vec3;

/// A body is still while its fastest surface point moves slower than this (m/s; Box2D v3's
/// default sleep threshold).
pub const SLEEP_SPEED: f32 = 0.05;

/// An island falls asleep once every body in it has been still this long (s).
pub const TIME_TO_SLEEP: f32 = 0.5;

/// An awake dynamic body whose fastest surface point is at or over [`SLEEP_SPEED`]: what keeps
/// its island awake. The speeds split the point speed into its parts, so a user can tell a
/// sliding body (centre) from one turning about its long axis (a capsule's axial spin barely
/// moves its surface, while the same turn across the axis swings its ends).
#[derive(Clone, Debug, PartialEq)]
pub struct Restless {
    pub body: BodyId,
    /// Fastest surface point (m/s), as the sleep timers read it.
    pub point_speed: f32,
    /// Speed of the centre of mass (m/s).
    pub centre_speed: f32,
    /// Angular speed (rad/s) about a capsule's own axis (zero for other shapes), and across it.
    pub axial_spin: f32,
    pub cross_spin: f32,
}

/// The awake dynamic bodies too fast to fall asleep, fastest first.
pub fn restless_bodies(bodies: &[Body]) -> Vec<Restless> {
    let mut restless: Vec<Restless> = (bodies.iter().enumerate())
        .filter(|(_, b)| b.is_awake_dynamic() && b.max_point_speed() >= SLEEP_SPEED)
        .map(|(i, b)| {
            let (axial_spin, cross_spin) = b.spin_about_and_across_axis();
            Restless {
                body: BodyId(i as u32),
                point_speed: b.max_point_speed(),
                centre_speed: b.linear_velocity.length(),
                axial_spin,
                cross_spin,
            }
        })
        .collect();
    restless.sort_by(|a, b| b.point_speed.total_cmp(&a.point_speed));
    restless
}

/// Reused storage for the once-a-frame sleep pass.
#[derive(Clone, Debug, Default)]
pub struct Islands {
    /// Union-find parent per body.
    parent: Vec<u32>,
    /// Per island root: the shortest time any of its bodies has been still.
    still_for: Vec<f32>,
    /// Per island id (a root at the time it fell asleep): wake it this frame.
    wake: Vec<bool>,
    any_asleep: bool,
}

impl Islands {
    /// Steps 1-4 of the module docs, once per frame of `dt`. Returns the awake dynamic bodies.
    pub fn update(
        &mut self,
        dt: f32,
        bodies: &mut [Body],
        constraints: &[Constraint],
        contacts: &Contacts,
    ) -> usize {
        let pairs = || {
            let joined = constraints.iter().map(|c| {
                let (a, b) = c.bodies();
                (a.0, b.0)
            });
            joined.chain(contacts.points.iter().map(|p| (p.body_a.0, p.body_b.0)))
        };
        if self.any_asleep {
            self.wake_reached(bodies, pairs());
        }
        for body in bodies.iter_mut().filter(|b| b.is_awake_dynamic()) {
            body.still_for = if body.max_point_speed() < SLEEP_SPEED {
                body.still_for + dt
            } else {
                0.0
            };
        }
        self.parent.clear();
        self.parent.extend(0..bodies.len() as u32);
        for (a, b) in pairs() {
            if bodies[a as usize].is_awake_dynamic() && bodies[b as usize].is_awake_dynamic() {
                self.union(a, b);
            }
        }
        self.still_for.clear();
        self.still_for.resize(bodies.len(), f32::INFINITY);
        for (i, body) in bodies.iter().enumerate() {
            if body.is_awake_dynamic() {
                let root = self.find(i as u32) as usize;
                self.still_for[root] = self.still_for[root].min(body.still_for);
            }
        }
        let mut awake = 0;
        for (i, body) in bodies.iter_mut().enumerate() {
            if !body.is_awake_dynamic() {
                continue;
            }
            let root = self.find(i as u32);
            if self.still_for[root as usize] >= TIME_TO_SLEEP {
                body.asleep = true;
                body.sleep_island = root;
                body.linear_velocity = Vec3::ZERO;
                body.angular_velocity = Vec3::ZERO;
                self.any_asleep = true;
            } else {
                awake += 1;
            }
        }
        awake
    }

    /// Wakes every sleeping body (sleeping turned off).
    pub fn wake_all(&mut self, bodies: &mut [Body]) {
        if self.any_asleep {
            for body in bodies.iter_mut() {
                body.asleep = false;
                body.still_for = 0.0;
            }
            self.any_asleep = false;
        }
    }

    /// Step 1: marks the islands something awake reaches, then wakes their bodies.
    fn wake_reached(&mut self, bodies: &mut [Body], pairs: impl Iterator<Item = (u32, u32)>) {
        self.wake.clear();
        self.wake.resize(bodies.len(), false);
        for (a, b) in pairs {
            let (a, b) = (&bodies[a as usize], &bodies[b as usize]);
            for (sleeper, other) in [(a, b), (b, a)] {
                if sleeper.asleep && other.moves_this_step() {
                    self.wake[sleeper.sleep_island as usize] = true;
                }
            }
        }
        for body in bodies.iter().filter(|b| b.asleep) {
            let zero = Vec3::ZERO;
            if body.external_force != zero
                || body.linear_velocity != zero
                || body.angular_velocity != zero
            {
                self.wake[body.sleep_island as usize] = true;
            }
        }
        self.any_asleep = false;
        for body in bodies.iter_mut().filter(|b| b.asleep) {
            if self.wake[body.sleep_island as usize] {
                body.asleep = false;
                body.still_for = 0.0;
            } else {
                self.any_asleep = true;
            }
        }
    }

    fn find(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            // path halving
            let grandparent = self.parent[self.parent[i as usize] as usize];
            self.parent[i as usize] = grandparent;
            i = grandparent;
        }
        i
    }

    /// Joins two islands under the lower root, so roots do not depend on the pair order.
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        let (low, high) = (ra.min(rb), ra.max(rb));
        self.parent[high as usize] = low;
    }
}
