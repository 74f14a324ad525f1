//! Contacts, solved in the same iteration loop as the joints (position level).
//!
//! Detection is speculative: pairs are found at the current poses (step 2 of the solver) within
//! a margin grown by how far the bodies' surfaces may travel this step (spin included), so fast
//! bodies meet thin ones before they could pass. Each contact point keeps its world normal `n` (from a to b) and its
//! two surface points in body space for the step; each iteration measures the separation
//! `C = (p_b - p_a) . n` at the preview poses and, when negative, pushes the points apart
//! along `n` (non-penetration, `C >= 0`). The pushes act at lever arms fixed when the point is
//! found (Box2D v3's fixed anchors), not at the turned body-space points: see
//! `ContactPoint::arm_a`.
//!
//! Coulomb friction at position level: the tangential slip of the two points is removed while
//! the friction impulse stays within `mu_s` times the normal impulse accumulated this step
//! (sticking); beyond that at most `mu_d` times it is applied (sliding), so a block on a slope
//! accelerates at `g (sin theta - mu_d cos theta)`. Slip is measured from a pair of friction
//! anchors, body-space points that coincided when the contact began to stick. A point found
//! again next step (same body pair, same shape features: [`manifold`]) that stuck to the end
//! of the step carries its anchors' leftover slip into its new anchors, so the small slips
//! left by a finite number of iterations are pulled back instead of adding up to creep (the
//! role of Box2D's anchors and warm starting); a sliding contact starts fresh anchors each
//! step. A pair keeps at most four points ([`manifold::reduce`]). Friction coefficients
//! combine as the geometric mean. Restitution is a velocity pass after the positions (see
//! [`Contacts::velocity_pass`]); a pair uses the larger coefficient.
//!
//! Beside the paper's hard projection, two options: warm starting ([`Contacts::warm_start`],
//! a fraction of each resting point's last impulse applied first) and soft contacts
//! ([`Softness`], each point a damped spring in XPBD's compliance form).
//!
//! Filtering: bodies joined by a joint (unless `collide_connected`) or a rod never collide, and
//! a pair collides only if each body's group bits meet the other's mask bits.

pub mod box_box;
pub mod box_capsule;
pub mod broadphase;
pub mod collider;
pub mod detect;
pub mod feature;
pub mod handover;
pub mod lanes;
mod lanes_substep;
pub mod manifold;
pub mod narrowphase;
pub mod round_lanes;
mod softness;
mod substep;

pub use softness::{Softness, Stacking};
pub use substep::SubstepStart;

use crate::body::{Body, BodyId};
use crate::constraint::Constraints;
use crate::math::Vec3;
use crate::solver_body::{pair_mut, SharedSlice, SolverBody};
use detect::Detection;
use feature::FeatureId;

