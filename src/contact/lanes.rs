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
//! An inactive lane applies a zero impulse, which leaves its bodies as they were (the
//! orientation is rebuilt from the same predicted orientation and correction).

use super::ContactPoint;
use crate::lanes::{body_indices, padded, BodyLanes, Lane, MAX_LANES, V3};
use crate::solver_body::SharedBodies;

/// Solves `L::W` points at once: packed, solved once, unpacked (the solver packs once a
/// substep and solves the packed batch every iteration).
pub fn solve_lanes<L: Lane>(rows: &mut [ContactPoint], bodies: SharedBodies) {
    let mut lanes = ContactLanes::<L>::pack(rows);
    lanes.solve(bodies);
    lanes.unpack(rows);
}

/// `L::W` contact points of one colour in lanes: what a solve reads, packed once a substep
/// (nothing here changes between iterations), and the impulses the iterations accumulate,
/// which [`ContactLanes::unpack`] hands back to the points (Box2D v3's
/// `b2ContactConstraintSIMD`). Reading the points' fields into lanes each iteration cost
/// about as much as the solve's arithmetic.
#[derive(Clone, Copy, Debug)]
pub struct ContactLanes<L> {
    index_a: [u32; MAX_LANES],
    index_b: [u32; MAX_LANES],
    normal: V3<L>,
    local_a: V3<L>,
    local_b: V3<L>,
    arm_a: V3<L>,
    arm_b: V3<L>,
    anchor_a: V3<L>,
    anchor_b: V3<L>,
    static_friction: L,
    dynamic_friction: L,
    allowed_penetration: L,
    /// Whether any point is soft; a batch of hard points (the paper's projection) skips the
    /// soft terms, which would add exact zeros.
    soft: bool,
    compliance: L,
    damping: L,
    start_separation: L,
    /// Stacking's inverse-mass scales ([`super::Stacking`]); a batch without any skips them.
    stacked: bool,
    mass_scale_a: L,
    mass_scale_b: L,
    normal_impulse: L,
    friction_impulse: L,
    /// Lanes that slid in some iteration (their points stop sticking).
    slid: L,
}

impl<L: Lane> ContactLanes<L> {
    /// One to `L::W` points sharing no movable body (lanes past the last repeat the first:
    /// [`padded`]), at the start of a substep's iterations.
    pub fn pack(rows: &[ContactPoint]) -> Self {
        assert!((1..=L::W).contains(&rows.len()), "a batch is one to W rows");
        let row = |i: usize| padded(rows, i);
        let (index_a, index_b) = body_indices::<L, _>(rows, |p| (p.body_a.0, p.body_b.0));
        ContactLanes {
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
            friction_impulse: L::from_fn(|i| row(i).friction_impulse),
            slid: L::zero(),
        }
    }

    /// Hands the accumulated impulses, and whether a point slid, back to the points (the
    /// batch's own: repeated lanes are dropped).
    pub fn unpack(&self, rows: &mut [ContactPoint]) {
        for (i, p) in rows.iter_mut().enumerate().take(L::W) {
            p.normal_impulse = self.normal_impulse.lane(i);
            p.friction_impulse = self.friction_impulse.lane(i);
            if self.slid.lane(i).to_bits() != 0 {
                p.sticking = false;
            }
        }
    }

    /// One iteration of the batch's points: [`ContactPoint::solve`] per lane.
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
        let w = sa * a.positional_inverse_mass(ra, n) + sb * b.positional_inverse_mass(rb, n);
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
        a.apply_positional_impulse(n.scale(-(lambda * sa)), ra);
        b.apply_positional_impulse(n.scale(lambda * sb), rb);

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
            let w = sa * a.positional_inverse_mass(ra, t) + sb * b.positional_inverse_mass(rb, t);
            let active = pushing & moving & w.gt(zero);
            let needed = length / w.max(L::splat(f32::MIN_POSITIVE));
            // `<=` as in the scalar code
            let limit = self.static_friction * normal_impulse;
            let within = (friction_impulse + needed).le(limit);
            let sliding = (self.dynamic_friction * normal_impulse - friction_impulse)
                .max(zero)
                .min(needed);
            let applied = active.select(within.select(needed, sliding), zero);
            self.slid = self.slid | (active & limit.lt(friction_impulse + needed));
            a.apply_positional_impulse(t.scale(applied * sa), ra);
            b.apply_positional_impulse(t.scale(-(applied * sb)), rb);
            self.friction_impulse = friction_impulse + applied.max(zero);
        }

        // SAFETY: as for the gather.
        unsafe {
            a.scatter(bodies, index_a);
            b.scatter(bodies, index_b);
        }
    }
}
