//! Box against sphere or capsule (a sphere is a capsule of zero length), in the box's space:
//!
//! - the segment's point deepest in, or nearest, the box: the minimum of the box's signed
//!   distance along the segment, which is convex in the segment's parameter (closed form
//!   between the parameters where a coordinate crosses a face's plane or zero);
//! - each cap centre, so a capsule lying on a face gets two points;
//! - the ends of the segment's part over the faces near the nearest point (the segment clipped
//!   to each face's tangent slabs), so a capsule across a face's edge has a point where it can
//!   sink into the face.
//!
//! A candidate within 1 cm of one kept, pushing the same way, is dropped; feature ids are the
//! candidate's slot. A capsule beyond one of the box's slabs by more than the margin is
//! skipped, and that distance is the pair's gap bound ([`super::broadphase::gaps`]).

use super::collider::Collider;
use super::feature::Feature;
use crate::math::Vec3;

/// A point (box space) against the box: the nearest surface point and outward normal, and the
/// signed distance (negative inside, measured to the face of least penetration).
fn point_box(p: Vec3, half: Vec3) -> (Vec3, Vec3, f32) {
    let clamped = p.clamp(-half, half);
    let outside = p - clamped;
    if outside.length_squared() > 1e-12 {
        let distance = outside.length();
        return (clamped, outside / distance, distance);
    }
    let depth = half - p.abs();
    let k = if depth.x <= depth.y && depth.x <= depth.z {
        0
    } else if depth.y <= depth.z {
        1
    } else {
        2
    };
    let mut normal = Vec3::ZERO;
    normal[k] = if p[k] >= 0.0 { 1.0 } else { -1.0 };
    let mut surface = p;
    surface[k] = normal[k] * half[k];
    (surface, normal, -depth[k])
}

/// Box (a) against a sphere or capsule (b): the segment's point deepest in or nearest the box,
/// each cap centre, and the ends of the segment's part over the faces near that point
/// (`box_segment_features`), so a capsule lying on a face or across its edge gets points
/// where it can sink.
pub fn box_capsule(a: &Collider, half: Vec3, b: &Collider, margin: f32, out: &mut Vec<Feature>) {
    let Some((w0, w1, radius)) = b.segment() else {
        return;
    };
    let (s0, s1) = (a.local_point(w0), a.local_point(w1));
    // a capsule beyond one of the box's slabs by more than the margin makes no point (the
    // slack covers the rounding of the candidates' distances, a few ulps of the coordinates)
    if segment_box_gap(s0, s1, half) - radius > margin + BOX_GAP_SLACK {
        return;
    }
    box_segment_features(a, half, (s0, s1, radius), margin, out);
}

/// How far (m) beyond the margin [`segment_box_gap`] must put a capsule for
/// [`box_capsule`] to skip it: many times the rounding of the candidates' distances.
const BOX_GAP_SLACK: f32 = 1e-4;

/// [`box_capsule`]'s points for the capsule's segment in box space and its radius.
fn box_segment_features(
    a: &Collider,
    half: Vec3,
    (s0, s1, radius): (Vec3, Vec3, f32),
    margin: f32,
    out: &mut Vec<Feature>,
) {
    let p = segment_point_nearest_box(s0, s1, half);
    // slots (the points' feature ids): the nearest point, the segment's ends, and two per
    // face axis for the ends of its part over that face
    let mut candidates: [Option<Vec3>; 9] = [None; 9];
    (candidates[0], candidates[1], candidates[2]) = (Some(p), Some(s0), Some(s1));
    for (k, near) in faces_near(p, half).into_iter().enumerate() {
        if near {
            // an end of the segment's part over the face that is an end of the segment is
            // already a candidate
            let (low, high) = clip_to_face(s0, s1, k, half);
            let new = |q: Vec3| (q != s0 && q != s1).then_some(q);
            (candidates[3 + 2 * k], candidates[4 + 2 * k]) = (new(low), new(high));
        }
    }
    // the kept points in box space: where on b, and the normal
    let mut kept = [(Vec3::ZERO, Vec3::ZERO); 9];
    let mut count = 0;
    for (id, candidate) in (0..).zip(candidates) {
        let Some(candidate) = candidate else {
            continue;
        };
        let (surface, normal, distance) = point_box(candidate, half);
        let separation = distance - radius;
        let on_b = candidate - radius * normal;
        // a point within 1 cm of one kept, pushing the same way, adds nothing
        let duplicate = kept[..count]
            .iter()
            .any(|&(at, n)| (at - on_b).length() < 0.01 && normal.dot(n) > 0.99);
        if separation < margin && !duplicate {
            kept[count] = (on_b, normal);
            count += 1;
            out.push(Feature {
                normal: a.orientation * normal,
                point_a: a.world_point(surface),
                point_b: a.world_point(on_b),
                separation,
                id,
            });
        }
    }
}