/// One contact point between two bodies, kept for a step and solved in the iterations.
///
/// `repr(C)` with the flags last, so that a float follows each `Vec3` (why:
/// [`handover::Handed`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ContactPoint {
    /// First body of the pair; the normal points away from it.
    pub body_a: BodyId,
    /// Second body of the pair.
    pub body_b: BodyId,
    /// The touching shape features, which recognise the point next step.
    pub id: FeatureId,
    /// World normal from a to b, fixed for the step.
    pub normal: Vec3,
    /// Surface points in body space.
    pub local_a: Vec3,
    /// Body b's surface point in body b's space.
    pub local_b: Vec3,
    /// The pair's static friction coefficient mu_s (geometric mean of the bodies').
    pub static_friction: f32,
    /// The pair's dynamic friction coefficient mu_d (geometric mean of the bodies').
    pub dynamic_friction: f32,
    /// The pair's coefficient of restitution (the larger of the bodies').
    pub restitution: f32,
    /// Lever arms (world offsets of the points from the body centres when found), fixed for
    /// the step: impulses act there, as Box2D v3's fixed anchors. The separation and the slip
    /// are measured at the body-space points as the bodies turn, but an impulse at a turned
    /// point would tilt the lever arm with the body: a capsule spinning about its axis carries
    /// its contact point off the line of the normal, and the push out of the floor then spins it
    /// further (axial spin grew to 170 rad/s in the drop without joint limits, and to 5-40
    /// rad/s with them: the twitching limbs of a settled pile).
    arm_a: Vec3,
    arm_b: Vec3,
    /// Friction anchors in body space: where the points were when the contact began to stick.
    anchor_a: Vec3,
    anchor_b: Vec3,
    /// Normal velocity of the points when the contact was found (m/s, negative approaching).
    approach_speed: f32,
    /// Penetration (m) this substep may leave: what the point had at the substep's start less
    /// what the push-out speed limit removes in one substep (zero for a point not yet touching).
    allowed_penetration: f32,
    /// Soft contact ([`Softness`]) this substep: compliance over inverse mass, `1 / (omega h)^2`,
    /// and the damping term `2 zeta / (omega h)`; both zero for the paper's hard contact.
    compliance: f32,
    damping: f32,
    /// Stacking ([`Stacking`]) this substep: how much of its true inverse mass each body shows
    /// this point (1, the paper's contact, or less for the lower body of a stacked pair).
    mass_scale_a: f32,
    mass_scale_b: f32,
    /// The separation the solve measures (with the allowed penetration) at the substep's start,
    /// which soft contacts damp against.
    start_separation: f32,
    /// Positional impulses accumulated this substep (kg m).
    normal_impulse: f32,
    /// The normal impulse the point ended its last substep with (kg m), which warm starting
    /// applies first.
    warm_impulse: f32,
    friction_impulse: f32,
    /// Whether the contact stuck (friction within the static cone) through the step.
    sticking: bool,
    /// Whether the point has pushed this frame (or was found again with a push to carry).
    touched: bool,
}

impl ContactPoint {
    /// A point before its first substep: no impulse, sticking, nothing touched, the paper's hard
    /// contact. Detection fills in the pair, the geometry and the materials over it.
    pub const UNSOLVED: ContactPoint = ContactPoint {
        body_a: BodyId(0),
        body_b: BodyId(0),
        id: 0,
        normal: Vec3::Y,
        local_a: Vec3::ZERO,
        local_b: Vec3::ZERO,
        static_friction: 0.0,
        dynamic_friction: 0.0,
        restitution: 0.0,
        arm_a: Vec3::ZERO,
        arm_b: Vec3::ZERO,
        anchor_a: Vec3::ZERO,
        anchor_b: Vec3::ZERO,
        sticking: true,
        touched: false,
        approach_speed: 0.0,
        allowed_penetration: 0.0,
        compliance: 0.0,
        damping: 0.0,
        mass_scale_a: 1.0,
        mass_scale_b: 1.0,
        start_separation: 0.0,
        normal_impulse: 0.0,
        warm_impulse: 0.0,
        friction_impulse: 0.0,
    };

    /// Normal velocity of the points when the contact was found (m/s, negative approaching).
    pub fn approach_speed(&self) -> f32 {
        self.approach_speed
    }

    /// Separation (m) of the two points along the normal at the current poses.
    pub fn separation_at(&self, a: &Body, b: &Body) -> f32 {
        (b.world_point(self.local_b) - a.world_point(self.local_a)).dot(self.normal)
    }

