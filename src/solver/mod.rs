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
//!    within a margin grown by how far the bodies may travel in the whole frame); with
//!    [`ContactDetection::Substep`] it moves to the start of each substep (step 3) instead;
//! 2. prepare: flatten joints, rods and contact points into rows stored per kind (the joints'
//!    and rods' beside step 1 on a second thread, as they do not depend on the contacts; kept
//!    from the last frame while the constraints' stamp and the bodies' sleep states are the
//!    same: [`Constraints::stamp`]), and colour each kind's rows so rows of one colour share
//!    no movable body ([`graph`]). Joints and rods keep their stored order (solving colour by
//!    colour is exactly the paper's sequential sweep); contact points, whose order is only
//!    the broad phase's, take the greedy colouring (few, full colours). Either way both
//!    solvers sweep the same reordered rows, so the scalar and SIMD solvers compute the same
//!    thing. The SIMD solver packs the contact points into lanes here, where they stay
//!    through the frame's substeps (each substep's start, warm start, iterations and velocity
//!    pass run on the lanes: `packed_contacts.rs`) until they are unpacked at the frame's end;
//! 3. for each substep (with [`ContactDetection::Substep`], after contact detection at the
//!    substep's starting poses, with the reach of one substep, and the points coloured as in
//!    step 2; points found again keep their impulses and anchors, as from frame to frame):
//!    1. apply gravity and external forces to the linear velocities; update angular
//!       velocities with the gyroscopic term (implicit, see [`gyroscopic_update`]); apply
//!       damping, if any, then the angular speed limit, if any
//!       ([`Settings::angular_speed_limit`]);
//!    2. predict the preview poses `p* = p + h v`, `q* = exp(h w) q` (exact exponential map)
//!       into the hot [`SolverBody`] array, with each body's world inverse inertia there (the
//!       SIMD solver does 3.1-3.2 and 3.4 a lane width of bodies at a time:
//!       `integrate_lanes.rs`);
//!       take the rows' per-substep constants (the limits' starting twist; a stiff rod's
//!       compliance; with joint damping or friction, each damper's starting
//!       relative orientation, relaxation and friction bound);
//!    3. `iterations` times: solve the joint dampers (damping, friction) if any
//!       ([`crate::constraint::damper`]), then the rods, then the joints, then the contact
//!       points, each kind colour by colour (the humanoid builder appends a ragdoll's rod
//!       before its joints, so for ragdolls this is their stored order); within a colour rows are
//!       independent, so they are solved [`SolverKind::Scalar`] one by one or
//!       [`SolverKind::Simd`] W at a time from lanes packed once before the iterations (and
//!       the contacts' impulses unpacked after them: [`packed`]), and on several threads when
//!       a colour is large enough ([`PARALLEL_MIN_ROWS`]); then
//!       [`Settings::contact_extra_sweeps`] sweeps of the contact points alone (none in the
//!       paper's method);
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

pub mod declared;
pub mod graph;
mod integrate;
mod integrate_lanes;
pub mod packed;
mod packed_contacts;
pub mod profile;
mod rows;
mod settings;
/// The hot body and the SIMD lanes live below the constraint kinds, which use them; re-exported
/// here, where they belong to the reader.
pub use crate::{lanes, solver_body as body};

use crate::body::Body;
use crate::constraint::{Constraint, Constraints, DamperRow, JointDamping, JointRow, RodRow};
use crate::contact::{ContactPoint, Contacts};
use crate::lanes::LaneWidth;
use body::{SharedBodies, SolverBody};
pub use declared::{Bounds, Declaration, SettingValue};
use graph::{Colouring, Colours, Order};
use integrate::{commit_pose, integrate_velocity, predict_pose};
pub use integrate::{gyroscopic_update, GYROSCOPIC_PASSES};
use packed::{with_packs, WidthPacks};
use profile::lap;
pub use profile::Profile;
use rayon::prelude::*;
use rows::{solve_colours, sweep};
pub use rows::{Row, ScalarRows};
pub(crate) use settings::method_settings;
pub use settings::{
    ContactDetection, Settings, SolverKind, DEFAULT_MAX_ANGULAR_SPEED, DEFAULT_MAX_LINEAR_SPEED,
    DEFAULT_MAX_PENETRATION, DEFAULT_MAX_SEPARATION, MAX_CONTACT_STACKING, MAX_DT, MAX_ITERATIONS,
    MAX_SUBSTEPS, METHOD_SETTINGS,
};
use std::time::Instant;

