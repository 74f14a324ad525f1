//! One candidate pair's narrow phase: its reach, the shape test (or what the lanes found), and
//! its contact points, each taking its predecessor's impulse and anchors.

use crate::body::BodyId;
use crate::contact::broadphase::gaps;
use crate::contact::collider::Collider;
use crate::contact::feature::Feature;
use crate::contact::handover::Handover;
use crate::contact::round_lanes::{round_radius, RoundTest};
use crate::contact::{manifold, narrowphase, ContactPoint};

/// What the narrow phase of one pair reads.
pub(super) struct PairContext<'a> {
    pub(super) colliders: &'a [Collider],
    pub(super) handover: &'a Handover,
    pub(super) dt: f32,
    pub(super) margin: f32,
}

impl PairContext<'_> {
    /// Whether both bodies are spheres or capsules ([`round_lanes`](crate::contact::round_lanes)).
    pub(super) fn is_round(&self, a: u32, b: u32) -> bool {
        let round = |i: u32| round_radius(&self.colliders[i as usize].shape).is_some();
        round(a) && round(b)
    }

    /// How far the pair's surfaces may be apart and still make a point: the margin plus how
    /// far they may close this frame, the relative speed of the centres plus what spin adds at
    /// the farthest surface point (a limb spinning at 20 rad/s moves its tip 5 cm a frame
    /// further than its centre).
    pub(super) fn reach(&self, a: u32, b: u32) -> f32 {
        let (ca, cb) = (&self.colliders[a as usize], &self.colliders[b as usize]);
        let closing =
            (ca.linear_velocity - cb.linear_velocity).length() + ca.spin_bound + cb.spin_bound;
        self.margin + self.dt * closing
    }

    /// The contact points of the pair (a, b) within `reach` ([`Self::reach`]; filtered, then
    /// the narrow phase, or what the lanes found, `test`) onto `points`, and a lower bound on
    /// the distance of its shapes if it made none ([`gaps`]).
    pub(super) fn collide(
        &self,
        a: u32,
        b: u32,
        (test, reach): (RoundTest, f32),
        points: &mut Vec<ContactPoint>,
        features: &mut Vec<Feature>,
    ) -> f32 {
        let (ca, cb) = (&self.colliders[a as usize], &self.colliders[b as usize]);
        if ca.collision_group & cb.collision_mask == 0
            || cb.collision_group & ca.collision_mask == 0
        {
            return gaps::UNKNOWN;
        }
        features.clear();
        match test {
            RoundTest::Scalar => {
                if !narrowphase::collide(ca, cb, reach, features) {
                    return narrowphase::gap(ca, cb);
                }
            }
            RoundTest::Apart { gap } => return gap,
            RoundTest::Close { on_a, on_b, gap } => {
                let radius = |c: &Collider| round_radius(&c.shape).unwrap_or(0.0);
                let (on_a, on_b) = ((on_a, radius(ca)), (on_b, radius(cb)));
                features.extend(narrowphase::sphere_sphere(ca, cb, on_a, on_b, reach, 0));
                if features.is_empty() {
                    return gap;
                }
            }
        }
        let static_friction = (ca.static_friction * cb.static_friction).sqrt();
        let dynamic_friction = (ca.dynamic_friction * cb.dynamic_friction).sqrt();
        let restitution = ca.restitution.max(cb.restitution);
        let previous = self.handover.of_pair(a, b);
        manifold::reduce(features, 0);
        for f in features.iter() {
            let (local_a, local_b) = (ca.local_point(f.point_a), cb.local_point(f.point_b));
            let same = previous.clone().find(|p| p.id == f.id);
            let warm_impulse = same.map_or(0.0, |p| p.normal_impulse);
            let kept = same.filter(|p| p.sticking);
            let (anchor_a, anchor_b) = kept.map_or((local_a, local_b), |p| {
                let anchors = (p.anchor_a, p.anchor_b);
                manifold::carried_anchors(anchors, ca, cb, f.normal, (local_a, local_b))
            });
            points.push(ContactPoint {
                body_a: BodyId(a),
                body_b: BodyId(b),
                id: f.id,
                normal: f.normal,
                local_a,
                local_b,
                arm_a: f.point_a - ca.position,
                arm_b: f.point_b - cb.position,
                anchor_a,
                anchor_b,
                static_friction,
                dynamic_friction,
                restitution,
                approach_speed: (cb.point_velocity(f.point_b) - ca.point_velocity(f.point_a))
                    .dot(f.normal),
                normal_impulse: warm_impulse,
                ..ContactPoint::UNSOLVED
            });
        }
        gaps::UNKNOWN
    }
}