    /// One projection on the preview poses: the normal push (its accumulated impulse kept at or
    /// above zero), then friction on the anchors' slip within the Coulomb cone.
    #[inline(always)]
    pub fn solve(&mut self, a: &mut SolverBody, b: &mut SolverBody) {
        let n = self.normal;
        let point_a = a.position + a.orientation * self.local_a;
        let point_b = b.position + b.orientation * self.local_b;
        let separation = (point_b - point_a).dot(n) + self.allowed_penetration;
        let (ra, rb) = (self.arm_a, self.arm_b);
        let (sa, sb) = (self.mass_scale_a, self.mass_scale_b);
        // Projected Gauss-Seidel on the step's accumulated impulse: push while penetrating, and
        // give back what earlier iterations pushed too far, but never pull (total >= 0).
        let w = sa * a.positional_inverse_mass(ra, n) + sb * b.positional_inverse_mass(rb, n);
        if w > 0.0 && (separation < 0.0 || self.normal_impulse > 0.0) {
            // XPBD (Macklin et al. 2016) with compliance alpha~ = compliance w and damping
            // gamma; both zero, this is the hard projection total = P - C / w
            let soft = self.compliance * w;
            let error = separation
                + soft * self.normal_impulse
                + self.damping * (separation - self.start_separation);
            let total = (self.normal_impulse - error / ((1.0 + self.damping) * w + soft)).max(0.0);
            let lambda = total - self.normal_impulse;
            self.normal_impulse = total;
            a.apply_positional_impulse(-(lambda * sa) * n, ra);
            b.apply_positional_impulse((lambda * sb) * n, rb);
        }
        if self.normal_impulse <= 0.0 {
            return;
        }
        // friction: tangential slip of the anchors
        let slip = (b.position + b.orientation * self.anchor_b)
            - (a.position + a.orientation * self.anchor_a);
        let tangential = slip - slip.dot(n) * n;
        let length = tangential.length();
        if length < 1e-9 {
            return;
        }
        let t = tangential / length;
        let w = sa * a.positional_inverse_mass(ra, t) + sb * b.positional_inverse_mass(rb, t);
        if w <= 0.0 {
            return;
        }
        let needed = length / w;
        let applied =
            if self.friction_impulse + needed <= self.static_friction * self.normal_impulse {
                needed
            } else {
                self.sticking = false;
                // max/min, not clamp: no panic on a NaN bound (a NaN is caught after the step)
                (self.dynamic_friction * self.normal_impulse - self.friction_impulse)
                    .max(0.0)
                    .min(needed)
            };
        if applied > 0.0 {
            a.apply_positional_impulse((applied * sa) * t, ra);
            b.apply_positional_impulse(-(applied * sb) * t, rb);
            self.friction_impulse += applied;
        }
    }
}

/// The contacts of a world and the storage to find them, reused from step to step.
#[derive(Clone, Debug, Default)]
pub struct Contacts {
    /// The contact points of the current step.
    pub points: Vec<ContactPoint>,
    detection: Detection,
    /// Substeps begun since the last detection.
    substeps_begun: u32,
}

impl Contacts {
    /// Step 2 of the solver: finds the contact points at the current poses ([`detect`]).
    pub fn detect(&mut self, bodies: &[Body], constraints: &Constraints, dt: f32, margin: f32) {
        self.substeps_begun = 0;
        self.detection
            .detect(&mut self.points, bodies, constraints, dt, margin);
    }

    /// Runs detection's lanes `width` at a time (a width this CPU runs); the points found are
    /// the same at every width.
    pub fn set_lane_width(&mut self, width: crate::lanes::LaneWidth) {
        self.detection.set_lane_width(width);
    }

    /// How many candidate pairs the last detection skipped as proven out of reach (their
    /// shapes' distance bound, carried from step to step: [`broadphase::gaps`]).
    pub fn pairs_skipped(&self) -> usize {
        self.detection.pairs_skipped()
    }

    /// Detections so far that found too many candidate pairs to go on, and so no points: the
    /// bodies swept too far through each other in one step (the run must stop).
    pub fn pair_overflows(&self) -> u64 {
        self.detection.pair_overflows()
    }

    /// Where the last detection's wall time went, piece by piece.
    pub fn detection_profile(&self) -> &detect::DetectionProfile {
        self.detection.profile()
    }

