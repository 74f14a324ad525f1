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
    #[inline(always)]
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
            let lower = (L::splat(-start.stacking.rate) * height.abs())
                .exp()
                .max(L::splat(start.stacking.max_ratio.recip()));
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
    #[inline(always)]
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
        let (scale_a, scale_b) = (self.mass_scale_a, self.mass_scale_b);
        a.apply_positional_impulse_where(active, impulse.scale(-scale_a), self.arm_a);
        b.apply_positional_impulse_where(active, impulse.scale(scale_b), self.arm_b);
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
    #[inline(always)]
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{Body, BodyId, BodyKind};
    use crate::contact::{ContactPoint, Stacking};
    use crate::math::{Quat, Vec3};
    use crate::shape::{Axis, Shape};
    use crate::solver_body::SolverBody;

    /// A floor and `n` tilted capsules above it at various heights, each with one point on the
    /// floor in a different state: touched or not, sticking or slid, with or without an impulse
    /// from the last substep.
    fn scene(n: usize) -> (Vec<Body>, Vec<ContactPoint>) {
        let mut bodies = vec![Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0)];
        let mut points = Vec::new();
        for i in 0..n {
            let x = i as f32;
            let shape = Shape::Capsule {
                half_height: 0.2,
                radius: 0.05,
                axis: Axis::X,
            };
            let turn = Quat::from_rotation_z(0.07 * (x - 5.0)) * Quat::from_rotation_y(0.3 * x);
            let body = Body::new(format!("c{i}"), BodyKind::Dynamic, shape, 1.0 + 0.2 * x)
                .with_pose(Vec3::new(x, 0.04 + 0.004 * x, 0.1 * x), turn);
            bodies.push(body);
            let local_b = Vec3::new(0.1 - 0.02 * x, -0.05, 0.0);
            points.push(ContactPoint {
                body_a: BodyId(0),
                body_b: BodyId(i as u32 + 1),
                normal: Vec3::Y,
                local_a: Vec3::new(x, 0.0, 0.1 * x),
                local_b,
                anchor_a: Vec3::new(x + 0.003, 0.0, 0.1 * x),
                anchor_b: local_b + Vec3::new(0.001 * x, 0.0, -0.002),
                static_friction: 0.6,
                dynamic_friction: 0.5,
                restitution: 0.1 * (i % 3) as f32,
                approach_speed: -0.5 * x,
                sticking: i % 3 != 0,
                touched: i % 2 == 0,
                normal_impulse: if i % 4 < 2 { 0.01 * x } else { 0.0 },
                friction_impulse: 0.002,
                ..ContactPoint::UNSOLVED
            });
        }
        (bodies, points)
    }

    fn start(first: bool) -> SubstepStart {
        SubstepStart {
            h: 1.0 / 240.0,
            push_speed: 3.0,
            compliance: 0.02,
            damping: 0.3,
            // the cap under most pairs' ratios, so lanes with and without it are compared
            stacking: Stacking {
                up: Vec3::Y,
                rate: 10.0,
                max_ratio: 1.2,
            },
            first,
        }
    }

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6 * (1.0 + a.abs().max(b.abs()))
    }

    /// A substep's start in lanes (16 points, and a batch of 5 padded to 16) gives each point
    /// what the scalar start gives it: the push-out allowance and soft contacts' starting
    /// separation, stacking's mass scales (the lanes' `exp`, to rounding), fresh anchors for the
    /// points that slid or have not touched from the frame's second substep on, the flags, and
    /// the impulses moved to the warm start.
    #[test]
    fn the_substep_start_in_lanes_is_the_scalar_start() {
        for (n, first) in [(16, false), (5, false), (16, true)] {
            let (bodies, points) = scene(n);
            let mut scalar = points.clone();
            scalar
                .iter_mut()
                .for_each(|p| p.begin_substep(&bodies, &start(first)));
            let mut lanes = ContactLanes::<crate::lanes::portable::Portable<16>>::pack(&points);
            lanes.begin_substep(&bodies, &start(first));
            let mut unpacked = points.clone();
            lanes.unpack(&mut unpacked);
            let mut fresh_anchors = 0;
            for (i, (s, l)) in scalar.iter().zip(&unpacked).enumerate() {
                let what = format!("point {i} of {n}, first substep {first}");
                assert!(
                    close(s.allowed_penetration, l.allowed_penetration),
                    "{what}"
                );
                assert!(close(s.start_separation, l.start_separation), "{what}");
                assert!(close(s.mass_scale_a, l.mass_scale_a), "{what}");
                assert!(close(s.mass_scale_b, l.mass_scale_b), "{what}");
                assert!((s.anchor_b - l.anchor_b).length() < 1e-6, "{what}");
                assert_eq!(s.anchor_a, l.anchor_a, "{what}");
                assert_eq!((s.touched, s.sticking), (l.touched, l.sticking), "{what}");
                assert_eq!(s.warm_impulse, l.warm_impulse, "{what}");
                assert_eq!((l.normal_impulse, l.friction_impulse), (0.0, 0.0), "{what}");
                assert_eq!(
                    (s.compliance, s.damping),
                    (l.compliance, l.damping),
                    "{what}"
                );
                fresh_anchors += (points[i].anchor_b != s.anchor_b) as u32;
            }
            // the second substep re-anchors some points, the first none
            assert_eq!(
                fresh_anchors == 0,
                first,
                "{n} points, first substep {first}"
            );
        }
    }

    /// The warm start in lanes moves the preview poses as the scalar warm start does, point
    /// after point (the rows share no movable body), and the velocity pass read from the lanes
    /// changes the world bodies' velocities to the bit as the scalar pass.
    #[test]
    fn the_warm_start_and_the_velocity_pass_in_lanes_are_the_scalar_ones() {
        let (mut bodies, points) = scene(16);
        for (i, body) in bodies.iter_mut().enumerate().skip(1) {
            body.linear_velocity = Vec3::new(0.1 * i as f32, -0.4, 0.05);
            body.angular_velocity = Vec3::new(0.3, -0.2 * i as f32, 0.1);
        }
        let mut begun = points.clone();
        begun
            .iter_mut()
            .for_each(|p| p.begin_substep(&bodies, &start(false)));
        // the scalar passes, point after point
        let mut scalar_hot: Vec<SolverBody> = bodies.iter().map(SolverBody::from_body).collect();
        let mut scalar = begun.clone();
        for p in &mut scalar {
            let (a, b) = crate::solver_body::pair_mut(&mut scalar_hot, 0, p.body_b.index());
            p.warm_start(a, b, 0.5, 10.0);
        }
        let mut scalar_bodies = bodies.clone();
        let shared = SharedSlice::new(&mut scalar_bodies);
        // SAFETY: one thread
        scalar
            .iter()
            .for_each(|p| unsafe { p.velocity_pass(shared, 0.3) });
        // the lanes
        let mut lanes_hot: Vec<SolverBody> = bodies.iter().map(SolverBody::from_body).collect();
        let mut lanes = ContactLanes::<crate::lanes::portable::Portable<16>>::pack(&begun);
        lanes.warm_start(SharedBodies::new(&mut lanes_hot), 0.5, 10.0);
        let mut lanes_bodies = bodies.clone();
        // SAFETY: one thread
        unsafe { lanes.velocity_pass(SharedSlice::new(&mut lanes_bodies), 0.3) };
        let mut unpacked = begun.clone();
        lanes.unpack(&mut unpacked);
        let (mut moved, mut slowed) = (0, 0);
        for i in 1..bodies.len() {
            let (s, l) = (&scalar_hot[i], &lanes_hot[i]);
            assert!((s.position - l.position).length() < 1e-6, "body {i}");
            assert!(
                s.orientation.dot(l.orientation).abs() > 1.0 - 1e-6,
                "body {i}"
            );
            moved += (s.position != bodies[i].position) as u32;
            let (s, l) = (&scalar_bodies[i], &lanes_bodies[i]);
            assert_eq!(s.linear_velocity, l.linear_velocity, "body {i}");
            assert_eq!(s.angular_velocity, l.angular_velocity, "body {i}");
            slowed += (l.linear_velocity != bodies[i].linear_velocity) as u32;
        }
        assert!(moved >= 4, "{moved} bodies warm-started");
        assert!(slowed >= 4, "{slowed} bodies changed by the velocity pass");
        for (s, l) in scalar.iter().zip(&unpacked) {
            assert_eq!(
                (s.warm_impulse, s.normal_impulse),
                (l.warm_impulse, l.normal_impulse)
            );
        }
    }
}
