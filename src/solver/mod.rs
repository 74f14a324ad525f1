//! The step: an impulse-based solver from preview coordinates with a fixed number of
//! iterations (paper §4, after Bender and Schmitt 2006), written in position-level form.
//!
//! Bender and Schmitt apply impulses to velocities so that the preview pose `x* = x + h v`
//! satisfies each constraint. A velocity change `dv` moves the preview by `h dv`, so applying
//! the correction to `x*` directly and deriving `v = (x* - x) / h` at the end is the same
//! method with less bookkeeping (as in position-based dynamics). Soft constraints remove a
//! fraction alpha in [0, 1] of their error per iteration; hard constraints use alpha = 1.
//!
//! Step order, one frame of `dt` split into `substeps` substeps of `h = dt / substeps`
//! (`substeps = 1` is the paper's method and the reference; smaller steps buy more accuracy per
//! constraint solve than more iterations, Macklin et al. 2019, "Small Steps in Physics
//! Simulation"):
//! 1. contact detection, once per frame, at the current poses (speculative: points are made
//!    within a margin grown by how far the bodies may travel in the whole frame);
//! 2. prepare: flatten joints, rods and contact points into rows stored per kind, and colour
//!    each kind's rows so rows of one colour share no movable body ([`graph`]). Joints and
//!    rods keep their stored order (solving colour by colour is exactly the paper's sequential
//!    sweep); contact points, whose order is only the broad phase's, take the greedy colouring
//!    (few, full colours). Either way both solvers sweep the same reordered rows, so the scalar
//!    and SIMD solvers compute the same thing;
//! 3. for each substep:
//!    1. apply gravity and external forces to the linear velocities; update angular
//!       velocities with the gyroscopic term (implicit, see [`gyroscopic_update`]); apply
//!       damping, if any;
//!    2. predict the preview poses `p* = p + h v`, `q* = exp(h w) q` (exact exponential map)
//!       into the hot [`SolverBody`] array, with each body's world inverse inertia there;
//!       take the rows' per-substep constants (the limits' starting twist; a stiff rod's
//!       compliance; with joint damping, each damper's starting
//!       relative orientation and relaxation);
//!    3. `iterations` times: solve the joint dampers if any ([`crate::constraint::damper`]),
//!       then the rods, then the joints, then the contact points, each
//!       kind colour by colour (the humanoid builder appends a ragdoll's rod before its
//!       joints, so for ragdolls this is their stored order); within a colour rows are
//!       independent, so they are solved [`SolverKind::Scalar`] one by one or
//!       [`SolverKind::Simd`] W at a time from lanes packed once before the iterations (and
//!       the contacts' impulses unpacked after them: [`packed`]), and on several threads when
//!       a colour is large enough ([`PARALLEL_MIN_ROWS`]);
//!    4. derive the velocities `v = (p* - p) / h`, `w = log(q* q^-1) / h` and commit the poses
//!       back to the [`Body`]s;
//!    5. a stiff rod's damping (`bend_damping`, `twist_damping`) on the velocities
//!       ([`RodRow::damp_velocities`]);
//!    6. the contacts' velocity pass: each contact that pushed in this substep leaves with zero
//!       relative normal velocity, or bounces (restitution);
//! 4. the world checks its health ([`crate::world::World::check_health`]): NaN or infinity in
//!    any body, a dynamic body faster than the speed bounds, a joint or rod apart by more than
//!    `max_separation`, a contact deeper than `max_penetration`; the caller then measures
//!    residuals on the final poses (paper Fig. 8), once per frame;
//! 5. with sleeping on, the world's sleep pass ([`crate::sleep`]) wakes the islands something
//!    awake reached and puts still ones to sleep. A sleeping body is immovable here: not
//!    integrated, no rows with other immovable bodies, inverse mass zero in the hot array.
//!
//! Results do not depend on the thread count: colours are built in a fixed order and the rows
//! of a colour write disjoint bodies. Once warmed up, the step does not allocate: every
//! vector here is reused from frame to frame.