    /// Starts a substep: the accumulated impulses count one substep's pushes (the projection's
    /// `total >= 0` clamp and the friction cone are per substep, as the preview restarts from
    /// the current pose). A point's friction anchors last while it sticks; from the second
    /// substep of a frame on, a point that slid in the last substep, or has not pushed yet this
    /// frame (not yet touching), is anchored afresh where it is now. Static
    /// friction pulls the anchors back together, so anchors kept through the substeps before a
    /// landing had it pull back, within one substep, how far the body had moved along the
    /// surface since the frame began: a box thrown down onto a rough floor was thrown back at
    /// 0.6 m/s (`a_box_thrown_onto_a_rough_floor_is_not_thrown_back`), and limbs landing in the
    /// 1000-ragdoll rain were spun about their own axis (the axis of least inertia) up to
    /// 700 rad/s, past the explosion bound. The first substep keeps what detection set (fresh
    /// anchors, or a held point's carried ones), so one substep a frame is the paper's method.
    ///
    /// Deep overlap is pushed out at no more than `push_speed` (m/s, Box2D's
    /// `maxContactPushSpeed`): a point that starts the substep penetrating by `d` must end it
    /// penetrating by at most `d - push_speed h`. Pushing a deep overlap out in one substep
    /// turns into that depth over `h` of velocity; in a pile those kicks spin limbs up until a
    /// joint limit throws them (arms at 600 rad/s at 4 substeps, before the limit). A point not
    /// yet touching must not penetrate at all, so fast bodies still stop at the surface.
    ///
    /// Soft contacts take their per-substep constants here (see [`Softness`]).
    ///
    /// Stacking ([`Stacking`]) sets each point's inverse-mass scales here.
    pub fn begin_substep(
        &mut self,
        bodies: &[Body],
        h: f32,
        push_speed: f32,
        soft: Softness,
        stacking: Stacking,
    ) {
        let start = self.start_substep(h, push_speed, soft, stacking);
        let begin = |point: &mut ContactPoint| point.begin_substep(bodies, &start);
        if self.points.len() >= PARALLEL_PAIRS && rayon::current_num_threads() > 1 {
            use rayon::prelude::*;
            self.points.par_iter_mut().for_each(begin);
        } else {
            self.points.iter_mut().for_each(begin);
        }
    }

    /// The constants of a new substep for [`ContactPoint::begin_substep`] (whether it is the
    /// frame's first counts from the last detection); the SIMD solver begins its packed points
    /// from them ([`lanes`]).
    pub fn start_substep(
        &mut self,
        h: f32,
        push_speed: f32,
        soft: Softness,
        stacking: Stacking,
    ) -> SubstepStart {
        let (compliance, damping) = soft.substep_constants(h);
        let first = self.substeps_begun == 0;
        self.substeps_begun += 1;
        SubstepStart {
            h,
            push_speed,
            compliance,
            damping,
            stacking,
            first,
        }
    }

    /// Warm starting: applies `fraction` of each point's last normal impulse to the preview
    /// poses and makes it the substep's accumulated impulse, so the iterations build only the
    /// rest of the push (and may give it back: the total stays `>= 0`). Only resting points,
    /// which approached slower than `impact_speed` (m/s) when found: an impact's impulse stops
    /// a fall once, and repeating it next substep would throw the body back.
    pub fn warm_start(&mut self, bodies: &mut [SolverBody], fraction: f32, impact_speed: f32) {
        for point in &mut self.points {
            let (a, b) = pair_mut(bodies, point.body_a.index(), point.body_b.index());
            point.warm_start(a, b, fraction, impact_speed);
        }
    }

    /// One iteration over all contact points.
    pub fn solve(&mut self, bodies: &mut [SolverBody]) {
        for point in &mut self.points {
            let (a, b) = pair_mut(bodies, point.body_a.index(), point.body_b.index());
            point.solve(a, b);
        }
    }

