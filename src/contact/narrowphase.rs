//! Narrow phase: closest features of a pair of shapes at the current poses, turned into contact
//! points. Spheres are capsules of zero length. Pairs: sphere/capsule with sphere/capsule, box
//! and half-space; box with half-space; box with sphere/capsule in [`super::box_capsule`], box
//! with box in [`super::box_box`]. Shapes are read from the step's [`Collider`] records.

use super::box_capsule::{box_capsule, box_capsule_gap};
use super::collider::Collider;
use super::feature::{closest_points_on_segments, Feature, FeatureId};
use crate::math::Vec3;
use crate::shape::Shape;

/// Sphere/capsule against sphere/capsule: one point at the closest features, two when the
/// segments are parallel and overlap (so a capsule lying on another does not rock).
pub fn capsule_capsule(a: &Collider, b: &Collider, margin: f32, out: &mut Vec<Feature>) {
    // Bounding spheres first: every surface point lies within `half height + radius` of the
    // centre, so centres farther apart than both plus the reach have no feature in reach. On
    // the 1000-ragdoll rain about one capsule pair in eight ends here (counted over 10 s).
    let reach = a.bounding_radius + b.bounding_radius + margin;
    if (b.position - a.position).length_squared() > reach * reach {
        return;
    }
    let (Some((a0, a1, ra)), Some((b0, b1, rb))) = (a.segment(), b.segment()) else {
        return;
    };
    // beyond this (squared, a hair over the reach so rounding cannot differ) no point: the
    // square root and the division wait for the pairs that may touch
    let beyond = {
        let touch = ra + rb + margin;
        touch * touch * (1.0 + 1e-3)
    };
    let push = |pa: Vec3, pb: Vec3, id: FeatureId| {
        if (pb - pa).length_squared() <= beyond {
            out.extend(sphere_sphere(a, b, (pa, ra), (pb, rb), margin, id));
        }
    };
    let (da, db) = (a1 - a0, b1 - b0);
    // segments whose angle has a sine clearly over 1e-3 (squared with a factor 2 to spare)
    // skip the exact test's three square roots: most pairs
    let (la, lb) = (da.length_squared(), db.length_squared());
    let maybe_parallel = da.cross(db).length_squared() <= 2e-6 * la * lb;
    let parallel = maybe_parallel
        && la > 1e-12
        && lb > 1e-12
        && da.normalize().cross(db.normalize()).length() < 1e-3;
    // Crossing segments whose lines pass farther apart than the reach have no point: the
    // distance between the lines, |(centre b - centre a) . c| / |c| with c = da x db, bounds
    // the segments' from below. The bound is loosened by 1% and by 1e-3 of the bounding radii
    // (the computed c tilts off the true perpendicular by at most 1.4e-4 rad when its sine is
    // over 1.4e-3, moving the projected segments by 1.4e-4 of their length), so the pairs it
    // ends are pairs the closest points would end too. A third of the rain's segment tests.
    if !maybe_parallel {
        let c = da.cross(db);
        let across = (b.position - a.position).dot(c);
        let bound = 1.01 * (ra + rb + margin) + 1e-3 * (a.bounding_radius + b.bounding_radius);
        if across * across > bound * bound * c.length_squared() {
            return;
        }
    }
    segment_pairs(parallel, (a0, a1), (b0, b1), push);
}

/// A lower bound on the distance (m) between the surfaces of two spheres or capsules, for a pair
/// that made no point ([`super::broadphase::gaps`]): the bounding spheres' gap when that alone
/// is large, else the segments' distance less the radii (what `capsule_capsule` measures).
/// [`f32::NEG_INFINITY`] for other shapes.
pub fn capsule_gap(a: &Collider, b: &Collider) -> f32 {
    let (Some((a0, a1, ra)), Some((b0, b1, rb))) = (a.segment(), b.segment()) else {
        return f32::NEG_INFINITY;
    };
    let spheres = (b.position - a.position).length() - a.bounding_radius - b.bounding_radius;
    if spheres > 0.1 {
        return spheres;
    }
    let (pa, pb) = closest_points_on_segments(a0, a1, b0, b1);
    (pb - pa).length() - ra - rb
}

/// The closest points of two segments, as (point on a, point on b, id) handed to `push`: one
/// pair, or where the segments are `parallel` and overlap, the two ends of the overlap of b's
/// segment projected on a's (ids 1 and 2).
fn segment_pairs(
    parallel: bool,
    (a0, a1): (Vec3, Vec3),
    (b0, b1): (Vec3, Vec3),
    mut push: impl FnMut(Vec3, Vec3, FeatureId),
) {
    if parallel {
        let da = a1 - a0;
        let axis = da.normalize();
        let project = |p: Vec3| (p - a0).dot(axis).max(0.0).min(da.length());
        let (s0, s1) = (project(b0), project(b1));
        if (s0 - s1).abs() > 1e-6 {
            for (s, id) in [(s0, 1), (s1, 2)] {
                let pa = a0 + s * axis;
                let (_, pb) = closest_points_on_segments(pa, pa, b0, b1);
                push(pa, pb, id);
            }
            return;
        }
    }
    let (pa, pb) = closest_points_on_segments(a0, a1, b0, b1);
    push(pa, pb, 0);
}

