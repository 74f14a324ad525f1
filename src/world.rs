//! The world: bodies, constraints, contacts and settings; physics only (the ragdolls that
//! group its bodies live in [`crate::lab::Lab`]).

use crate::body::{Body, BodyId};
use crate::constraint::{Constraint, Constraints};
use crate::contact::{ContactPoint, Contacts};
use crate::sleep::Islands;
use crate::solver::Solver;

pub use crate::solver::{
    ContactDetection, Settings, SolverKind, DEFAULT_MAX_ANGULAR_SPEED, DEFAULT_MAX_LINEAR_SPEED,
};

/// The physics world: bodies, constraints, contacts, settings and the solver's storage.
#[derive(Clone, Debug, Default)]
pub struct World {
    /// Time step, iterations and the other simulation settings.
    pub settings: Settings,
    /// The bodies, indexed by [`BodyId`].
    pub bodies: Vec<Body>,
    /// The joints and rods, by the index [`World::add_constraint`] returns.
    pub constraints: Constraints,
    /// The contact points and the storage to find them.
    pub contacts: Contacts,
    /// The solver's reused per-step storage (hot bodies, rows per kind, colours).
    pub solver: Solver,
    /// The sleep pass's reused storage.
    pub islands: Islands,
    /// Dynamic bodies awake after the last step (all of them unless sleeping is on).
    pub awake_bodies: usize,
    /// Frames stepped so far.
    pub frame: u64,
    /// Simulated time (s).
    pub time: f64,
}

/// A simulation that produced NaN or exploded.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationError {
    /// The frame whose step failed.
    pub frame: u64,
    /// Name of the offending body.
    pub body: String,
    /// The constraint on that body with the largest error, if any.
    pub constraint: Option<String>,
    /// What happened to the body, read after its name (e.g. "came apart: ...").
    pub reason: String,
}

impl std::fmt::Display for SimulationError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "frame {}: body \"{}\" {}",
            self.frame, self.body, self.reason
        )?;
        match &self.constraint {
            Some(c) => write!(f, "; largest error among its constraints: \"{c}\""),
            None => write!(f, "; it has no constraints"),
        }
    }
}

impl std::error::Error for SimulationError {}

impl World {
    /// An empty world with `settings`.
    pub fn new(settings: Settings) -> Self {
        World {
            settings,
            ..Default::default()
        }
    }

    /// Adds `body` and returns its id.
    pub fn add_body(&mut self, body: Body) -> BodyId {
        self.bodies.push(body);
        BodyId(self.bodies.len() as u32 - 1)
    }

    /// Adds `constraint` and returns its index in `constraints`.
    pub fn add_constraint(&mut self, constraint: impl Into<Constraint>) -> usize {
        self.constraints.push(constraint.into());
        self.constraints.len() - 1
    }

    /// The body `id`.
    pub fn body(&self, id: BodyId) -> &Body {
        &self.bodies[id.index()]
    }

    /// The body `id`, mutable.
    pub fn body_mut(&mut self, id: BodyId) -> &mut Body {
        &mut self.bodies[id.index()]
    }

    /// Runs the SIMD solver's and detection's lanes `width` at a time (a width this CPU runs:
    /// [`crate::lanes::LaneWidth::is_available`]); every width gives the same results, to the
    /// bit. The default is the widest the CPU runs ([`crate::lanes::LaneWidth::detect`]).
    pub fn set_lane_width(&mut self, width: crate::lanes::LaneWidth) {
        self.solver.set_lane_width(width);
        self.contacts.set_lane_width(width);
    }

    /// A hash (FNV-1a, 64 bits) of every body's pose, velocities and sleep state, bit for bit:
    /// two runs that agree exactly give the same hash.
    pub fn state_hash(&self) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        let mut eat = |x: u32| {
            for byte in x.to_le_bytes() {
                hash = (hash ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
            }
        };
        for b in &self.bodies {
            let q = b.orientation;
            let values = [
                b.position.to_array(),
                b.linear_velocity.to_array(),
                b.angular_velocity.to_array(),
            ];
            values
                .iter()
                .flatten()
                .chain(&[q.x, q.y, q.z, q.w])
                .for_each(|v| eat(v.to_bits()));
            eat(b.is_asleep() as u32);
        }
        hash
    }