    /// Step 4b of the solver: the contacts' velocity pass (Mueller et al. 2020, XPBD rigid
    /// bodies). For every point that pushed this step, set the relative normal velocity of its
    /// two points to `-e` times the approach speed it had when found, if that approach was
    /// faster than `threshold` (m/s, a bounce), and to zero otherwise. The zero matters as much
    /// as the bounce: a position correction turns into velocity when velocities are derived
    /// from positions, so a body pushed out of a penetration would leave with that speed and
    /// come back next step; in a pile those kicks settle into a flip every frame (limbs
    /// twitching at 0.1 m/s and 3 rad/s after 10 s, before this pass removed them).
    ///
    /// `colours` are the points' colour ranges in order, each with whether its points share no
    /// movable body: those run on several threads when large, with the same result as one
    /// after another (a movable body is written by one point of a colour only).
    pub fn velocity_pass(
        &self,
        bodies: &mut [Body],
        threshold: f32,
        colours: impl Iterator<Item = (std::ops::Range<usize>, bool)>,
    ) {
        let shared = SharedSlice::new(bodies);
        // SAFETY: within an independent colour no two points share an awake dynamic body, the
        // only bodies written; the others run on this thread one at a time.
        let pass = |p: &ContactPoint| unsafe { p.velocity_pass(shared, threshold) };
        let parallel = rayon::current_num_threads() > 1;
        for (range, independent) in colours {
            let points = &self.points[range];
            if independent && parallel && points.len() >= PARALLEL_VELOCITY_POINTS {
                use rayon::prelude::*;
                let chunk = points.len().div_ceil(rayon::current_num_threads());
                points
                    .par_chunks(chunk)
                    .for_each(|chunk| chunk.iter().for_each(pass));
            } else {
                points.iter().for_each(pass);
            }
        }
    }

    /// Deepest overlap (m) of the shapes at the current poses, found by a detection of its own
    /// into `self`, which must be a scratch store and not the world's contacts. The world's
    /// points are found once a frame and measured at their body-space points along their
    /// fixed normals; when bodies slide or roll over each other within a frame (4 substeps
    /// in a pile), the features that overlap at the end are not those points, and the points
    /// report a fraction of it (the drop at 4 substeps of 5: 1.7 cm at the points, 5.6 cm
    /// found afresh). Pairs of sleeping bodies are not looked at. Neither margin nor speculative
    /// reach: only shapes that overlap now make points.
    pub fn deepest_overlap(&mut self, bodies: &[Body], constraints: &Constraints) -> f32 {
        self.detect(bodies, constraints, 0.0, 0.0);
        self.points
            .iter()
            .map(|p| -p.separation_at(&bodies[p.body_a.index()], &bodies[p.body_b.index()]))
            .fold(0.0, f32::max)
    }

    /// Deepest penetration (m) among the contact points at the current poses.
    pub fn max_penetration(&self, bodies: &[Body]) -> f32 {
        self.points
            .iter()
            .map(|p| -p.separation_at(&bodies[p.body_a.index()], &bodies[p.body_b.index()]))
            .fold(0.0, f32::max)
    }
}

/// A colour with at least this many points runs its velocity pass on several threads.
const PARALLEL_VELOCITY_POINTS: usize = 1024;

/// Pairs with at least this many candidates run the narrow phase on several threads.
pub(crate) const PARALLEL_PAIRS: usize = 2048;

#[cfg(test)]
mod tests {
    use super::*;

    /// A float follows each `Vec3` of a point; the flags come last ([`ContactPoint`]).
    #[test]
    fn a_float_follows_each_vector() {
        crate::math::assert_float_follows!(ContactPoint:
            normal => local_a,
            local_a => local_b,
            local_b => static_friction,
            arm_a => arm_b,
            arm_b => anchor_a,
            anchor_a => anchor_b,
            anchor_b => approach_speed,
        );
    }
}