/// The feature between a sphere of a (centre and radius) and one of b, closer than `margin`;
/// spheres with coinciding centres are pushed apart along the line between the bodies.
#[inline]
pub(super) fn sphere_sphere(
    a: &Collider,
    b: &Collider,
    (pa, ra): (Vec3, f32),
    (pb, rb): (Vec3, f32),
    margin: f32,
    id: FeatureId,
) -> Option<Feature> {
    let delta = pb - pa;
    let distance = delta.length();
    let normal = if distance > 1e-9 {
        delta / distance
    } else {
        (b.position - a.position).try_normalize().unwrap_or(Vec3::Y)
    };
    let separation = distance - ra - rb;
    (separation < margin).then(|| Feature {
        normal,
        point_a: pa + ra * normal,
        point_b: pb - rb * normal,
        separation,
        id,
    })
}

/// Half-space (body a: the plane through its position with normal `orientation * +Y`, solid
/// below) against a sphere or capsule: one point per cap centre within reach.
pub fn half_space_capsule(plane: &Collider, b: &Collider, margin: f32, out: &mut Vec<Feature>) {
    let Some((b0, b1, rb)) = b.segment() else {
        return;
    };
    let normal = plane.orientation * Vec3::Y;
    let ends: &[Vec3] = if (b1 - b0).length_squared() < 1e-12 {
        &[b0]
    } else {
        &[b0, b1]
    };
    for (id, &c) in (0..).zip(ends) {
        let height = (c - plane.position).dot(normal);
        let separation = height - rb;
        if separation < margin {
            out.push(Feature {
                normal,
                point_a: c - height * normal,
                point_b: c - rb * normal,
                separation,
                id,
            });
        }
    }
}

/// The eight corners of a box in world space.
fn box_corners(body: &Collider, half: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        let sign = Vec3::new(
            if i & 1 == 0 { -1.0 } else { 1.0 },
            if i & 2 == 0 { -1.0 } else { 1.0 },
            if i & 4 == 0 { -1.0 } else { 1.0 },
        );
        body.world_point(sign * half)
    })
}

/// Half-space against a box: one point per corner within reach.
pub fn half_space_box(
    plane: &Collider,
    b: &Collider,
    half: Vec3,
    margin: f32,
    out: &mut Vec<Feature>,
) {
    let normal = plane.orientation * Vec3::Y;
    for (id, corner) in (0..).zip(box_corners(b, half)) {
        let separation = (corner - plane.position).dot(normal);
        if separation < margin {
            out.push(Feature {
                normal,
                point_a: corner - separation * normal,
                point_b: corner,
                separation,
                id,
            });
        }
    }
}

/// A lower bound on the distance (m) between the surfaces of a pair that made no point
/// ([`super::broadphase::gaps`]): [`capsule_gap`] for two spheres or capsules, the box's axes
/// for a box and a sphere or capsule, [`f32::NEG_INFINITY`] (no bound) for the rest.
pub fn gap(a: &Collider, b: &Collider) -> f32 {
    match (&a.shape, &b.shape) {
        (Shape::Cuboid { half_extents }, _) => box_capsule_gap(a, *half_extents, b),
        (_, Shape::Cuboid { half_extents }) => box_capsule_gap(b, *half_extents, a),
        _ => capsule_gap(a, b),
    }
}

/// Contacts between two bodies at their current poses, within `margin`; normals point from a
/// to b.
pub fn collide(a: &Collider, b: &Collider, margin: f32, out: &mut Vec<Feature>) -> bool {
    let before = out.len();
    let round = |s: &Shape| matches!(s, Shape::Sphere { .. } | Shape::Capsule { .. });
    match (&a.shape, &b.shape) {
        (Shape::HalfSpace, s) if round(s) => half_space_capsule(a, b, margin, out),
        (Shape::HalfSpace, Shape::Cuboid { half_extents }) => {
            half_space_box(a, b, *half_extents, margin, out)
        }
        (sa, sb) if round(sa) && round(sb) => capsule_capsule(a, b, margin, out),
        (Shape::Cuboid { half_extents }, s) if round(s) => {
            box_capsule(a, *half_extents, b, margin, out)
        }
        (s, Shape::Cuboid { half_extents }) if round(s) => {
            box_capsule(b, *half_extents, a, margin, out);
            for f in &mut out[before..] {
                *f = Feature {
                    normal: -f.normal,
                    point_a: f.point_b,
                    point_b: f.point_a,
                    ..*f
                };
            }
        }
        (Shape::Cuboid { half_extents: ha }, Shape::Cuboid { half_extents: hb }) => {
            super::box_box::box_box(a, *ha, b, *hb, margin, out)
        }
        _ => {}
    }
    out.len() > before
}