/// A colour with at least this many rows is split across threads (when there are several);
/// below it the hand-off costs more than it saves.
pub const PARALLEL_MIN_ROWS: usize = 256;

/// Bodies integrated per parallel task.
const BODY_CHUNK: usize = 512;

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
    /// The rows in lanes for [`SolverKind::Simd`] ([`packed`]), in the lane type of the
    /// width the CPU runs ([`LaneWidth::detect`]): rods packed once a substep, joints once a
    /// frame, contact points once a detection.
    packs: WidthPacks,
    colouring: Colouring,
    joint_scratch: Vec<JointRow>,
    rod_scratch: Vec<RodRow>,
    damper_scratch: Vec<DamperRow>,
    contact_scratch: Vec<ContactPoint>,
    /// What the joints', rods' and dampers' rows, their colours and the joints' lanes were
    /// last prepared from; while it stays the same, step 2 reuses them ([`Prepared`]).
    prepared: Option<Prepared>,
    prepared_movable: Vec<bool>,
    /// Wall time of the last step's phases.
    pub profile: Profile,
}

/// The inputs of step 2's joint, rod and damper rows besides which bodies are movable: the
/// rows, colours and lanes depend on nothing else (a row's per-substep constants are taken at
/// each substep's start), so a settled pile's rows are prepared once, not every frame
/// (0.6-0.9 ms a frame on the 1000-ragdoll rain).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Prepared {
    constraints: u64,
    damped: bool,
    simd: bool,
}

impl Solver {
    /// Advances the bodies by one frame of `settings.dt` (steps 1-3 of the module docs).
    pub fn step(
        &mut self,
        settings: &Settings,
        bodies: &mut [Body],
        constraints: &Constraints,
        contacts: &mut Contacts,
    ) {
        let dt = settings.dt;
        let substeps = settings.substeps.max(1);
        let h = dt / substeps as f32;
        self.profile = Profile::default();
        let mut clock = Instant::now();
        let margin = settings.contact_margin;
        let detect_each_substep =
            settings.contacts && settings.contact_detection == ContactDetection::Substep;
        // 1. contacts at the current poses, once per frame, and 2. the joints' and rods' rows
        // beside them (they do not depend on the contacts: on several threads the rows fill
        // the detection's serial stretches; the detect phase times both)
        let simd = settings.solver == SolverKind::Simd;
        let parallel = rayon::current_num_threads() > 1;
        let detect = |contacts: &mut Contacts| {
            if settings.contacts && !detect_each_substep {
                contacts.detect(bodies, constraints, dt, margin);
            }
        };
        let prepare = |solver: &mut Solver| {
            let damped = settings.joint_damping > 0.0 || settings.joint_friction > 0.0;
            solver.prepare(bodies, constraints, damped, simd, parallel);
        };
        if parallel {
            rayon::join(|| detect(contacts), || prepare(self));
        } else {
            detect(contacts);
            prepare(self);
        }
        self.profile.detect = lap(&mut clock);
        // 2. the contact points, coloured
        if !detect_each_substep {
            self.colour_contacts(contacts, simd);
        }
        self.profile.prepare = lap(&mut clock);
        // 3. substeps
        for substep in 0..substeps {
            // 3 (detection every substep): contacts afresh at the substep's starting poses
            if detect_each_substep {
                contacts.detect(bodies, constraints, h, margin);
                self.colour_contacts(contacts, simd);
                self.profile.detect += lap(&mut clock);
            }
            self.substep(settings, h, bodies, contacts);
            clock = Instant::now();
            // the SIMD solver's points, kept in lanes, go back before the next detection
            if simd && (detect_each_substep || substep + 1 == substeps) {
                let parallel = rayon::current_num_threads() > 1;
                let points = &mut contacts.points;
                with_packs!(&mut self.packs, p => p.contacts.unpack(points, parallel));
                self.profile.contacts += lap(&mut clock);
            }
        }
    }

    /// The lane width the SIMD solver runs.
    pub fn lane_width(&self) -> LaneWidth {
        self.packs.width()
    }

    /// Runs the SIMD solver `width` lanes at a time (a width the CPU runs: see
    /// [`LaneWidth::is_available`]); results are the same at every width. Call between steps:
    /// the next step packs its rows afresh.
    ///
    /// # Panics
    /// If this CPU does not run `width`.
    pub fn set_lane_width(&mut self, width: LaneWidth) {
        assert!(width.is_available(), "this CPU does not run {width:?}");
        self.packs = WidthPacks::new(width);
        self.prepared = None;
    }

