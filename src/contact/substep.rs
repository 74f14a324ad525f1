//! What a contact point does at each substep's start and end, one point at a time (the scalar
//! solver; the SIMD solver does the same on its packed lanes, [`super::lanes`]).

use super::{manifold, ContactPoint, Stacking};
use crate::body::Body;
use crate::math::Vec3;
use crate::solver_body::{SharedSlice, SolverBody};

/// The constants a substep starts its points with ([`super::Contacts::start_substep`]).
#[derive(Clone, Copy, Debug)]
pub struct SubstepStart {
    /// The substep (s).
    pub h: f32,
    /// The push-out speed limit (m/s; infinite: none).
    pub push_speed: f32,
    /// Soft contacts' `1 / (omega h)^2` ([`super::Softness`]); zero for hard contacts.
    pub compliance: f32,
    /// Soft contacts' `2 zeta / (omega h)`; zero for hard contacts.
    pub damping: f32,
    /// Mass scaling by height.
    pub stacking: Stacking,
    /// The first substep since detection keeps the anchors detection set.
    pub first: bool,
}

impl SubstepStart {
    /// Whether the points need their separation at the substep's start (the push cap or soft
    /// damping; the paper's contacts use neither).
    pub fn needs_separation(&self) -> bool {
        self.push_speed.is_finite() || self.damping > 0.0
    }
}

impl ContactPoint {
    /// [`super::Contacts::begin_substep`] for this point.
    #[inline(always)]
    pub fn begin_substep(&mut self, bodies: &[Body], start: &SubstepStart) {
        let (a, b) = (&bodies[self.body_a.index()], &bodies[self.body_b.index()]);
        let separation = start.needs_separation().then(|| self.separation_at(a, b));
        self.allowed_penetration = match (separation, start.push_speed.is_finite()) {
            (Some(s), true) => (-s - start.push_speed * start.h).max(0.0),
            _ => 0.0,
        };
        (self.compliance, self.damping) = (start.compliance, start.damping);
        (self.mass_scale_a, self.mass_scale_b) = match start.stacking.rate {
            0.0 => (1.0, 1.0),
            _ => start.stacking.scales(a.position, b.position),
        };
        self.start_separation = match (separation, start.damping > 0.0) {
            (Some(s), true) => s + self.allowed_penetration,
            _ => 0.0,
        };
        // re-anchor a point that slid, or that has not touched yet this frame
        self.touched |= self.normal_impulse > 0.0;
        if !start.first && (!self.touched || !self.sticking) {
            (self.anchor_a, self.anchor_b) = manifold::fresh_anchors(self, a, b);
            self.sticking = true;
        }
        self.warm_impulse = self.normal_impulse;
        self.normal_impulse = 0.0;
        self.friction_impulse = 0.0;
    }

    /// The contacts' velocity pass ([`super::Contacts::velocity_pass`]) for this point.
    ///
    /// # Safety
    /// No other thread may access the point's awake dynamic bodies meanwhile, nor write its
    /// others.
    #[inline(always)]
    pub unsafe fn velocity_pass(&self, bodies: SharedSlice<Body>, threshold: f32) {
        if self.normal_impulse > 0.0 {
            self.velocity_row().apply(bodies, threshold);
        }
    }

    fn velocity_row(&self) -> VelocityRow {
        VelocityRow {
            body_a: self.body_a.index(),
            body_b: self.body_b.index(),
            normal: self.normal,
            arm_a: self.arm_a,
            arm_b: self.arm_b,
            restitution: self.restitution,
            approach_speed: self.approach_speed,
            compliance: self.compliance,
            mass_scale_a: self.mass_scale_a,
            mass_scale_b: self.mass_scale_b,
        }
    }

    /// [`super::Contacts::warm_start`] for this point, on its two bodies.
    #[inline(always)]
    pub fn warm_start(
        &mut self,
        a: &mut SolverBody,
        b: &mut SolverBody,
        fraction: f32,
        impact_speed: f32,
    ) {
        let resting = self.approach_speed >= -impact_speed;
        self.warm_impulse *= if resting { fraction } else { 0.0 };
        if self.warm_impulse <= 0.0 {
            return;
        }
        let impulse = self.warm_impulse * self.normal;
        if a.inverse_mass != 0.0 {
            a.apply_positional_impulse(-self.mass_scale_a * impulse, self.arm_a);
        }
        if b.inverse_mass != 0.0 {
            b.apply_positional_impulse(self.mass_scale_b * impulse, self.arm_b);
        }
        self.normal_impulse = self.warm_impulse;
    }
}

/// What the contacts' velocity pass reads of a point, from a [`ContactPoint`] or from its
/// lane in the SIMD solver's packed points.
#[derive(Clone, Copy, Debug)]
pub(crate) struct VelocityRow {
    pub body_a: usize,
    pub body_b: usize,
    pub normal: Vec3,
    pub arm_a: Vec3,
    pub arm_b: Vec3,
    pub restitution: f32,
    pub approach_speed: f32,
    pub compliance: f32,
    pub mass_scale_a: f32,
    pub mass_scale_b: f32,
}

impl VelocityRow {
    /// [`Contacts::velocity_pass`] of one point that pushed: its relative normal velocity to the
    /// bounce, or to zero (a soft contact, [`Softness`], keeps its spring's velocity unless it
    /// bounces). A sleeping body counts as immovable; only awake dynamic bodies change.
    ///
    /// # Safety
    /// No other thread may access the point's awake dynamic bodies meanwhile, nor write its
    /// others.
    #[inline(always)]
    pub(crate) unsafe fn apply(&self, bodies: SharedSlice<Body>, threshold: f32) {
        let p = self;
        let (pa, pb) = (bodies.ptr(p.body_a), bodies.ptr(p.body_b));
        let (ra, rb) = (p.arm_a, p.arm_b);
        let impulse = {
            let (a, b) = (&*pa, &*pb);
            let now = relative_normal_velocity(a, b, a.position + ra, b.position + rb, p.normal);
            let bounce = p.restitution > 0.0 && p.approach_speed < -threshold;
            // a soft contact is a damped spring: its velocity is the spring's, not a
            // projection's
            if !bounce && p.compliance > 0.0 {
                return;
            }
            let target = if bounce {
                -p.restitution * p.approach_speed
            } else {
                0.0
            };
            let change = target - now;
            let inverse_mass = |body: &Body, r| match body.asleep {
                true => 0.0,
                false => body.positional_inverse_mass(r, p.normal),
            };
            let w = p.mass_scale_a * inverse_mass(a, ra) + p.mass_scale_b * inverse_mass(b, rb);
            if change == 0.0 || w <= 0.0 {
                return;
            }
            (change / w) * p.normal
        };
        if (*pa).is_awake_dynamic() {
            (*pa).apply_velocity_impulse(-p.mass_scale_a * impulse, ra);
        }
        if (*pb).is_awake_dynamic() {
            (*pb).apply_velocity_impulse(p.mass_scale_b * impulse, rb);
        }
    }
}

/// Velocity of b's point minus a's along `normal` (m/s).
fn relative_normal_velocity(a: &Body, b: &Body, point_a: Vec3, point_b: Vec3, normal: Vec3) -> f32 {
    let velocity = |body: &Body, point: Vec3| {
        body.linear_velocity + body.angular_velocity.cross(point - body.position)
    };
    (velocity(b, point_b) - velocity(a, point_a)).dot(normal)
}