/// A generator of floats in [0, 1) (a linear congruential one), for tests.
#[cfg(test)]
pub(super) fn lcg(mut seed: u32) -> impl FnMut() -> f32 {
    move || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1 << 24) as f32
    }
}

/// Pair `i` of the random sphere and capsule pairs the narrow phase is checked on to the bit,
/// with a margin: crossing at any angle, nearly parallel (sines around the thresholds 1e-3
/// and 1.4e-3) and exactly parallel, at distances around touching.
#[cfg(test)]
pub(super) fn random_round_pair(
    i: u32,
    random: &mut dyn FnMut() -> f32,
) -> (Collider, Collider, f32) {
    use crate::body::{Body, BodyKind};
    use crate::math::Quat;
    use crate::shape::Axis;
    let shape = |random: &mut dyn FnMut() -> f32| match i % 7 {
        0 => Shape::Sphere {
            radius: 0.02 + 0.1 * random(),
        },
        _ => Shape::Capsule {
            half_height: 0.05 + 0.3 * random(),
            radius: 0.02 + 0.06 * random(),
            axis: Axis::Y,
        },
    };
    let direction = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
    let turn = Quat::from_rotation_arc(Vec3::Y, direction);
    let angle = match i % 4 {
        0 => 3.0 * random(),
        1 => 2e-3 * random(),
        2 => 0.0,
        _ => 1e-3 + 1e-3 * (random() - 0.5),
    };
    let tilt = Vec3::new(random() - 0.5, 0.0, random() - 0.5).normalize();
    let other = turn * Quat::from_axis_angle(tilt, angle);
    let offset = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5) * 0.6;
    let centre = Vec3::new(10.0 * random(), random(), 10.0 * random());
    let body = |s: Shape, p: Vec3, q: Quat| {
        Collider::new(&Body::new("c", BodyKind::Dynamic, s, 1.0).with_pose(p, q))
    };
    let a = body(shape(random), centre, turn);
    let b = body(shape(random), centre + offset, other);
    (a, b, 0.02 + 0.05 * random())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `capsule_capsule` as it was before its shortcuts (the exact parallel test and the
    /// distance for every pair, no line bound): the reference the shortcuts must match.
    fn reference(a: &Collider, b: &Collider, margin: f32, out: &mut Vec<Feature>) {
        let reach = a.bounding_radius + b.bounding_radius + margin;
        if (b.position - a.position).length_squared() > reach * reach {
            return;
        }
        let (Some((a0, a1, ra)), Some((b0, b1, rb))) = (a.segment(), b.segment()) else {
            return;
        };
        let push = |pa: Vec3, pb: Vec3, id: FeatureId| {
            out.extend(sphere_sphere(a, b, (pa, ra), (pb, rb), margin, id));
        };
        let (da, db) = (a1 - a0, b1 - b0);
        let parallel = da.length_squared() > 1e-12
            && db.length_squared() > 1e-12
            && da.normalize().cross(db.normalize()).length() < 1e-3;
        segment_pairs(parallel, (a0, a1), (b0, b1), push);
    }

    /// The shortcuts change no bit: 200 000 random capsule and sphere pairs, crossing at any
    /// angle, nearly parallel (sines around the thresholds 1e-3 and 1.4e-3) and exactly
    /// parallel, at distances around touching (where the bounds cut), give the same features
    /// as the reference (47 000 of them touch; the line bound ends over 20 000).
    #[test]
    fn the_shortcuts_give_the_reference_points_to_the_bit() {
        let mut random = lcg(2024);
        let (mut touching, mut ended_by_line) = (0, 0);
        for i in 0..200_000 {
            let (a, b, margin) = random_round_pair(i, &mut random);
            let (mut fast, mut exact) = (Vec::new(), Vec::new());
            capsule_capsule(&a, &b, margin, &mut fast);
            reference(&a, &b, margin, &mut exact);
            assert_eq!(fast, exact, "pair {i}");
            touching += !exact.is_empty() as u32;
            let (da, db) = (2.0 * a.half_axis, 2.0 * b.half_axis);
            let c = da.cross(db);
            let across = (b.position - a.position).dot(c);
            let (ra, rb) = (a.segment().unwrap().2, b.segment().unwrap().2);
            let touch = 1.1 * (ra + rb + margin);
            let line_cut = c.length_squared() > 2e-6 * da.length_squared() * db.length_squared()
                && across * across > touch * touch * c.length_squared();
            ended_by_line += line_cut as u32;
        }
        assert!(touching > 40_000, "{touching} pairs touch");
        assert!(
            ended_by_line > 20_000,
            "{ended_by_line} pairs ended by the line bound"
        );
    }
}