pub mod graph;
pub mod packed;
pub mod profile;
/// The hot body and the SIMD lanes live below the constraint kinds, which use them; re-exported
/// here, where they belong to the reader.
pub use crate::{lanes, solver_body as body};

use crate::body::{Body, BodyKind};
use crate::constraint::{Constraint, DamperRow, JointDamping, JointRow, RodRow};
use crate::contact::{ContactPoint, Contacts};
use crate::math::{quat_from_rotation_vector, rotation_vector, skew, Mat3, Vec3};
use body::{SharedBodies, SolverBody};
use graph::{Colouring, Colours, Order};
use packed::Packed;
pub use packed::SIMD_WIDTH;
use profile::lap;
pub use profile::Profile;
use rayon::prelude::*;
use std::time::Instant;

/// A colour with at least this many rows is split across threads (when there are several);
/// below it the hand-off costs more than it saves.
pub const PARALLEL_MIN_ROWS: usize = 256;

/// Fixed-point passes of the gyroscopic update, at most.
pub const GYROSCOPIC_PASSES: u32 = 4;

/// Bodies integrated per parallel task.
const BODY_CHUNK: usize = 512;

/// How the rows of a colour are solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// One row after another: the reference.
    #[default]
    Scalar,
    /// W rows at once in SIMD lanes, branch-free (paper §7); the same maths.
    Simd,
}

impl std::fmt::Display for SolverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SolverKind::Scalar => "scalar",
            SolverKind::Simd => "simd",
        })
    }
}

/// Simulation settings (from the scene file, overridable on the command line).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Gravitational acceleration (m/s^2).
    pub gravity: Vec3,
    /// Frame time step (s).
    pub dt: f32,
    /// Solver iterations per substep (paper §8: a fixed number).
    pub iterations: u32,
    /// Substeps per frame, each of `dt / substeps` with `iterations` sweeps (Macklin et al.
    /// 2019). 1 is the paper's method and the reference.
    pub substeps: u32,
    /// How the rows of a colour are solved: scalar (the reference) or SIMD lanes.
    pub solver: SolverKind,
    /// A dynamic body faster than this (m/s) counts as exploded.
    pub max_linear_speed: f32,
    /// A dynamic body spinning faster than this (rad/s) counts as exploded.
    pub max_angular_speed: f32,
    /// A joint or rod whose hard constraints are further apart than this (m) after a frame
    /// counts as broken apart.
    pub max_separation: f32,
    /// A contact deeper than this (m) after a frame counts as a body driven through another.
    pub max_penetration: f32,
    /// Whether bodies collide. Off, the step does no collision work at all.
    pub contacts: bool,
    /// Contact points are made this far (m) before the surfaces touch.
    pub contact_margin: f32,
    /// Deep overlap is pushed out no faster than this (m/s); infinity pushes it out at once.
    pub contact_push_speed: f32,
    /// Each substep starts every contact point with this fraction of the normal impulse it
    /// ended the last substep with (warm starting; Rapier's `warmstart_coefficient`); a point
    /// found again next frame keeps it ([`crate::contact::manifold`]). 0 is the paper's method.
    pub contact_warm_start: f32,
    /// Soft contacts: natural frequency (Hz) and damping ratio of each contact point
    /// ([`crate::contact::Softness`]). 0 Hz (the default) is the paper's hard projection.
    pub contact_hertz: f32,
    /// Soft contacts' damping ratio zeta (1: critical).
    pub contact_damping_ratio: f32,
    /// Stacking (1/m): in a contact the lower body counts `e^(k dh)` times heavier, `dh` the
    /// other's height above it ([`crate::contact::Stacking`]). 0 (the default) is the paper's
    /// contact.
    pub contact_stacking: f32,
    /// Islands of bodies that stay still fall asleep and leave the step ([`crate::sleep`]).
    /// Off (the default) in the paper's scenes, whose residuals are measured every frame.
    pub sleep: bool,
    /// Velocity damping rates (1/s): each substep `v /= 1 + h c`. Zero (the default) in the
    /// paper's scenes; a game scene may use a little to let piles come to rest.
    pub linear_damping: f32,
    /// Angular velocity damping rate (1/s): each substep `w /= 1 + h c`.
    pub angular_damping: f32,
    /// Joint damping (N m s/rad): a rotational dashpot across every ball-and-socket joint and
    /// rod, the torque `-k w_rel` ([`crate::constraint::damper`]), as a ragdoll's muscles would
    /// damp it. Zero (the default) in the paper's scenes: no damper rows at all.
    pub joint_damping: f32,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 60.0,
            iterations: 20,
            substeps: 1,
            solver: SolverKind::Scalar,
            max_linear_speed: DEFAULT_MAX_LINEAR_SPEED,
            max_angular_speed: DEFAULT_MAX_ANGULAR_SPEED,
            max_separation: DEFAULT_MAX_SEPARATION,
            max_penetration: DEFAULT_MAX_PENETRATION,
            contacts: false,
            contact_margin: 0.02,
            contact_push_speed: DEFAULT_CONTACT_PUSH_SPEED,
            contact_warm_start: 0.0,
            contact_hertz: 0.0,
            contact_damping_ratio: 1.0,
            contact_stacking: 0.0,
            sleep: false,
            linear_damping: 0.0,
            angular_damping: 0.0,
            joint_damping: 0.0,
        }
    }
}

