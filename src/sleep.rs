//! Sleeping: islands of bodies that have stayed still are taken out of the step (Box2D's solver
//! sets, Rapier's islands), so a settled pile costs almost nothing.
//!
//! Once a frame, after the solver (step 5 of [`crate::solver`]'s order), when the scene turns
//! sleeping on:
//! 1. **Wake.** A sleeping island wakes when something awake reaches it: a touching contact
//!    point ([`TOUCH_DISTANCE`]) or a joint or rod between one of its bodies and an awake
//!    dynamic body or a moving kinematic body, or a force, a velocity or a teleport given to
//!    one of its bodies by the user
//!    ([`Body::set_pose`] wakes the body itself; its joints and contacts wake the rest).
//! 2. **Timers.** Every awake dynamic body counts how long three test points (its centre of mass
//!    and the ends of its shape's two longest half extents) have each stayed inside a sphere of
//!    radius [`SLEEP_REACH`] (2.5 cm). The spheres grow to take in each frame's points; one
//!    grown wider restarts the count from the current points. This is Jolt's test. It measures
//!    where a body goes, not how fast it moves on the way: a limb jittering on the spot counts
//!    as still, where a test of the instantaneous speed (Box2D's) would keep it, and its whole
//!    island, awake for ever. Unlike Jolt's, the spheres start afresh every [`TIME_TO_SLEEP`]
//!    (a window) while the count goes on, so the test asks how far a body went in the last
//!    window, not since it last moved: a body creeping at a few mm/s stays still, where spheres
//!    kept for seconds reach 2.5 cm and restart its count, and in a pile of hundreds some body
//!    always has just restarted.
//! 3. **Islands.** Union-find over the awake dynamic bodies, joined by every joint, rod and
//!    touching contact point between two of them (fixed and kinematic bodies join nothing: a
//!    floor does not tie the whole pile into one island).
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

/// The sleep speed (m/s; Box2D v3's default threshold): the sleep test's sphere is this times
/// [`TIME_TO_SLEEP`] wide, and [`restless_bodies`] names the awake bodies whose fastest surface
/// point is at or over it.
pub const SLEEP_SPEED: f32 = 0.05;

/// An island falls asleep once every body in it has been still this long (s).
pub const TIME_TO_SLEEP: f32 = 0.5;

/// A contact point joins two bodies into one island, or wakes a sleeping one, only while its
/// surfaces are at most this far apart (m). Points are made speculatively up to the contact
/// margin and further for fast bodies; a body resting 2 cm from a jittering one is not
/// touched by it.
pub const TOUCH_DISTANCE: f32 = 0.005;

/// A body is still while each of its sleep test points stays inside a sphere of this radius
/// (m) through a window: [`SLEEP_SPEED`] times [`TIME_TO_SLEEP`], Jolt's rule (2.5 cm). A point
/// jittering on the spot sleeps while its swing stays under this either side; a point going
/// steadily spans the sphere's diameter in a window, so it sleeps only under twice
/// [`SLEEP_SPEED`]. Over the drop's layouts 1-128 x both spines at the game method, piles at
/// rest after 10 s: 255 of 256 at this radius, 254 at half of it; spheres kept until a body
/// moves (Jolt's, no windows) leave 253.
pub const SLEEP_REACH: f32 = SLEEP_SPEED * TIME_TO_SLEEP;

/// An awake dynamic body whose fastest surface point is at or over [`SLEEP_SPEED`]: what keeps
/// its island awake. The speeds split the point speed into its parts, so a user can tell a
/// sliding body (centre) from one turning about its long axis (a capsule's axial spin barely
/// moves its surface, while the same turn across the axis swings its ends).
#[derive(Clone, Debug, PartialEq)]
pub struct Restless {
    /// Which body.
    pub body: BodyId,
    /// Fastest surface point (m/s), as the sleep timers read it.
    pub point_speed: f32,
    /// Speed of the centre of mass (m/s).
    pub centre_speed: f32,
    /// Angular speed (rad/s) about a capsule's own axis (zero for other shapes), and across it.
    pub axial_spin: f32,
    /// Angular speed (rad/s) across a capsule's axis (all of it for other shapes).
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

/// Step 2 for one body: grows each test point's sphere to take in the point where it is now;
/// a sphere wider than [`SLEEP_REACH`] restarts the test from here. A window's spheres start
/// afresh once it has lasted [`TIME_TO_SLEEP`].
fn update_sleep_timer(body: &mut Body, dt: f32) {
    let points = body.sleep_test_points();
    if body.still_for == 0.0 || body.sleep_window >= TIME_TO_SLEEP {
        body.sleep_spheres = points.map(|p| (p, 0.0));
        body.sleep_window = 0.0;
    } else {
        for ((centre, radius), p) in body.sleep_spheres.iter_mut().zip(points) {
            let distance = centre.distance(p);
            if distance > *radius {
                // the smallest sphere around the old one and the point
                let grown = 0.5 * (*radius + distance);
                *centre += (p - *centre) * ((grown - *radius) / distance);
                *radius = grown;
            }
        }
        if body
            .sleep_spheres
            .iter()
            .any(|&(_, radius)| radius > SLEEP_REACH)
        {
            body.sleep_spheres = points.map(|p| (p, 0.0));
            body.still_for = 0.0;
            return;
        }
    }
    body.still_for += dt;
    body.sleep_window += dt;
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
    /// The body pairs of this frame's touching contact points.
    touching: Vec<(u32, u32)>,
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
        // taken out of `self` while the passes below borrow it; put back, storage kept
        let mut touching = std::mem::take(&mut self.touching);
        touching.clear();
        for p in &contacts.points {
            let (a, b) = (&bodies[p.body_a.index()], &bodies[p.body_b.index()]);
            if p.separation_at(a, b) <= TOUCH_DISTANCE {
                touching.push((p.body_a.0, p.body_b.0));
            }
        }
        let touching_pairs = &touching;
        let pairs = || {
            let joined = constraints.iter().map(|c| {
                let (a, b) = c.bodies();
                (a.0, b.0)
            });
            joined.chain(touching_pairs.iter().copied())
        };
        if self.any_asleep {
            self.wake_reached(bodies, pairs());
        }
        for body in bodies.iter_mut().filter(|b| b.is_awake_dynamic()) {
            update_sleep_timer(body, dt);
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
        self.touching = touching;
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