    /// Drops what step 2 kept of the last frame, so the next step prepares every joint, rod
    /// and damper row afresh (with the same result, to the bit: a test compares the two).
    pub fn clear_prepared(&mut self) {
        self.prepared = None;
    }

    /// Step 2: joint, rod and damper rows, coloured, and the joints packed for the SIMD
    /// solver; kept from the last frame when made from the same inputs ([`Prepared`]).
    fn prepare(
        &mut self,
        bodies: &[Body],
        constraints: &Constraints,
        damped: bool,
        simd: bool,
        parallel: bool,
    ) {
        self.movable.clear();
        self.movable
            .extend(bodies.iter().map(Body::is_awake_dynamic));
        let inputs = Prepared {
            constraints: constraints.stamp(),
            damped,
            simd,
        };
        if self.prepared == Some(inputs) && self.prepared_movable == self.movable {
            return;
        }
        self.prepared = Some(inputs);
        self.prepared_movable.clone_from(&self.movable);
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
        if simd {
            let (rows, colours) = (&self.joints, &self.joint_colours);
            with_packs!(&mut self.packs, p => p.joints.pack(rows, colours, parallel));
        }
    }

    /// Step 2 (or 3's start, detecting every substep): the contact points, coloured, and for
    /// the SIMD solver packed into lanes, where they stay until the frame's (or substep's) end
    /// ([`packed_contacts`]).
    fn colour_contacts(&mut self, contacts: &mut Contacts, simd: bool) {
        self.colouring.colour(
            Order::Greedy,
            &mut contacts.points,
            &mut self.contact_scratch,
            &mut self.contact_colours,
            &self.movable,
            |p| (p.body_a.0, p.body_b.0),
        );
        if simd {
            let parallel = rayon::current_num_threads() > 1;
            let (points, colours) = (&contacts.points, &self.contact_colours);
            with_packs!(&mut self.packs, p => p.contacts.pack(points, colours, parallel));
        }
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
        self.predict(settings, h, bodies, parallel);
        // impacts faster than two frames of free fall bounce (step 3.5), and are not warm-started
        let impact_speed = 2.0 * settings.gravity.length() * settings.dt;
        self.begin_rows(settings, h, bodies, contacts, impact_speed, parallel);
        self.profile.integrate += lap(&mut clock);
        // 3.3 fixed iterations, kind by kind, colour by colour; the SIMD solver packs each
        // kind's batches into lanes first (its cost counted with the kind)
        self.iterate(settings, contacts, parallel, &mut clock);
        // 3.4 velocities from the corrected previews; commit the poses
        self.commit_poses(settings.solver == SolverKind::Simd, h, bodies, parallel);
        // 3.5 the stiff rods' damping, on the velocities
        self.rods.iter().for_each(|r| r.damp_velocities(bodies, h));
        self.profile.commit += lap(&mut clock);
        // 3.6 the contacts' velocity pass; bounces slower than two frames of free fall stay
        // inelastic
        if settings.contacts && settings.solver == SolverKind::Simd {
            let points = &mut contacts.points;
            with_packs!(&mut self.packs, p => {
                p.contacts.velocity_pass(points, bodies, impact_speed, parallel)
            });
        } else if settings.contacts {
            let colours = &self.contact_colours;
            let ranges = colours.ranges().map(|(c, r)| (r, !colours.is_overflow(c)));
            contacts.velocity_pass(bodies, impact_speed, ranges);
        }
        self.profile.velocity_pass += lap(&mut clock);
    }

    /// Steps 3.1-3.2: each body's velocities, then its preview pose into the hot array (the
    /// SIMD solver takes a lane width of bodies at a time: [`integrate_lanes`]).
    fn predict(&mut self, settings: &Settings, h: f32, bodies: &mut [Body], parallel: bool) {
        self.bodies.resize(bodies.len(), SolverBody::default());
        let simd = settings.solver == SolverKind::Simd;
        let width = self.packs.width();
        let predict = |bodies: &mut [Body], hot: &mut [SolverBody]| {
            if simd {
                integrate_lanes::predict(width, bodies, hot, settings, h);
            } else {
                bodies.iter_mut().zip(hot).for_each(|(body, hot)| {
                    integrate_velocity(body, settings, h);
                    *hot = predict_pose(body, h);
                });
            }
        };
        if parallel && bodies.len() >= 2 * BODY_CHUNK {
            bodies
                .par_chunks_mut(BODY_CHUNK)
                .zip(self.bodies.par_chunks_mut(BODY_CHUNK))
                .for_each(|(b, s)| predict(b, s));
        } else {
            predict(bodies, &mut self.bodies);
        }
    }

