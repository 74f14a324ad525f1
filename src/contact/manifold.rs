//! A pair's contact manifold: at most four points, and points recognised from step to step.
//!
//! **Reduction.** Box against box can clip up to eight points. More points than four add
//! solver work without adding support: four points spanning the largest area hold a resting
//! box as well as eight (Box2D v2's reduction, Jolt's `PruneContactPoints`). Kept: the deepest
//! point; the point farthest from it; the point making the largest triangle with those two;
//! the point adding the most area outside that triangle. Distances and areas are measured in
//! the contact plane.
//!
//! **Persistence.** A point found again next step with the same [`FeatureId`](super::feature::FeatureId) on the same body
//! pair is the same contact, however far it moved (no distance threshold). What it carries
//! over is the slip its friction has not yet removed: if it stuck to the end of last step, the
//! tangential offset of its two friction anchors at the current poses becomes the offset of
//! its new anchors, so next step's friction pulls that residual back instead of letting
//! the finite iteration count's leftovers add up to creep. Carrying the offset rather than
//! the old body-space anchors lets a rolling body roll: its contact point moves over the
//! surface every step while the offset stays near zero.

use super::collider::Collider;
use super::feature::Feature;
use super::ContactPoint;
use crate::body::Body;
use crate::math::Vec3;

/// The most points a body pair keeps.
pub const MAX_POINTS: usize = 4;

/// Keeps at most [`MAX_POINTS`] of the pair's points `points[first..]`, spanning the largest
/// area (see the module docs), in their found order.
pub fn reduce(points: &mut Vec<Feature>, first: usize) {
    let pair = &points[first..];
    if pair.len() <= MAX_POINTS {
        return;
    }
    let normal = pair[0].normal;
    let flat = |f: &Feature| {
        let p = 0.5 * (f.point_a + f.point_b);
        p - p.dot(normal) * normal
    };
    let argmax = |score: &dyn Fn(&Feature) -> f32| {
        (0..pair.len())
            .max_by(|&i, &j| score(&pair[i]).total_cmp(&score(&pair[j])).then(j.cmp(&i)))
            .unwrap_or(0)
    };
    let deepest = argmax(&|f| -f.separation);
    let p0 = flat(&pair[deepest]);
    let farthest = argmax(&|f| flat(f).distance_squared(p0));
    let p1 = flat(&pair[farthest]);
    let area = |a: Vec3, b: Vec3, c: Vec3| (b - a).cross(c - a).dot(normal);
    let widest = argmax(&|f| area(p0, p1, flat(f)).abs());
    let p2 = flat(&pair[widest]);
    // outside the triangle (p0, p1, p2) beyond one of its edges, by the area that adds
    let turn = area(p0, p1, p2).signum();
    let outside = |f: &Feature| {
        let q = flat(f);
        [(p0, p1), (p1, p2), (p2, p0)]
            .map(|(a, b)| -turn * area(a, b, q))
            .into_iter()
            .fold(f32::MIN, f32::max)
    };
    let fourth = argmax(&outside);
    let mut keep = [deepest, farthest, widest, fourth];
    keep.sort_unstable();
    let kept: [Feature; MAX_POINTS] = keep.map(|i| pair[i]);
    points.truncate(first);
    // a degenerate pair (all points on a line) may pick one point twice: keep it once
    for (i, f) in kept.iter().enumerate() {
        if i == 0 || keep[i] != keep[i - 1] {
            points.push(*f);
        }
    }
}

/// The friction anchors (body space) of a point found again, whose last step's anchors were
/// `previous` and stuck to the end: its new body-space points `local_a`, `local_b`, with b's
/// shifted by the anchors' tangential offset at the current poses (see the module docs).
#[inline]
pub fn carried_anchors(
    previous: (Vec3, Vec3),
    a: &Collider,
    b: &Collider,
    normal: Vec3,
    local: (Vec3, Vec3),
) -> (Vec3, Vec3) {
    let offset = b.world_point(previous.1) - a.world_point(previous.0);
    let tangential = offset - offset.dot(normal) * normal;
    (local.0, local.1 + b.orientation.inverse() * tangential)
}

/// Friction anchors (body space) for a point that begins to stick where it is now: its
/// body-space points, b's shifted so that the two have no tangential offset at the current
/// poses (what a point found fresh starts with, at the poses it was found at).
pub fn fresh_anchors(point: &ContactPoint, a: &Body, b: &Body) -> (Vec3, Vec3) {
    let offset = b.world_point(point.local_b) - a.world_point(point.local_a);
    let tangential = offset - offset.dot(point.normal) * point.normal;
    (
        point.local_a,
        point.local_b - b.orientation.inverse() * tangential,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feature(x: f32, z: f32, separation: f32, id: u32) -> Feature {
        let p = Vec3::new(x, 0.0, z);
        Feature {
            normal: Vec3::Y,
            point_a: p,
            point_b: p,
            separation,
            id,
        }
    }

    #[test]
    fn eight_points_of_an_octagon_reduce_to_four_spanning_the_most_area() {
        // a regular octagon of radius 1, vertex 3 the deepest
        let octagon: Vec<Feature> = (0..8)
            .map(|k| {
                let angle = k as f32 * std::f32::consts::FRAC_PI_4;
                let depth = if k == 3 { -0.02 } else { -0.01 };
                feature(angle.cos(), angle.sin(), depth, k)
            })
            .collect();
        let mut points = octagon.clone();
        reduce(&mut points, 0);
        let ids: Vec<u32> = points.iter().map(|f| f.id).collect();
        // the deepest, its opposite, and the two that make a square with them: area 2, the
        // most any four vertices of the octagon span
        assert_eq!(ids, vec![1, 3, 5, 7]);
    }

    #[test]
    fn four_points_or_fewer_are_kept_as_found() {
        let mut points: Vec<Feature> = (0..4)
            .map(|k| feature(k as f32, (k * k) as f32, -0.01, k))
            .collect();
        let before = points.clone();
        reduce(&mut points, 0);
        assert_eq!(points, before);
    }

    #[test]
    fn only_the_pair_after_first_is_reduced() {
        let mut points = vec![feature(9.0, 9.0, 0.0, 99)];
        points.extend((0..6).map(|k| feature(k as f32, (k % 2) as f32, -0.01, k)));
        reduce(&mut points, 1);
        assert_eq!(points.len(), 1 + MAX_POINTS);
        assert_eq!(points[0].id, 99);
    }
}
