//! The substep's start, the warm start and the velocity pass of [`ContactLanes`], W points at a
//! time: [`ContactPoint::begin_substep`](super::ContactPoint::begin_substep),
//! [`Contacts::warm_start`](super::Contacts::warm_start) and the contacts' velocity pass, with
//! their branches as masks. Together with the packed solve they keep a point in lanes from
//! the frame's detection to its end.

use super::lanes::ContactLanes;
use super::substep::VelocityRow;
use super::SubstepStart;
use crate::body::Body;
use crate::lanes::{not, BodyLanes, Lane, Q, V3};
use crate::solver_body::{SharedBodies, SharedSlice};

impl<L: Lane> ContactLanes<L> {
    /// [`ContactPoint::begin_substep`](super::ContactPoint::begin_substep) per lane: the push-out
    /// allowance and soft contacts' starting separation, stacking's mass scales, fresh anchors
    /// for points that slid or have not touched yet (from the frame's second substep on), and
    /// the accumulated impulses reset (the last substep's normal impulse kept to warm-start).
    pub fn begin_substep(&mut self, bodies: &[Body], start: &SubstepStart) {
        let zero = L::zero();
        let one = L::splat(1.0);
        let body_a = |i: usize| &bodies[self.index_a[i] as usize];
        let body_b = |i: usize| &bodies[self.index_b[i] as usize];
        let (pa, qa) = (
            V3::<L>::from_fn(|i| body_a(i).position),
            Q::<L>::from_fn(|i| body_a(i).orientation),
        );
        let (pb, qb) = (
            V3::<L>::from_fn(|i| body_b(i).position),
            Q::<L>::from_fn(|i| body_b(i).orientation),
        );
        let n = self.normal;
        // b's point less a's at the substep's start: the separation along n, and the slip a
        // fresh anchor takes out
        let offset = (pb + qb.rotate(self.local_b)) - (pa + qa.rotate(self.local_a));
        let separation = offset.dot(n);
        let capped = start.push_speed.is_finite();
        self.allowed_penetration = match start.needs_separation() && capped {
            true => (-separation - L::splat(start.push_speed * start.h)).max(zero),
            false => zero,
        };
        self.compliance = L::splat(start.compliance);
        self.damping = L::splat(start.damping);
        self.soft = start.compliance != 0.0 || start.damping != 0.0;
        self.start_separation = match start.damping > 0.0 {
            true => separation + self.allowed_penetration,
            false => zero,
        };
        self.stacked = start.stacking.rate != 0.0;
        if self.stacked {
            let height = (pb - pa).dot(V3::splat(start.stacking.up));
            let lower = (L::splat(-start.stacking.rate) * height.abs()).exp();
            self.mass_scale_a = height.gt(zero).select(lower, one);
            self.mass_scale_b = height.lt(zero).select(lower, one);
        } else {
            self.mass_scale_a = one;
            self.mass_scale_b = one;
        }
        self.touched = self.touched | self.normal_impulse.gt(zero);
        if !start.first {
            let fresh = not(self.touched) | not(self.sticking);
            if fresh.any() {
                let tangential = offset - n.scale(offset.dot(n));
                let anchor_b = self.local_b - qb.conjugate().rotate(tangential);
                self.anchor_a = V3::select(fresh, self.local_a, self.anchor_a);
                self.anchor_b = V3::select(fresh, anchor_b, self.anchor_b);
                self.sticking = self.sticking | fresh;
            }
        }
        self.warm_impulse = self.normal_impulse;
        self.normal_impulse = zero;
        self.friction_impulse = zero;
    }

    /// [`Contacts::warm_start`](super::Contacts::warm_start) per lane: `fraction` of a resting
    /// point's last normal impulse, applied to the preview poses and made the substep's
    /// accumulated impulse.
    pub fn warm_start(&mut self, bodies: SharedBodies, fraction: f32, impact_speed: f32) {
        let zero = L::zero();
        let resting = not(self.approach_speed.lt(L::splat(-impact_speed)));
        self.warm_impulse = self.warm_impulse * resting.select(L::splat(fraction), zero);
        let active = self.warm_impulse.gt(zero);
        if !active.any() {
            return;
        }
        let (index_a, index_b) = (&self.index_a[..L::W], &self.index_b[..L::W]);
        // SAFETY: the rows of a batch share no movable body (graph colouring).
        let (mut a, mut b) = unsafe {
            (
                BodyLanes::<L>::gather(bodies, index_a),
                BodyLanes::<L>::gather(bodies, index_b),
            )
        };
        let impulse = self.normal.scale(active.select(self.warm_impulse, zero));
        a.apply_positional_impulse(impulse.scale(-self.mass_scale_a), self.arm_a);
        b.apply_positional_impulse(impulse.scale(self.mass_scale_b), self.arm_b);
        self.normal_impulse = active.select(self.warm_impulse, self.normal_impulse);
        // SAFETY: as for the gather.
        unsafe {
            a.scatter(bodies, index_a);
            b.scatter(bodies, index_b);
        }
    }

    /// The contacts' velocity pass ([`super::Contacts::velocity_pass`]) for the batch's points
    /// that pushed this substep, one after another: read from the lanes, the scalar pass
    /// itself. (A pass in lanes, the same arithmetic and bits, gathered every lane's two world
    /// bodies, about twenty fields each, for a few multiplications: 1.5 times the scalar pass
    /// field by field, 1.1 times with the bodies' first 96 bytes transposed as six groups of
    /// four floats.)
    ///
    /// # Safety
    /// No other thread may access the batch's awake dynamic bodies meanwhile, nor write its
    /// others.
    pub unsafe fn velocity_pass(&self, bodies: SharedSlice<Body>, threshold: f32) {
        let zero = L::zero();
        let pushing = self.normal_impulse.gt(zero);
        if !pushing.any() {
            return;
        }
        for i in 0..self.rows as usize {
            if pushing.at(i).to_bits() == 0 {
                continue;
            }
            let row = VelocityRow {
                body_a: self.index_a[i] as usize,
                body_b: self.index_b[i] as usize,
                normal: self.normal.lane(i),
                arm_a: self.arm_a.lane(i),
                arm_b: self.arm_b.lane(i),
                restitution: self.restitution.at(i),
                approach_speed: self.approach_speed.at(i),
                compliance: self.compliance.at(i),
                mass_scale_a: self.mass_scale_a.at(i),
                mass_scale_b: self.mass_scale_b.at(i),
            };
            row.apply(bodies, threshold);
        }
    }
}
