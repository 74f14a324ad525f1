//! Contact points W at a time: [`ContactPoint::solve`] on [`Lane`]s, branch-free (paper §7's
//! batching applied to contacts, as Box2D v3's `contact_solver.c` does with `b2FloatW`).
//!
//! The same two parts as the scalar solve, with its branches as masks:
//! 1. non-penetration: the accumulated impulse `total = max(P_n - C / w, 0)`, active where the
//!    point penetrates or has pushed this substep (`C < 0 or P_n > 0`) and `w > 0`;
//! 2. friction on the anchors' tangential slip, only where `P_n > 0`: the whole slip while the
//!    accumulated friction stays within `mu_s P_n` (sticking), else at most `mu_d P_n` in all
//!    (sliding, which clears the point's `sticking` flag).
//!
//! The substep's start, the warm start and the velocity pass on the same lanes:
//! `lanes_substep.rs`.
//!
//! A lane applies its impulses only where the scalar code does (masks): the others keep their
//! bodies bit for bit, so no lane's result depends on the other rows of its batch.

use super::ContactPoint;
use crate::lanes::{body_indices, not, padded, BodyLanes, Lane, MAX_LANES, V3};
use crate::solver_body::SharedBodies;

/// Solves `L::W` points at once: packed, solved once, unpacked (the solver packs once a frame
/// and solves the packed batch every iteration).
#[inline(always)]
pub fn solve_lanes<L: Lane>(rows: &mut [ContactPoint], bodies: SharedBodies) {
    let mut lanes = ContactLanes::<L>::pack(rows);
    lanes.solve(bodies);
    lanes.unpack(rows);
}

/// `L::W` contact points of one colour in lanes (Box2D v3's `b2ContactConstraintSIMD`): the
/// whole point, packed once a frame (or once a detection) and kept through the frame's
/// substeps. Each substep begins the lanes ([`ContactLanes::begin_substep`]), the iterations
/// solve them, and the velocity pass runs on them; [`ContactLanes::unpack`] hands everything
/// back to the points at the frame's end. Reading the points' fields into lanes each
/// iteration cost about as much as the solve's arithmetic; packing and unpacking them each
/// substep, with the substep's start and the velocity pass one point at a time, a sixth of the
/// 1000-ragdoll rain's frame.
#[derive(Clone, Copy, Debug)]
pub struct ContactLanes<L> {
    /// The batch's own rows (lanes past them repeat the first).
    pub(super) rows: u8,
    pub(super) index_a: [u32; MAX_LANES],
    pub(super) index_b: [u32; MAX_LANES],
    pub(super) normal: V3<L>,
    pub(super) local_a: V3<L>,
    pub(super) local_b: V3<L>,
    pub(super) arm_a: V3<L>,
    pub(super) arm_b: V3<L>,
    pub(super) anchor_a: V3<L>,
    pub(super) anchor_b: V3<L>,
    pub(super) static_friction: L,
    pub(super) dynamic_friction: L,
    pub(super) restitution: L,
    pub(super) approach_speed: L,
    pub(super) allowed_penetration: L,
    /// Whether any point is soft; a batch of hard points (the paper's projection) skips the
    /// soft terms, which would add exact zeros.
    pub(super) soft: bool,
    pub(super) compliance: L,
    pub(super) damping: L,
    pub(super) start_separation: L,
    /// Stacking's inverse-mass scales ([`super::Stacking`]); a batch without any skips them.
    pub(super) stacked: bool,
    pub(super) mass_scale_a: L,
    pub(super) mass_scale_b: L,
    pub(super) normal_impulse: L,
    pub(super) warm_impulse: L,
    pub(super) friction_impulse: L,
    /// Masks: the point has pushed this frame; it has stuck through the substep.
    pub(super) touched: L,
    pub(super) sticking: L,
}

/// A mask lane per flag.
#[inline(always)]
fn mask<L: Lane>(mut flag: impl FnMut(usize) -> bool) -> L {
    L::from_fn(|i| flag(i) as u32 as f32).gt(L::zero())
}

impl<L: Lane> ContactLanes<L> {
    /// One to `L::W` points sharing no movable body (lanes past the last repeat the first:
    /// [`padded`]).
    #[inline(always)]
    pub fn pack(rows: &[ContactPoint]) -> Self {
        assert!((1..=L::W).contains(&rows.len()), "a batch is one to W rows");
        let row = |i: usize| padded(rows, i);
        let (index_a, index_b) = body_indices::<L, _>(rows, |p| (p.body_a.0, p.body_b.0));
        ContactLanes {
            rows: rows.len() as u8,
            index_a,
            index_b,
            normal: V3::from_fn(|i| row(i).normal),
            local_a: V3::from_fn(|i| row(i).local_a),
            local_b: V3::from_fn(|i| row(i).local_b),
            arm_a: V3::from_fn(|i| row(i).arm_a),
            arm_b: V3::from_fn(|i| row(i).arm_b),
            anchor_a: V3::from_fn(|i| row(i).anchor_a),
            anchor_b: V3::from_fn(|i| row(i).anchor_b),
            static_friction: L::from_fn(|i| row(i).static_friction),
            dynamic_friction: L::from_fn(|i| row(i).dynamic_friction),
            restitution: L::from_fn(|i| row(i).restitution),
            approach_speed: L::from_fn(|i| row(i).approach_speed),
            allowed_penetration: L::from_fn(|i| row(i).allowed_penetration),
            soft: rows.iter().any(|r| r.compliance != 0.0 || r.damping != 0.0),
            compliance: L::from_fn(|i| row(i).compliance),
            damping: L::from_fn(|i| row(i).damping),
            start_separation: L::from_fn(|i| row(i).start_separation),
            stacked: rows
                .iter()
                .any(|r| r.mass_scale_a != 1.0 || r.mass_scale_b != 1.0),
            mass_scale_a: L::from_fn(|i| row(i).mass_scale_a),
            mass_scale_b: L::from_fn(|i| row(i).mass_scale_b),
            normal_impulse: L::from_fn(|i| row(i).normal_impulse),
            warm_impulse: L::from_fn(|i| row(i).warm_impulse),
            friction_impulse: L::from_fn(|i| row(i).friction_impulse),
            touched: mask(|i| row(i).touched),
            sticking: mask(|i| row(i).sticking),
        }
    }