/// Default limit on the speed at which deep overlap is pushed out (m/s): none, the paper-era
/// projection. Box2D v3 uses 3 m/s; here 3 m/s left a 30-ragdoll pile with a fifth of its bodies
/// still creeping after 10 s (the overlap is pushed out slowly while the velocity pass keeps
/// taking the push's speed away), so the limit waits for the contact work to tune it.
pub const DEFAULT_CONTACT_PUSH_SPEED: f32 = f32::INFINITY;

/// Default explosion bound on linear speed (m/s): well above anything a falling ragdoll or a
/// thrown prop reaches in our scenes (a 50 m/s projectile is the fastest).
pub const DEFAULT_MAX_LINEAR_SPEED: f32 = 250.0;
/// Default explosion bound on angular speed (rad/s), about 80 turns per second.
pub const DEFAULT_MAX_ANGULAR_SPEED: f32 = 500.0;

/// Default bound on a joint's or rod's dislocation after a frame (m): half a metre is no
/// residual error any more but a ragdoll come apart (`--dt 1` left a joint 1 km apart).
pub const DEFAULT_MAX_SEPARATION: f32 = 0.5;

/// Default bound on a contact's depth after a frame (m): deeper than any body here is thick
/// (`--dt 1 --iterations 1` drove bodies 39 m into the floor).
pub const DEFAULT_MAX_PENETRATION: f32 = 0.5;

/// The solver's per-step storage, reused from frame to frame: hot bodies and rows per kind.
#[derive(Clone, Debug, Default)]
pub struct Solver {
    bodies: Vec<SolverBody>,
    movable: Vec<bool>,
    joints: Vec<JointRow>,
    joint_colours: Colours,
    rods: Vec<RodRow>,
    rod_colours: Colours,
    /// Joint damping's rows, one per joint and rod, only when the scene asks for damping.
    dampers: Vec<DamperRow>,
    damper_colours: Colours,
    contact_colours: Colours,
    /// The rows in lanes for [`SolverKind::Simd`], packed once a substep ([`packed`]).
    joint_lanes: Packed<JointRow>,
    rod_lanes: Packed<RodRow>,
    contact_lanes: Packed<ContactPoint>,
    colouring: Colouring,
    joint_scratch: Vec<JointRow>,
    rod_scratch: Vec<RodRow>,
    damper_scratch: Vec<DamperRow>,
    contact_scratch: Vec<ContactPoint>,
    /// Wall time of the last step's phases.
    pub profile: Profile,
}

