//! Narrow phase: closest features of a pair of shapes at the current poses, turned into contact
//! points. Spheres are capsules of zero length. Pairs: sphere/capsule with sphere/capsule, box
//! and half-space; box with half-space; box with box in [`super::box_box`]. Shapes are read
//! from the step's [`Collider`] records.

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
    let mut push = |pa: Vec3, pb: Vec3, id: FeatureId| {
        let delta = pb - pa;
        if delta.length_squared() > beyond {
            return;
        }
        let distance = delta.length();
        let normal = if distance > 1e-9 {
            delta / distance
        } else {
            (b.position - a.position).try_normalize().unwrap_or(Vec3::Y)
        };
        let separation = distance - ra - rb;
        if separation < margin {
            out.push(Feature {
                normal,
                point_a: pa + ra * normal,
                point_b: pb - rb * normal,
                separation,
                id,
            });
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
    if parallel {
        // the two ends of the overlap of b's segment projected on a's
        let axis = da.normalize();
        let project = |p: Vec3| (p - a0).dot(axis).clamp(0.0, da.length());
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

/// Box (a) against a sphere or capsule (b): the closest features (alternating projection
/// between the segment and the box, exact for these convex pairs) plus each cap centre on its
/// own, so a capsule lying on a face gets two points.
pub fn box_capsule(a: &Collider, half: Vec3, b: &Collider, margin: f32, out: &mut Vec<Feature>) {
    let Some((w0, w1, radius)) = b.segment() else {
        return;
    };
    let to_local = |p: Vec3| a.orientation.inverse() * (p - a.position);
    let (s0, s1) = (to_local(w0), to_local(w1));
    let mut p = closest_points_on_segments(s0, s1, Vec3::ZERO, Vec3::ZERO).0;
    for _ in 0..6 {
        let q = p.clamp(-half, half);
        p = closest_points_on_segments(s0, s1, q, q).0;
    }
    let first = out.len();
    for (id, candidate) in (0..).zip([p, s0, s1]) {
        let (surface, normal, distance) = point_box(candidate, half);
        let separation = distance - radius;
        let on_b = candidate - radius * normal;
        let duplicate = out[first..]
            .iter()
            .any(|f| (to_local(f.point_b) - on_b).length() < 0.01);
        if separation < margin && !duplicate {
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