    /// Step 3.2, the rows' per-substep constants (joints, rods, dampers, contact points), then
    /// the contacts' warm start.
    fn begin_rows(
        &mut self,
        settings: &Settings,
        h: f32,
        bodies_now: &[Body],
        contacts: &mut Contacts,
        impact_speed: f32,
        parallel: bool,
    ) {
        if settings.solver == SolverKind::Simd {
            // the joints are packed once a frame; their lanes take the starting twist
            let joints = &mut self.joints;
            with_packs!(&mut self.packs, p => p.joints.begin_substep(joints, bodies_now, parallel));
        } else if parallel && self.joints.len() >= 2 * PARALLEL_MIN_ROWS {
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
            friction: settings.joint_friction,
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
            max_ratio: settings.contact_stacking_max_ratio,
        };
        let push_speed = settings.contact_push_speed;
        let warm = settings.contact_warm_start;
        if settings.solver == SolverKind::Simd {
            let start = contacts.start_substep(h, push_speed, softness, stacking);
            let (points, hot) = (&mut contacts.points, &mut self.bodies);
            with_packs!(&mut self.packs, p => {
                p.contacts.begin_substep(points, bodies_now, &start, parallel);
                if warm > 0.0 {
                    p.contacts.warm_start(points, hot, warm, impact_speed, parallel);
                }
            });
        } else {
            contacts.begin_substep(bodies_now, h, push_speed, softness, stacking);
            if warm > 0.0 {
                contacts.warm_start(&mut self.bodies, warm, impact_speed);
            }
        }
    }

    /// Step 3.3: `iterations` sweeps, kind by kind, colour by colour.
    fn iterate(
        &mut self,
        settings: &Settings,
        contacts: &mut Contacts,
        parallel: bool,
        clock: &mut Instant,
    ) {
        let shared = SharedBodies::new(&mut self.bodies);
        let simd = settings.solver == SolverKind::Simd;
        if simd {
            let (rows, colours) = (&self.rods, &self.rod_colours);
            with_packs!(&mut self.packs, p => p.rods.pack(rows, colours, parallel));
            self.profile.rods += lap(clock);
        }
        // the last `contact_extra_sweeps` passes sweep the contacts alone
        for pass in 0..settings.iterations + settings.contact_extra_sweeps {
            if pass < settings.iterations {
                if !self.dampers.is_empty() {
                    let (dampers, colours) = (&mut self.dampers, &self.damper_colours);
                    solve_colours(self.packs.width(), dampers, colours, shared, parallel);
                    self.profile.joints += lap(clock);
                }
                let (rods, colours) = (&mut self.rods, &self.rod_colours);
                with_packs!(&mut self.packs, p => {
                    sweep(rods, colours, simd.then_some(&mut p.rods), shared, parallel)
                });
                self.profile.rods += lap(clock);
                let (joints, colours) = (&mut self.joints, &self.joint_colours);
                with_packs!(&mut self.packs, p => {
                    sweep(joints, colours, simd.then_some(&mut p.joints), shared, parallel)
                });
                self.profile.joints += lap(clock);
            }
            let (points, colours) = (&mut contacts.points, &self.contact_colours);
            with_packs!(&mut self.packs, p => {
                sweep(points, colours, simd.then_some(&mut p.contacts), shared, parallel)
            });
            self.profile.contacts += lap(clock);
        }
    }

    /// Step 3.4: velocities from the corrected previews; commit the poses (the SIMD solver a
    /// lane width of bodies at a time).
    fn commit_poses(&mut self, simd: bool, h: f32, bodies: &mut [Body], parallel: bool) {
        let width = self.packs.width();
        let commit = |bodies: &mut [Body], hot: &[SolverBody]| {
            if simd {
                integrate_lanes::commit(width, bodies, hot, h);
            } else {
                bodies
                    .iter_mut()
                    .zip(hot)
                    .for_each(|(b, s)| commit_pose(b, s, h));
            }
        };
        if parallel && bodies.len() >= 2 * BODY_CHUNK {
            bodies
                .par_chunks_mut(BODY_CHUNK)
                .zip(self.bodies.par_chunks(BODY_CHUNK))
                .for_each(|(b, s)| commit(b, s));
        } else {
            commit(bodies, &self.bodies);
        }
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