    /// Hands the points back their state: anchors, impulses, flags and the substep's constants
    /// (the batch's own: repeated lanes are dropped).
    #[inline(always)]
    pub fn unpack(&self, rows: &mut [ContactPoint]) {
        for (i, p) in rows.iter_mut().enumerate().take(L::W) {
            p.anchor_a = self.anchor_a.lane(i);
            p.anchor_b = self.anchor_b.lane(i);
            p.allowed_penetration = self.allowed_penetration.at(i);
            p.compliance = self.compliance.at(i);
            p.damping = self.damping.at(i);
            p.start_separation = self.start_separation.at(i);
            p.mass_scale_a = self.mass_scale_a.at(i);
            p.mass_scale_b = self.mass_scale_b.at(i);
            p.normal_impulse = self.normal_impulse.at(i);
            p.warm_impulse = self.warm_impulse.at(i);
            p.friction_impulse = self.friction_impulse.at(i);
            p.touched = self.touched.at(i).to_bits() != 0;
            p.sticking = self.sticking.at(i).to_bits() != 0;
        }
    }

    /// One iteration of the batch's points: [`ContactPoint::solve`] per lane.
    #[inline(always)]
    pub fn solve(&mut self, bodies: SharedBodies) {
        let (index_a, index_b) = (&self.index_a[..L::W], &self.index_b[..L::W]);
        // SAFETY: the rows of a batch share no movable body (graph colouring).
        let (mut a, mut b) = unsafe {
            (
                BodyLanes::<L>::gather(bodies, index_a),
                BodyLanes::<L>::gather(bodies, index_b),
            )
        };
        let (n, ra, rb) = (self.normal, self.arm_a, self.arm_b);
        let zero = L::zero();
        let one = L::splat(1.0);
        let (sa, sb) = match self.stacked {
            true => (self.mass_scale_a, self.mass_scale_b),
            false => (one, one),
        };
        let normal_impulse = self.normal_impulse;

        // 1. non-penetration: measured at the turned points, pushed at the fixed lever arms
        let point_a = a.position + a.orientation.rotate(self.local_a);
        let point_b = b.position + b.orientation.rotate(self.local_b);
        let separation = (point_b - point_a).dot(n) + self.allowed_penetration;
        let ((turn_a, wa), (turn_b, wb)) = (a.response(ra, n), b.response(rb, n));
        let w = sa * wa + sb * wb;
        let active = w.gt(zero) & (separation.lt(zero) | normal_impulse.gt(zero));
        let (error, denominator) = if self.soft {
            let soft = self.compliance * w;
            let damping = self.damping;
            (
                separation + soft * normal_impulse + damping * (separation - self.start_separation),
                (L::splat(1.0) + damping) * w + soft,
            )
        } else {
            (separation, w)
        };
        let total =
            (normal_impulse - error / denominator.max(L::splat(f32::MIN_POSITIVE))).max(zero);
        let total = active.select(total, normal_impulse);
        let lambda = total - normal_impulse;
        let normal_impulse = total;
        self.normal_impulse = normal_impulse;
        a.push_along_where(active, n, turn_a, -(lambda * sa));
        b.push_along_where(active, n, turn_b, lambda * sb);

        // 2. friction, where the point pushes
        let pushing = normal_impulse.gt(zero);
        if pushing.any() {
            let friction_impulse = self.friction_impulse;
            let slip = (b.position + b.orientation.rotate(self.anchor_b))
                - (a.position + a.orientation.rotate(self.anchor_a));
            let tangential = slip - n.scale(slip.dot(n));
            let length = tangential.length();
            let moving = length.gt(L::splat(1e-9));
            let t =
                tangential.scale(moving.select(L::splat(1.0) / length.max(L::splat(1e-9)), zero));
            let ((turn_a, wa), (turn_b, wb)) = (a.response(ra, t), b.response(rb, t));
            let w = sa * wa + sb * wb;
            let active = pushing & moving & w.gt(zero);
            let needed = length / w.max(L::splat(f32::MIN_POSITIVE));
            // `<=` as in the scalar code
            let limit = self.static_friction * normal_impulse;
            let within = (friction_impulse + needed).le(limit);
            let sliding = (self.dynamic_friction * normal_impulse - friction_impulse)
                .max(zero)
                .min(needed);
            let applied = active.select(within.select(needed, sliding), zero);
            self.sticking = self.sticking & not(active & limit.lt(friction_impulse + needed));
            let applying = applied.gt(zero);
            a.push_along_where(applying, t, turn_a, applied * sa);
            b.push_along_where(applying, t, turn_b, -(applied * sb));
            self.friction_impulse = friction_impulse + applied.max(zero);
        }

        // SAFETY: as for the gather.
        unsafe {
            a.scatter(bodies, index_a);
            b.scatter(bodies, index_b);
        }
    }
}