/// The part of segment [s0, s1] (box space) over the box's face on axis `k`: the segment
/// clipped to the face's two tangent slabs, or the whole segment where no part of it is over
/// the face. The ends of that part are where a capsule across a face's edge can sink: the
/// nearest point alone jumps along the segment as the capsule turns (a forearm across a
/// stair's edge sank 1.3 cm within one substep beside its nearest point, found 3 cm along its
/// axis a substep earlier), while the clipped ends bound the part that can touch the face.
fn clip_to_face(s0: Vec3, s1: Vec3, k: usize, half: Vec3) -> (Vec3, Vec3) {
    let d = s1 - s0;
    let (mut low, mut high) = (0.0f32, 1.0f32);
    for j in (0..3).filter(|&j| j != k) {
        if d[j].abs() < 1e-9 {
            if s0[j].abs() > half[j] {
                return (s0, s1);
            }
            continue;
        }
        let (t0, t1) = ((-half[j] - s0[j]) / d[j], (half[j] - s0[j]) / d[j]);
        low = low.max(t0.min(t1));
        high = high.min(t0.max(t1));
    }
    if low > high {
        return (s0, s1);
    }
    (point_at(s0, s1, low), point_at(s0, s1, high))
}

/// The point of segment [s0, s1] at parameter `t`, its ends exactly (`s0 + 1 (s1 - s0)` may
/// round off `s1`, and an end is recognised as one by equality).
fn point_at(s0: Vec3, s1: Vec3, t: f32) -> Vec3 {
    match t {
        0.0 => s0,
        1.0 => s1,
        _ => s0 + t * (s1 - s0),
    }
}

/// The faces whose clipped segments [`box_segment_features`] tries, for the segment's point `p`
/// nearest the box: each face `p` lies beyond (one, or two or three at an edge or a corner,
/// where the capsule may sink into either face), or the nearest face when `p` is inside.
fn faces_near(p: Vec3, half: Vec3) -> [bool; 3] {
    let beyond = p.abs().cmpgt(half);
    if beyond.any() {
        return [beyond.x, beyond.y, beyond.z];
    }
    let depth = half - p.abs();
    let nearest = depth.min_element();
    [depth.x == nearest, depth.y == nearest, depth.z == nearest]
}

/// A lower bound on the distance between segment [s0, s1] and the box of half extents `half`
/// (box space): how far the segment lies beyond the box's slab along the best of the box's
/// axes (negative when it reaches into every slab). Two convex sets are at least as far apart
/// as their extents along any axis.
fn segment_box_gap(s0: Vec3, s1: Vec3, half: Vec3) -> f32 {
    let (low, high) = (s0.min(s1), s0.max(s1));
    (low - half).max(-half - high).max_element()
}

/// A lower bound on the distance (m) between the surfaces of a box and a sphere or capsule
/// that made no point ([`super::broadphase::gaps`]): the segment's distance to the box along
/// the box's axes, less the radius.
pub(super) fn box_capsule_gap(a: &Collider, half: Vec3, b: &Collider) -> f32 {
    let Some((w0, w1, radius)) = b.segment() else {
        return f32::NEG_INFINITY;
    };
    segment_box_gap(a.local_point(w0), a.local_point(w1), half) - radius
}

/// The point of segment [s0, s1] deepest in, or nearest, the box of half extents `half` (box
/// space): the minimum of the box's signed distance along the segment, exactly. That distance
/// is convex in the segment's parameter and, between the parameters where a coordinate crosses
/// a face's plane or zero, either a squared distance that is one quadratic (outside) or the
/// largest of three linear depths (inside); so the least of those crossings brackets the
/// minimum, and the two intervals beside it are solved in closed form. Alternating projection
/// converges slowly for a capsule nearly parallel to an edge: six rounds left a shank lying
/// along a stair's edge with its point at one end, and its middle sank 2.2 cm unseen.
fn segment_point_nearest_box(s0: Vec3, s1: Vec3, half: Vec3) -> Vec3 {
    let d = s1 - s0;
    let mut crossings = [0.0f32; 11];
    crossings[1] = 1.0;
    let mut count = 2;
    for j in 0..3 {
        if d[j] == 0.0 {
            continue;
        }
        for plane in [-half[j], 0.0, half[j]] {
            let t = (plane - s0[j]) / d[j];
            if t > 0.0 && t < 1.0 {
                crossings[count] = t;
                count += 1;
            }
        }
    }
    let crossings = &mut crossings[..count];
    crossings.sort_unstable_by(f32::total_cmp);
    let at = |t: f32| s0 + t * d;
    let (mut best_t, mut best) = (0.0, f32::INFINITY);
    let mut nearest = 0;
    for (i, &t) in crossings.iter().enumerate() {
        let distance = signed_distance_to_box(at(t), half);
        if distance < best {
            (best_t, best, nearest) = (t, distance, i);
        } else if distance > best {
            break; // convex: rising from here on
        }
    }
    for i in nearest.saturating_sub(1)..(nearest + 1).min(count - 1) {
        let t = interval_minimum(s0, d, half, crossings[i], crossings[i + 1]);
        let distance = signed_distance_to_box(at(t), half);
        if distance < best {
            (best_t, best) = (t, distance);
        }
    }
    point_at(s0, s1, best_t)
}