impl Solver {
    /// Advances the bodies by one frame of `settings.dt` (steps 1-3 of the module docs).
    pub fn step(
        &mut self,
        settings: &Settings,
        bodies: &mut [Body],
        constraints: &[Constraint],
        contacts: &mut Contacts,
    ) {
        let dt = settings.dt;
        let substeps = settings.substeps.max(1);
        let h = dt / substeps as f32;
        self.profile = Profile::default();
        let mut clock = Instant::now();
        // 1. contacts at the current poses, once per frame
        if settings.contacts {
            contacts.detect(bodies, constraints, dt, settings.contact_margin);
        }
        self.profile.detect = lap(&mut clock);
        // 2. prepare: rows per kind, coloured
        self.prepare(bodies, constraints, contacts, settings.joint_damping > 0.0);
        self.profile.prepare = lap(&mut clock);
        // 3. substeps
        for _ in 0..substeps {
            self.substep(settings, h, bodies, contacts);
        }
    }

    /// Step 2: rows per kind, coloured.
    fn prepare(
        &mut self,
        bodies: &[Body],
        constraints: &[Constraint],
        contacts: &mut Contacts,
        damped: bool,
    ) {
        self.movable.clear();
        self.movable
            .extend(bodies.iter().map(Body::is_awake_dynamic));
        self.joints.clear();
        self.rods.clear();
        self.dampers.clear();
        for constraint in constraints {
            let (a, b) = constraint.bodies();
            if !(self.movable[a.index()] || self.movable[b.index()]) {
                continue; // nothing to move (a sleeping island, or fixed bodies only)
            }
            if damped {
                self.dampers.push(DamperRow::prepare(constraint));
            }
            match constraint {
                Constraint::BallSocket(joint) => self.joints.push(joint.prepare()),
                Constraint::Rod(rod) => self.rods.push(rod.prepare()),
            }
        }
        let movable = &self.movable;
        self.colouring.colour(
            Order::Kept,
            &mut self.joints,
            &mut self.joint_scratch,
            &mut self.joint_colours,
            movable,
            |r| (r.body_a, r.body_b),
        );
        self.colouring.colour(
            Order::Kept,
            &mut self.rods,
            &mut self.rod_scratch,
            &mut self.rod_colours,
            movable,
            |r| (r.body_a, r.body_b),
        );
        self.colouring.colour(
            Order::Kept,
            &mut self.dampers,
            &mut self.damper_scratch,
            &mut self.damper_colours,
            movable,
            |r| (r.body_a, r.body_b),
        );
        self.colouring.colour(
            Order::Greedy,
            &mut contacts.points,
            &mut self.contact_scratch,
            &mut self.contact_colours,
            movable,
            |p| (p.body_a.0, p.body_b.0),
        );
    }