    /// Every rod's state at the current poses, in constraint order.
    pub fn rod_states(&self) -> impl Iterator<Item = crate::constraint::RodState> + '_ {
        self.constraints.iter().filter_map(|c| match c {
            Constraint::Rod(rod) => Some(rod.state(self.body(rod.body_a), self.body(rod.body_b))),
            _ => None,
        })
    }

    /// The first body named `name`, if any.
    pub fn find_body(&self, name: &str) -> Option<BodyId> {
        self.bodies
            .iter()
            .position(|b| b.name == name)
            .map(|i| BodyId(i as u32))
    }

    /// Advances one frame (see [`crate::solver`] for the step order).
    ///
    /// Called from outside rayon's pool with several threads, the step moves onto a pool
    /// worker first: each colour's parallel solve then forks from a worker (rayon's `join`)
    /// instead of injecting a job from outside and sleeping until it ends, a few hundred
    /// hand-offs a frame in the rain (10% of its stepping time, measured).
    pub fn step(&mut self) -> Result<(), SimulationError> {
        if rayon::current_thread_index().is_none() && rayon::current_num_threads() > 1 {
            return rayon::scope(|_| self.step_here());
        }
        self.step_here()
    }

    fn step_here(&mut self) -> Result<(), SimulationError> {
        let step_started = std::time::Instant::now();
        let stepped = self.step_phases();
        self.solver.profile.step = step_started.elapsed().as_secs_f64();
        stepped
    }

    /// Steps 1-5 of the solver's list, each phase timed into `solver.profile`.
    fn step_phases(&mut self) -> Result<(), SimulationError> {
        let overflows = self.contacts.pair_overflows();
        self.solver.step(
            &self.settings,
            &mut self.bodies,
            &self.constraints,
            &mut self.contacts,
        );
        self.frame += 1;
        self.time += self.settings.dt as f64;
        if self.contacts.pair_overflows() != overflows {
            return Err(self.swept_too_far());
        }
        let started = std::time::Instant::now();
        let health = self.check_health();
        self.solver.profile.health = started.elapsed().as_secs_f64();
        health?;
        // 5. sleeping: islands that stayed still leave the step, reached ones come back
        let started = std::time::Instant::now();
        self.awake_bodies = if self.settings.sleep {
            let (dt, bodies) = (self.settings.dt, &mut self.bodies);
            self.islands
                .update(dt, bodies, &self.constraints, &self.contacts)
        } else {
            self.islands.wake_all(&mut self.bodies);
            self.bodies.iter().filter(|b| b.is_dynamic()).count()
        };
        self.solver.profile.sleep = started.elapsed().as_secs_f64();
        Ok(())
    }

    /// The contact points of the current poses that overlap, found afresh with every body
    /// awake (sleeping bodies make no pairs): how many of how many points, and their mean
    /// overlap (m; 0 when none overlaps): penetration at rest.
    pub fn overlap_at_rest(&self) -> (usize, usize, f32) {
        let mut bodies = self.bodies.clone();
        self.islands.clone().wake_all(&mut bodies);
        let mut contacts = Contacts::default();
        let (dt, margin) = (self.settings.dt, self.settings.contact_margin);
        contacts.detect(&bodies, &self.constraints, dt, margin);
        let overlaps: Vec<f32> = (contacts.points.iter())
            .map(|p| -p.separation_at(&bodies[p.body_a.index()], &bodies[p.body_b.index()]))
            .filter(|&d| d > 0.0)
            .collect();
        let mean = overlaps.iter().sum::<f32>() / overlaps.len().max(1) as f32;
        (overlaps.len(), contacts.points.len(), mean)
    }

    /// Kinetic energy of all bodies (J).
    pub fn kinetic_energy(&self) -> f32 {
        self.bodies.iter().map(Body::kinetic_energy).sum()
    }

    /// Gravitational potential energy of all bodies (J), zero at the origin.
    pub fn potential_energy(&self) -> f32 {
        self.bodies
            .iter()
            .map(|b| b.potential_energy(self.settings.gravity))
            .sum()
    }

    /// Step 4 of the solver: NaN or infinity in any body (fixed and kinematic too), a dynamic
    /// body faster than the speed bounds, a joint or rod apart by more than `max_separation`,
    /// or a contact deeper than `max_penetration` stops the run.
    pub fn check_health(&self) -> Result<(), SimulationError> {
        let settings = &self.settings;
        let finite = |body: &Body| {
            body.position.is_finite()
                && body.orientation.is_finite()
                && body.linear_velocity.is_finite()
                && body.angular_velocity.is_finite()
        };
        let too_fast = |body: &Body| {
            body.is_dynamic()
                && (body.linear_velocity.length() > settings.max_linear_speed
                    || body.angular_velocity.length() > settings.max_angular_speed)
        };
        let apart = |c: &Constraint| c.dislocation(&self.bodies);
        let came_apart = |c: &Constraint| apart(c) > settings.max_separation;
        let depth = |p: &ContactPoint| -p.separation_at(self.body(p.body_a), self.body(p.body_b));
        let too_deep = |p: &ContactPoint| depth(p) > settings.max_penetration;
        // the first bad item of each list, reported in this order; on several threads the
        // contacts are scanned beside the rest. Each scan is a few ns an item and bound by
        // memory: split finer (rayon's `position_first`), it took twice as long (0.89 against
        // 0.34 ms a frame in the rain, 2 threads).
        let scan_bodies = || self.bodies.iter().position(|b| !finite(b) || too_fast(b));
        let scan_constraints = || self.constraints.iter().position(came_apart);
        let scan_contacts = || match settings.contacts {
            true => self.contacts.points.iter().position(too_deep),
            false => None,
        };
        let ((bad_body, bad_constraint), bad_contact) =
            if rayon::current_num_threads() > 1 && self.contacts.points.len() >= PARALLEL_HEALTH {
                rayon::join(|| (scan_bodies(), scan_constraints()), scan_contacts)
            } else {
                ((scan_bodies(), scan_constraints()), scan_contacts())
            };
        if let Some(index) = bad_body {
            let body = &self.bodies[index];
            let reason = if !finite(body) {
                "has a non-finite pose or velocity (NaN or infinity)".to_string()
            } else if body.linear_velocity.length() > settings.max_linear_speed {
                format!(
                    "exploded: speed {:.1} m/s exceeds the bound {} m/s",
                    body.linear_velocity.length(),
                    settings.max_linear_speed
                )
            } else {
                format!(
                    "exploded: angular speed {:.1} rad/s exceeds the bound {} rad/s",
                    body.angular_velocity.length(),
                    settings.max_angular_speed
                )
            };
            return Err(SimulationError {
                frame: self.frame,
                body: body.name.clone(),
                constraint: self.worst_constraint_on(BodyId(index as u32)),
                reason,
            });
        }
        if let Some(index) = bad_constraint {
            let constraint = &self.constraints[index];
            let body = self.body(constraint.bodies().1);
            return Err(SimulationError {
                frame: self.frame,
                body: body.name.clone(),
                constraint: Some(constraint.name().to_string()),
                reason: format!(
                    "came apart: \"{}\" is {:.3} m apart, beyond the bound max_separation = {} m",
                    constraint.name(),
                    apart(constraint),
                    settings.max_separation
                ),
            });
        }
        if let Some(index) = bad_contact {
            let p = &self.contacts.points[index];
            let (a, b) = (self.body(p.body_a), self.body(p.body_b));
            return Err(SimulationError {
                frame: self.frame,
                body: b.name.clone(),
                constraint: self.worst_constraint_on(p.body_b),
                reason: format!(
                    "was driven {:.3} m into \"{}\", beyond the bound max_penetration = {} m",
                    depth(p),
                    a.name,
                    settings.max_penetration
                ),
            });
        }
        Ok(())
    }

    /// The error for a step whose contact detection stopped at its pair budget: bodies swept
    /// so far through each other (a time step far too long for their speed) that their pairs
    /// grew as the square of their number. Names the fastest body.
    fn swept_too_far(&self) -> SimulationError {
        let speed = |b: &Body| b.linear_velocity.length();
        let fastest = (self.bodies.iter().enumerate())
            .filter(|(_, b)| b.is_dynamic())
            .max_by(|(_, a), (_, b)| speed(a).total_cmp(&speed(b)))
            .map_or(0, |(i, _)| i);
        let body = &self.bodies[fastest];
        let dt = self.settings.dt;
        SimulationError {
            frame: self.frame,
            body: body.name.clone(),
            constraint: self.worst_constraint_on(BodyId(fastest as u32)),
            reason: format!(
                "exploded: it moves {:.1} m/s, {:.2} m in a step of {dt} s, the fastest of \
                 bodies sweeping so far through each other that contact detection found more \
                 than its bound of {} candidate pairs (is the time step too long?)",
                speed(body),
                speed(body) * dt,
                crate::contact::broadphase::pair_budget(self.bodies.len())
            ),
        }
    }

    /// Name of the constraint on `body` with the largest error (NaN counts as largest).
    fn worst_constraint_on(&self, body: BodyId) -> Option<String> {
        let size = |c: &Constraint| {
            let v = c.violation(&self.bodies);
            let s = v.dislocation + v.angular;
            if s.is_nan() {
                f32::INFINITY
            } else {
                s
            }
        };
        self.constraints
            .iter()
            .filter(|c| {
                let (a, b) = c.bodies();
                a == body || b == body
            })
            .max_by(|x, y| size(x).total_cmp(&size(y)))
            .map(|c| c.name().to_string())
    }
}

impl From<crate::constraint::BallSocket> for Constraint {
    fn from(joint: crate::constraint::BallSocket) -> Self {
        Constraint::BallSocket(joint)
    }
}

/// Contact points from which the health check scans them on a second thread.
const PARALLEL_HEALTH: usize = 4096;