/// The box's signed distance at `p` (box space): outside, the distance to the box; inside,
/// minus the depth below the nearest face. [`point_box`]'s distance without its surface point
/// and normal, for the many evaluations along a segment.
fn signed_distance_to_box(p: Vec3, half: Vec3) -> f32 {
    let beyond = p.abs() - half;
    let outside = beyond.max(Vec3::ZERO).length();
    outside + beyond.max_element().min(0.0)
}

/// Where the box's signed distance is least on the segment's parameter interval [t0, t1],
/// over which no coordinate crosses a face's plane or zero: each coordinate's excess over its
/// face, `g_j = sign_j (s0_j + t d_j) - half_j`, is then linear with a fixed sign. Outside the
/// box the squared distance, the sum of the positive excesses squared, is one quadratic;
/// inside, the distance is the largest excess, least at an end or where two excesses meet.
fn interval_minimum(s0: Vec3, d: Vec3, half: Vec3, t0: f32, t1: f32) -> f32 {
    let middle = s0 + 0.5 * (t0 + t1) * d;
    let sign = Vec3::select(middle.cmplt(Vec3::ZERO), -Vec3::ONE, Vec3::ONE);
    let (start, slope) = (sign * s0 - half, sign * d);
    let outside = (start + 0.5 * (t0 + t1) * slope).cmpgt(Vec3::ZERO);
    if outside.any() {
        let start = Vec3::select(outside, start, Vec3::ZERO);
        let slope = Vec3::select(outside, slope, Vec3::ZERO);
        let curvature = slope.length_squared();
        return match curvature > 0.0 {
            true => (-start.dot(slope) / curvature).clamp(t0, t1),
            false => t0,
        };
    }
    let largest = |t: f32| (start + t * slope).max_element();
    let (mut best_t, mut best) = (t0, largest(t0));
    for (i, j) in [(0, 1), (1, 2), (0, 2)] {
        if slope[i] != slope[j] {
            let t = (start[j] - start[i]) / (slope[i] - slope[j]);
            if t > t0 && t < t1 && largest(t) < best {
                (best_t, best) = (t, largest(t));
            }
        }
    }
    if largest(t1) < best {
        t1
    } else {
        best_t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::narrowphase::lcg;
    use crate::shape::Shape;

    /// The segment's point nearest the box is the least signed distance along it (against
    /// 2000 samples): random segments near, across and inside random boxes, and segments
    /// nearly parallel to an edge just outside it, where alternating projection crawls.
    #[test]
    fn the_point_nearest_a_box_is_the_least_signed_distance_along_the_segment() {
        let mut uniform = lcg(7);
        let mut random = move || uniform() - 0.5;
        for i in 0..20_000 {
            let half = Vec3::new(random() + 0.6, random() + 0.6, random() + 0.6);
            let (s0, s1) = if i % 2 == 0 {
                let s0 = 3.0 * Vec3::new(random(), random(), random());
                (s0, s0 + Vec3::new(random(), random(), random()))
            } else {
                // along the edge at (y, z) = (half.y, half.z), tilted by up to 0.1
                let edge =
                    Vec3::new(0.0, half.y, half.z) + 0.05 * Vec3::new(0.0, random(), random());
                let along = Vec3::new(1.0, 0.1 * random(), 0.1 * random());
                (
                    edge + (random() - 0.5) * along,
                    edge + (random() + 0.5) * along,
                )
            };
            let found = signed_distance_to_box(segment_point_nearest_box(s0, s1, half), half);
            let sampled = (0..=2000)
                .map(|k| signed_distance_to_box(s0 + (k as f32 / 2000.0) * (s1 - s0), half))
                .fold(f32::INFINITY, f32::min);
            assert!(
                found <= sampled + 1e-5,
                "case {i}: {found} against {sampled}"
            );
        }
    }

    /// A capsule across a face's edge has points at both ends of its part over the face, so
    /// no part of it can sink into the face between points: random capsules lying over a box's
    /// top face with one end beyond an edge, tilted either way. The part over the face is
    /// straight, so its deepest point is one of those ends; the nearest point alone missed it
    /// on most of these (the face points' shallowest bound was up to 4 cm above the deepest).
    #[test]
    fn a_capsule_across_a_face_edge_has_points_at_the_ends_of_its_part_over_the_face() {
        use crate::body::{Body, BodyKind};
        let mut uniform = lcg(3);
        let mut random = move || uniform() - 0.5;
        let mut crossing = 0;
        for i in 0..20_000 {
            let half = Vec3::new(random() + 0.7, 0.2, random() + 0.7);
            let radius = 0.03 + 0.05 * (random() + 0.5);
            let margin = 0.02;
            let inside = Vec3::new(0.8 * half.x * random(), 0.0, 0.8 * half.z * random());
            let beyond = Vec3::new(half.x + 0.3 * (random() + 0.5), 0.0, 0.4 * random());
            let (x0, x1) = if i % 2 == 0 {
                (inside, beyond)
            } else {
                (beyond, inside)
            };
            let top = half.y + radius;
            let s0 = x0 + Vec3::Y * (top + 0.04 * random());
            let s1 = x1 + Vec3::Y * (top + 0.04 * random());
            let box_body = Body::new(
                "box",
                BodyKind::Fixed,
                Shape::Cuboid { half_extents: half },
                0.0,
            );
            let mut out = Vec::new();
            box_segment_features(
                &Collider::new(&box_body),
                half,
                (s0, s1, radius),
                margin,
                &mut out,
            );
            let face = out
                .iter()
                .filter(|f| f.normal.y > 0.95)
                .map(|f| f.separation);
            let bound = face.fold(f32::INFINITY, f32::min);
            // the deepest of the segment's part over the face, sampled (within 2 mm: points
            // closer than 1 cm are merged, at these slopes up to 1.3 mm apart in depth)
            let deepest = (0..=400)
                .map(|k| s0 + (k as f32 / 400.0) * (s1 - s0))
                .filter(|p| p.x.abs() <= half.x && p.z.abs() <= half.z)
                .map(|p| p.y - half.y - radius)
                .fold(f32::INFINITY, f32::min);
            if deepest < margin {
                crossing += 1;
                assert!(
                    bound <= deepest + 2e-3,
                    "case {i}: points {bound}, segment {deepest}"
                );
            }
        }
        assert!(crossing > 10_000, "{crossing} capsules reach the face");
    }

    /// The box gap is a lower bound on the segment's distance to the box (against 400
    /// samples along it), and a capsule it puts beyond the margin makes no point: random
    /// boxes, and segments around them at distances around touching.
    #[test]
    fn the_box_gap_bounds_the_distance_and_skips_only_pairs_without_points() {
        let mut uniform = lcg(11);
        let mut random = move || uniform() - 0.5;
        let box_body = Collider::new(&crate::body::Body::new(
            "box",
            crate::body::BodyKind::Fixed,
            Shape::Cuboid {
                half_extents: Vec3::ONE,
            },
            1.0,
        ));
        let (mut skipped, mut near_threshold) = (0, 0);
        for _ in 0..50_000 {
            let half = Vec3::new(random() + 0.6, random() + 0.6, random() + 0.6);
            let s0 = 1.6 * half * Vec3::new(random(), random(), random()) * 2.0;
            let s1 = s0 + 0.4 * Vec3::new(random(), random(), random());
            let gap = segment_box_gap(s0, s1, half);
            let distance = (0..=400)
                .map(|i| point_box(s0.lerp(s1, i as f32 / 400.0), half).2)
                .fold(f32::INFINITY, f32::min);
            assert!(gap <= distance + 1e-6, "gap {gap} over distance {distance}");
            let (radius, margin) = (0.05 + 0.05 * (random() + 0.5), 0.02);
            if gap - radius > margin + BOX_GAP_SLACK {
                skipped += 1;
                near_threshold += (gap - radius < margin + 0.01) as u32;
                let mut out = Vec::new();
                box_segment_features(&box_body, half, (s0, s1, radius), margin, &mut out);
                assert!(out.is_empty(), "skipped a pair with points: {out:?}");
            }
        }
        assert!(
            skipped > 5_000 && near_threshold > 200,
            "{skipped} skipped, {near_threshold} near"
        );
    }
}