    /// Step 3: one substep of `h`.
    fn substep(
        &mut self,
        settings: &Settings,
        h: f32,
        bodies: &mut [Body],
        contacts: &mut Contacts,
    ) {
        let parallel = rayon::current_num_threads() > 1;
        let mut clock = Instant::now();
        // 3.1-3.2 velocities, then the preview poses into the hot array
        self.bodies.resize(bodies.len(), SolverBody::default());
        let predict = |(body, hot): (&mut Body, &mut SolverBody)| {
            integrate_velocity(body, settings, h);
            *hot = predict_pose(body, h);
        };
        if parallel && bodies.len() >= 2 * BODY_CHUNK {
            bodies
                .par_chunks_mut(BODY_CHUNK)
                .zip(self.bodies.par_chunks_mut(BODY_CHUNK))
                .for_each(|(b, s)| b.iter_mut().zip(s).for_each(predict));
        } else {
            bodies.iter_mut().zip(&mut self.bodies).for_each(predict);
        }
        let bodies_now: &[Body] = bodies;
        if parallel && self.joints.len() >= 2 * PARALLEL_MIN_ROWS {
            self.joints
                .par_chunks_mut(PARALLEL_MIN_ROWS)
                .for_each(|rows| rows.iter_mut().for_each(|r| r.begin_substep(bodies_now)));
        } else {
            self.joints
                .iter_mut()
                .for_each(|r| r.begin_substep(bodies_now));
        }
        self.rods.iter_mut().for_each(|r| r.begin_substep(h));
        let damping = JointDamping {
            coefficient: settings.joint_damping,
            h,
            iterations: settings.iterations,
        };
        let begin = |r: &mut DamperRow| r.begin_substep(bodies_now, damping);
        if parallel && self.dampers.len() >= 2 * PARALLEL_MIN_ROWS {
            self.dampers
                .par_chunks_mut(PARALLEL_MIN_ROWS)
                .for_each(|rows| rows.iter_mut().for_each(begin));
        } else {
            self.dampers.iter_mut().for_each(begin);
        }
        let softness = crate::contact::Softness {
            hertz: settings.contact_hertz,
            damping_ratio: settings.contact_damping_ratio,
        };
        let stacking = crate::contact::Stacking {
            up: -settings.gravity.normalize_or_zero(),
            rate: settings.contact_stacking,
        };
        let push_speed = settings.contact_push_speed;
        contacts.begin_substep(bodies, h, push_speed, softness, stacking);
        // impacts faster than two frames of free fall bounce (step 3.5), and are not warm-started
        let impact_speed = 2.0 * settings.gravity.length() * settings.dt;
        if settings.contact_warm_start > 0.0 {
            contacts.warm_start(&mut self.bodies, settings.contact_warm_start, impact_speed);
        }
        self.profile.integrate += lap(&mut clock);
        // 3.3 fixed iterations, kind by kind, colour by colour; the SIMD solver packs each
        // kind's batches into lanes first (its cost counted with the kind)
        let shared = SharedBodies::new(&mut self.bodies);
        let simd = settings.solver == SolverKind::Simd;
        if simd {
            self.rod_lanes.pack(&self.rods, &self.rod_colours, parallel);
            self.profile.rods += lap(&mut clock);
            (self.joint_lanes).pack(&self.joints, &self.joint_colours, parallel);
            self.profile.joints += lap(&mut clock);
            (self.contact_lanes).pack(&contacts.points, &self.contact_colours, parallel);
            self.profile.contacts += lap(&mut clock);
        }
        for _ in 0..settings.iterations {
            if !self.dampers.is_empty() {
                solve_colours(&mut self.dampers, &self.damper_colours, shared, parallel);
                self.profile.joints += lap(&mut clock);
            }
            let rod_lanes = simd.then_some(&mut self.rod_lanes);
            sweep(
                &mut self.rods,
                &self.rod_colours,
                rod_lanes,
                shared,
                parallel,
            );
            self.profile.rods += lap(&mut clock);
            let joint_lanes = simd.then_some(&mut self.joint_lanes);
            sweep(
                &mut self.joints,
                &self.joint_colours,
                joint_lanes,
                shared,
                parallel,
            );
            self.profile.joints += lap(&mut clock);
            let contact_lanes = simd.then_some(&mut self.contact_lanes);
            let points = &mut contacts.points;
            sweep(
                points,
                &self.contact_colours,
                contact_lanes,
                shared,
                parallel,
            );
            self.profile.contacts += lap(&mut clock);
        }
        if simd {
            self.contact_lanes.unpack(&mut contacts.points);
            self.profile.contacts += lap(&mut clock);
        }
        // 3.4 velocities from the corrected previews; commit the poses
        let commit = |(body, hot): (&mut Body, &SolverBody)| commit_pose(body, hot, h);
        if parallel && bodies.len() >= 2 * BODY_CHUNK {
            bodies
                .par_chunks_mut(BODY_CHUNK)
                .zip(self.bodies.par_chunks(BODY_CHUNK))
                .for_each(|(b, s)| b.iter_mut().zip(s).for_each(commit));
        } else {
            bodies.iter_mut().zip(&self.bodies).for_each(commit);
        }
        // 3.5 the stiff rods' damping, on the velocities
        self.rods.iter().for_each(|r| r.damp_velocities(bodies, h));
        self.profile.commit += lap(&mut clock);
        // 3.6 the contacts' velocity pass; bounces slower than two frames of free fall stay
        // inelastic
        if settings.contacts {
            let colours = &self.contact_colours;
            let ranges = colours.ranges().map(|(c, r)| (r, !colours.is_overflow(c)));
            contacts.velocity_pass(bodies, impact_speed, ranges);
        }
        self.profile.velocity_pass += lap(&mut clock);
    }

