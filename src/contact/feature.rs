//! What the narrow phase's pair tests share: the contact they report ([`Feature`], named by
//! [`FeatureId`]) and the closest points of two segments (capsule cores and box edges).

use crate::math::Vec3;

/// A contact found between bodies a and b: world normal from a to b, world points on each
/// surface, their separation along the normal (negative when penetrating), and which features
/// of the two shapes meet there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feature {
    /// Unit world normal from a to b.
    pub normal: Vec3,
    /// World point on a's surface.
    pub point_a: Vec3,
    /// World point on b's surface.
    pub point_b: Vec3,
    /// Distance (m) from `point_a` to `point_b` along the normal; negative when penetrating.
    pub separation: f32,
    /// The touching features (a box corner, a cap, a clipped edge; see [`FeatureId`]).
    pub id: FeatureId,
}

/// Names the features of the two shapes that meet at a contact point, unique among one pair's
/// points: a point found again next step with the same id on the same body pair is the same
/// contact (Box2D v3's `b2ManifoldPoint::id`, Jolt's feature keys), whatever its distance
/// from last step's. Capsules: 0 for the closest points, 1 and 2 for the two ends of a
/// parallel overlap or the two cap centres; a box against a half-space: the corner index;
/// boxes: [`super::box_box`].
pub type FeatureId = u32;

/// Closest points between segments [p0, p1] and [q0, q1] (Ericson, Real-Time Collision
/// Detection, 5.1.9), robust for points and parallel segments.
pub fn closest_points_on_segments(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> (Vec3, Vec3) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    const EPS: f32 = 1e-12;
    let (s, t) = if a <= EPS && e <= EPS {
        (0.0, 0.0)
    } else if a <= EPS {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= EPS {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s = if denom > EPS {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    (p0 + s * d1, q0 + t * d2)
}