    /// Colours per kind at the last step: (joints, rods, contacts), for benchmarks and reports.
    pub fn colour_counts(&self) -> (usize, usize, usize) {
        (
            self.joint_colours.count(),
            self.rod_colours.count(),
            self.contact_colours.count(),
        )
    }
}

/// One sweep over a kind's rows, colour by colour: from their packed lanes with the SIMD solver
/// ([`packed::Packed::solve`]), else one row at a time with the scalar kernel (the reference).
/// Rows of a colour are independent, so a large colour is split into chunks across threads;
/// the overflow colour is always sequential.
fn sweep<T: packed::LaneRows>(
    rows: &mut [T],
    colours: &Colours,
    lanes: Option<&mut Packed<T>>,
    bodies: SharedBodies,
    parallel: bool,
) {
    if let Some(lanes) = lanes {
        return lanes.solve(rows, bodies, parallel);
    }
    solve_colours(rows, colours, bodies, parallel);
}

/// The scalar sweep of [`sweep`] (also the dampers', which have no lane kernel).
fn solve_colours<T: Row>(rows: &mut [T], colours: &Colours, bodies: SharedBodies, parallel: bool) {
    let solve_row = |row: &mut T| {
        let (a, b) = row.bodies();
        // SAFETY: rows of a colour share no movable body, and chunks of a colour are
        // disjoint; the overflow colour runs on one thread.
        unsafe { bodies.with_pair(a, b, |a, b| row.solve(a, b)) };
    };
    for (colour, range) in colours.ranges() {
        let rows = &mut rows[range];
        if parallel && !colours.is_overflow(colour) && rows.len() >= PARALLEL_MIN_ROWS {
            let chunk = rows.len().div_ceil(rayon::current_num_threads());
            rows.par_chunks_mut(chunk)
                .for_each(|rows| rows.iter_mut().for_each(solve_row));
        } else {
            rows.iter_mut().for_each(solve_row);
        }
    }
}

/// A row kind as the solver sweeps it: its two bodies and its scalar kernel (one projection).
pub trait Row: Send {
    /// Indices of the row's two bodies, (a, b).
    fn bodies(&self) -> (u32, u32);
    /// One projection of the row on its two bodies.
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody);
}

impl Row for JointRow {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a, self.body_b)
    }
    #[inline]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        JointRow::solve(self, a, b)
    }
}

impl Row for DamperRow {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a, self.body_b)
    }
    #[inline]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        DamperRow::solve(self, a, b)
    }
}

impl Row for RodRow {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a, self.body_b)
    }
    #[inline]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        RodRow::solve(self, a, b)
    }
}

impl Row for ContactPoint {
    fn bodies(&self) -> (u32, u32) {
        (self.body_a.0, self.body_b.0)
    }
    #[inline]
    fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        ContactPoint::solve(self, a, b)
    }
}

/// Step 3.1: gravity, external force, the gyroscopic term and damping.
fn integrate_velocity(body: &mut Body, settings: &Settings, h: f32) {
    if !body.is_awake_dynamic() {
        return;
    }
    body.linear_velocity += h * (settings.gravity + body.external_force * body.inverse_mass);
    // Substeps stop the fixed point once it has converged to rounding (one or two passes at
    // h = dt/4); one step a frame keeps its four passes, bit for bit the reference. The implicit
    // Newton step alone would cost a fifth as much but lets a free spinning brick lose 1.4% of
    // its angular momentum over 10 s at 4 substeps.
    let converged = if settings.substeps > 1 { 1e-6 } else { 0.0 };
    body.angular_velocity =
        gyroscopic_update(body, h, converged) / (1.0 + h * settings.angular_damping);
    body.linear_velocity /= 1.0 + h * settings.linear_damping;
}

/// Step 3.2: the preview pose of a body as the hot solver body. Fixed bodies stay put.
fn predict_pose(body: &Body, h: f32) -> SolverBody {
    if body.asleep {
        // immovable until its island wakes
        return SolverBody {
            orientation: body.orientation,
            predicted: body.orientation,
            position: body.position,
            inverse_mass: 0.0,
            rotation_correction: Vec3::ZERO,
            inverse_inertia: Mat3::ZERO,
        };
    }
    let (position, orientation) = if body.kind == BodyKind::Fixed {
        (body.position, body.orientation)
    } else {
        (
            body.position + h * body.linear_velocity,
            (quat_from_rotation_vector(h * body.angular_velocity) * body.orientation).normalize(),
        )
    };
    SolverBody {
        orientation,
        predicted: orientation,
        position,
        inverse_mass: body.inverse_mass,
        rotation_correction: Vec3::ZERO,
        inverse_inertia: {
            let r = Mat3::from_quat(orientation);
            r * Mat3::from_diagonal(body.inverse_inertia_body) * r.transpose()
        },
    }
}

/// Step 3.4: velocities from the corrected preview, then the pose is committed.
fn commit_pose(body: &mut Body, hot: &SolverBody, h: f32) {
    if body.kind == BodyKind::Fixed || body.asleep {
        return;
    }
    if body.is_dynamic() {
        body.linear_velocity = (hot.position - body.position) / h;
        body.angular_velocity = rotation_vector(hot.orientation * body.orientation.inverse()) / h;
    }
    body.position = hot.position;
    body.orientation = hot.orientation;
    body.preview_position = hot.position;
    body.preview_orientation = hot.orientation;
    body.predicted_orientation = hot.orientation;
    body.rotation_correction = Vec3::ZERO;
    body.update_world_inertia();
}

/// Torque-free update of the angular velocity (the gyroscopic term of Euler's equations).
///
/// In body space `dL_b/dt = L_b x w_b`; over a step with constant `w_b` its exact solution turns
/// `L_b` by `exp(-dt w_b)`, while the orientation turns by `exp(dt w_b)`, so world `L = R L_b` is
/// unchanged when both use the same `w_b`. We solve that for the new velocity,
/// `w_b = I^-1 exp(-dt w_b) L_b`, by fixed-point iteration started from one implicit Newton step
/// (Catto, GDC 2015). At the fixed point a free body's angular momentum is conserved exactly
/// (see `tests/it/conservation.rs` for the tolerance measured). If the iteration does not contract
/// (a very fast spin of a very elongated body at a long time step), the Newton step is kept: it is
/// unconditionally stable and only slightly dissipative. The iteration stops early once a pass
/// changes `w` by less than `converged` times its length (0: always four passes), and keeps the
/// Newton step without passes where `(dt |w|)^2` is under `converged`.
pub fn gyroscopic_update(body: &Body, dt: f32, converged: f32) -> Vec3 {
    let q = body.orientation;
    let w = q.inverse() * body.angular_velocity;
    let inertia = Mat3::from_diagonal(body.inertia);
    let momentum = inertia * w;
    let f = dt * w.cross(momentum);
    let jacobian = inertia + dt * (skew(w) * inertia - skew(momentum));
    if jacobian.determinant().abs() < 1e-20 {
        return body.angular_velocity;
    }
    let newton = w - jacobian.inverse() * f;
    // Newton's error is of order (dt |w|)^2 relative: where that is under `converged`, the
    // first pass would change w by less than the threshold that stops the passes, so stop
    // before it (most bodies of a settled pile; a fast spin still runs its passes)
    if converged > 0.0 && dt * dt * w.length_squared() <= converged {
        return q * newton;
    }
    let inverse_inertia = body.inertia.recip();
    let mut current = newton;
    let mut last_change = f32::INFINITY;
    for _ in 0..GYROSCOPIC_PASSES {
        let next = inverse_inertia * (quat_from_rotation_vector(-dt * current) * momentum);
        let change = (next - current).length();
        if !(change < last_change) {
            return q * newton; // not contracting
        }
        current = next;
        last_change = change;
        if converged > 0.0 && change <= converged * current.length() {
            break;
        }
    }
    q * current
}
