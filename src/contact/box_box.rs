//! Box against box: separating-axis test over the 15 candidate axes (three face normals of each
//! box and the nine cross products of their edges; Gottschalk et al. 1996), then
//!
//! - **face contact** when a face normal separates least: the face of the other box most
//!   opposed to it (the incident face) is clipped against the side planes of the reference face
//!   (Sutherland-Hodgman), and every clipped vertex within reach below the reference face
//!   becomes a point, up to eight. Each point has its own depth, so a tilted box gets a
//!   restoring torque;
//! - **edge contact** when an edge-edge axis separates clearly less than every face axis: one
//!   point, at the closest points of the two supporting edges.
//!
//! Face axes are preferred within a small tolerance, and a's faces over b's, so the choice does
//! not flicker between nearly equal axes from one frame to the next.
//!
//! Feature ids ([`FeatureId`]): a face point names the reference face, the incident face and the
//! two features whose meeting made the clipped vertex (an incident corner is where two incident
//! edges meet; a crossing is an incident edge cut by a side plane of the reference face; a
//! reference corner is where two side planes meet), as Box2D v3's clip ids do. An edge point
//! names the two edge directions and which of the four parallel edges of each box supports it.

use super::collider::Collider;
use super::feature::{closest_points_on_segments, Feature, FeatureId};
use crate::math::Vec3;

/// An edge axis must separate by this much more (m) than the best face axis to be used.
const EDGE_TOLERANCE: f32 = 0.005;
/// b's face must separate by this much more (m) than a's to be the reference.
const FACE_TOLERANCE: f32 = 0.001;

/// High bits of a face point's and an edge point's id.
const FACE_ID: FeatureId = 1 << 24;
const EDGE_ID: FeatureId = 2 << 24;

/// A box in world space: centre, unit axes and half extents.
struct Oriented {
    centre: Vec3,
    axes: [Vec3; 3],
    half: Vec3,
}

impl Oriented {
    fn new(body: &Collider, half: Vec3) -> Self {
        let q = body.orientation;
        Oriented {
            centre: body.position,
            axes: [q * Vec3::X, q * Vec3::Y, q * Vec3::Z],
            half,
        }
    }

    /// Half the box's extent along unit `u`.
    fn radius(&self, u: Vec3) -> f32 {
        (0..3)
            .map(|k| self.half[k] * self.axes[k].dot(u).abs())
            .sum()
    }

    /// The four corners of the face whose outward normal is `sign * axes[k]`.
    fn face(&self, k: usize, sign: f32) -> [Vec3; 4] {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let centre = self.centre + sign * self.half[k] * self.axes[k];
        let (u, v) = (self.half[i] * self.axes[i], self.half[j] * self.axes[j]);
        [
            centre + u + v,
            centre - u + v,
            centre - u - v,
            centre + u - v,
        ]
    }

    /// The edge parallel to `axes[k]` that lies furthest along `u`, and which of the four it
    /// is (two bits: the side taken along each other axis).
    fn support_edge(&self, k: usize, u: Vec3) -> (Vec3, Vec3, FeatureId) {
        let mut centre = self.centre;
        let mut which = 0;
        for (bit, m) in (0..3).filter(|&m| m != k).enumerate() {
            let side = self.axes[m].dot(u).signum();
            centre += self.half[m] * side * self.axes[m];
            which |= FeatureId::from(side > 0.0) << bit;
        }
        let along = self.half[k] * self.axes[k];
        (centre - along, centre + along, which)
    }
}

enum Axis {
    /// Face `k` of box a (`false`) or b (`true`); the normal points from a to b.
    Face {
        of_b: bool,
        k: usize,
    },
    Edge {
        i: usize,
        j: usize,
    },
}

/// Contacts between boxes a and b within `margin`; normals point from a to b.
pub fn box_box(
    a: &Collider,
    half_a: Vec3,
    b: &Collider,
    half_b: Vec3,
    margin: f32,
    out: &mut Vec<Feature>,
) {
    let (ba, bb) = (Oriented::new(a, half_a), Oriented::new(b, half_b));
    let offset = bb.centre - ba.centre;
    let separation_along = |u: Vec3| offset.dot(u).abs() - ba.radius(u) - bb.radius(u);

    let mut face: Option<(f32, Axis)> = None;
    for (of_b, axes) in [(false, &ba.axes), (true, &bb.axes)] {
        let tolerance = if of_b { FACE_TOLERANCE } else { 0.0 };
        for (k, &u) in axes.iter().enumerate() {
            let s = separation_along(u);
            if s > margin {
                return;
            }
            if face.as_ref().is_none_or(|(best, _)| s > best + tolerance) {
                face = Some((s, Axis::Face { of_b, k }));
            }
        }
    }
    let Some((face_separation, mut axis)) = face else {
        return;
    };
    let mut edge_best = face_separation + EDGE_TOLERANCE;
    for i in 0..3 {
        for j in 0..3 {
            let u = ba.axes[i].cross(bb.axes[j]);
            let length = u.length();
            if length < 1e-4 {
                continue; // parallel edges: a face axis covers them
            }
            let s = separation_along(u / length);
            if s > margin {
                return;
            }
            if s > edge_best {
                edge_best = s;
                axis = Axis::Edge { i, j };
            }
        }
    }
    match axis {
        Axis::Face { of_b: false, k } => {
            let n = ba.axes[k] * offset.dot(ba.axes[k]).signum();
            clip_face(&ba, k, n, &bb, margin, false, out);
        }
        Axis::Face { of_b: true, k } => {
            let n = bb.axes[k] * -offset.dot(bb.axes[k]).signum();
            clip_face(&bb, k, n, &ba, margin, true, out);
        }
        Axis::Edge { i, j } => {
            let mut n = ba.axes[i].cross(bb.axes[j]).normalize();
            if offset.dot(n) < 0.0 {
                n = -n;
            }
            let (a0, a1, edge_a) = ba.support_edge(i, n);
            let (b0, b1, edge_b) = bb.support_edge(j, -n);
            let (pa, pb) = closest_points_on_segments(a0, a1, b0, b1);
            let separation = (pb - pa).dot(n);
            if separation < margin {
                out.push(Feature {
                    normal: n,
                    point_a: pa,
                    point_b: pb,
                    separation,
                    id: EDGE_ID | ((3 * i + j) as FeatureId) << 4 | edge_a << 2 | edge_b,
                });
            }
        }
    }
}

/// Clips the incident box's face against the reference face `k` of `reference` whose outward
/// normal is `n`, and pushes the clipped points within reach. `flipped` when the reference is
/// body b, so the features still read from a to b.
fn clip_face(
    reference: &Oriented,
    k: usize,
    n: Vec3,
    incident: &Oriented,
    margin: f32,
    flipped: bool,
    out: &mut Vec<Feature>,
) {
    let face_centre = reference.centre + reference.half[k] * n;
    // incident face: the one whose outward normal is most opposed to n
    let m = (0..3)
        .max_by(|&x, &y| {
            let dx = incident.axes[x].dot(n).abs();
            dx.total_cmp(&incident.axes[y].dot(n).abs())
        })
        .unwrap_or(0);
    let sign = -incident.axes[m].dot(n).signum();
    let mut polygon = Polygon::from(incident.face(m, sign));
    for (plane, side) in [(k + 1) % 3, (k + 2) % 3].into_iter().enumerate() {
        let (u, e) = (reference.axes[side], reference.half[side]);
        let along = face_centre.dot(u);
        polygon.clip(u, along + e, 4 + 2 * plane as u8);
        polygon.clip(-u, -along + e, 5 + 2 * plane as u8);
    }
    // the faces as 0..6: axis index and side
    let face_code = |axis: usize, outward: Vec3, of: &Oriented| {
        (2 * axis) as FeatureId + FeatureId::from(of.axes[axis].dot(outward) > 0.0)
    };
    let faces = FACE_ID
        | FeatureId::from(flipped) << 20
        | face_code(k, n, reference) << 16
        | face_code(m, -n, incident) << 12;
    for (&p, &vertex) in polygon.points().iter().zip(polygon.ids()) {
        let depth = (p - face_centre).dot(n);
        if depth < margin {
            let on_face = p - depth * n;
            let id = faces | FeatureId::from(vertex);
            out.push(if flipped {
                Feature {
                    normal: -n,
                    point_a: p,
                    point_b: on_face,
                    separation: depth,
                    id,
                }
            } else {
                Feature {
                    normal: n,
                    point_a: on_face,
                    point_b: p,
                    separation: depth,
                    id,
                }
            });
        }
    }
}

/// A convex polygon of at most eight vertices, on the stack, each vertex named by the two
/// features that meet there: `incoming << 3 | outgoing`, where 0..4 are the incident face's
/// edges (edge i runs from corner i to corner i + 1) and 4..8 the reference face's side planes.
struct Polygon {
    vertices: [Vec3; 8],
    ids: [u8; 8],
    len: usize,
}

impl Polygon {
    fn from(quad: [Vec3; 4]) -> Self {
        let mut vertices = [Vec3::ZERO; 8];
        vertices[..4].copy_from_slice(&quad);
        let mut ids = [0; 8];
        for (i, id) in ids.iter_mut().take(4).enumerate() {
            *id = ((i as u8 + 3) % 4) << 3 | i as u8;
        }
        Polygon {
            vertices,
            ids,
            len: 4,
        }
    }

    fn points(&self) -> &[Vec3] {
        &self.vertices[..self.len]
    }

    fn ids(&self) -> &[u8] {
        &self.ids[..self.len]
    }

    /// Keeps the part where `p . u <= limit` (Sutherland-Hodgman against side plane `plane`).
    fn clip(&mut self, u: Vec3, limit: f32, plane: u8) {
        let mut kept = [Vec3::ZERO; 8];
        let mut kept_ids = [0; 8];
        let mut len = 0;
        for index in 0..self.len {
            let p = self.vertices[index];
            let q = self.vertices[(index + 1) % self.len];
            let (dp, dq) = (p.dot(u) - limit, q.dot(u) - limit);
            // the feature along which the polygon runs from p to q
            let edge = self.ids[index] & 7;
            // vertices within EPS of the plane are on it: kept, and no crossing made there
            const EPS: f32 = 1e-6;
            if dp <= EPS && len < 8 {
                kept[len] = p;
                kept_ids[len] = self.ids[index];
                len += 1;
            }
            let crosses = (dp < -EPS && dq > EPS) || (dp > EPS && dq < -EPS);
            if crosses && len < 8 {
                kept[len] = p + (q - p) * (dp / (dp - dq));
                // leaving the kept side: along the edge, then the plane; entering: the reverse
                kept_ids[len] = if dp < 0.0 {
                    edge << 3 | plane
                } else {
                    plane << 3 | edge
                };
                len += 1;
            }
        }
        self.vertices = kept;
        self.ids = kept_ids;
        self.len = len;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{Body, BodyKind};
    use crate::math::Quat;
    use crate::shape::Shape;

    fn cuboid(half: Vec3, position: Vec3, orientation: Quat) -> Collider {
        let shape = Shape::Cuboid { half_extents: half };
        let body = Body::new("box", BodyKind::Dynamic, shape, 1.0);
        Collider::new(&body.with_pose(position, orientation))
    }

    #[test]
    fn a_box_resting_on_a_box_gets_its_four_bottom_corners() {
        let half = Vec3::new(0.2, 0.1, 0.15);
        let lower = cuboid(half, Vec3::ZERO, Quat::IDENTITY);
        let upper = cuboid(half, Vec3::new(0.0, 0.199, 0.0), Quat::IDENTITY);
        let mut out = Vec::new();
        box_box(&lower, half, &upper, half, 0.02, &mut out);
        assert_eq!(out.len(), 4, "{out:?}");
        for f in &out {
            assert!((f.normal - Vec3::Y).length() < 1e-6);
            assert!((f.separation + 0.001).abs() < 1e-5, "{}", f.separation);
            assert!(
                (f.point_b.x.abs() - 0.2).abs() < 1e-5 && (f.point_b.z.abs() - 0.15).abs() < 1e-5
            );
        }
    }

    /// The ids of a pair's points, sorted, and checked unique.
    fn ids(a: &Collider, b: &Collider, half: Vec3) -> Vec<FeatureId> {
        let mut out = Vec::new();
        box_box(a, half, b, half, 0.02, &mut out);
        let mut ids: Vec<FeatureId> = out.iter().map(|f| f.id).collect();
        ids.sort_unstable();
        let before = ids.len();
        ids.dedup();
        assert_eq!(ids.len(), before, "ids repeat: {out:?}");
        ids
    }

    #[test]
    fn feature_ids_are_unique_and_survive_small_motion() {
        let half = Vec3::new(0.2, 0.1, 0.15);
        let lower = cuboid(half, Vec3::ZERO, Quat::IDENTITY);
        // turned by 30 degrees on the lower box: the incident face is clipped by all four
        // side planes, so the points are incident corners, crossings and reference corners
        let turn = Quat::from_rotation_y(0.5);
        let upper = cuboid(half, Vec3::new(0.0, 0.199, 0.0), turn);
        let first = ids(&lower, &upper, half);
        assert!(
            first.len() > 4,
            "clipped polygon has {} points",
            first.len()
        );
        // a millimetre across and a small tilt later: the same features touch
        let moved = cuboid(
            half,
            Vec3::new(0.001, 0.1985, -0.001),
            Quat::from_rotation_x(0.002) * turn,
        );
        assert_eq!(ids(&lower, &moved, half), first);
        // slid half off the lower box: some of those features no longer touch
        let slid = cuboid(half, Vec3::new(0.3, 0.199, 0.0), turn);
        assert_ne!(ids(&lower, &slid, half), first);
    }

    #[test]
    fn a_tilted_box_gets_deeper_points_on_the_side_it_leans_to() {
        let half = Vec3::new(0.2, 0.1, 0.15);
        let lower = cuboid(half, Vec3::ZERO, Quat::IDENTITY);
        // tilted by 0.01 rad about z: its -x bottom edge rises, its +x edge sinks
        let tilt = Quat::from_rotation_z(0.01);
        let upper = cuboid(half, Vec3::new(0.0, 0.2, 0.0), tilt);
        for (first, second) in [(&lower, &upper), (&upper, &lower)] {
            let mut out = Vec::new();
            box_box(first, half, second, half, 0.02, &mut out);
            assert_eq!(out.len(), 4, "{out:?}");
            for f in &out {
                let x = if std::ptr::eq(first, &lower) {
                    f.point_b.x
                } else {
                    f.point_a.x
                };
                // the gap at a point x along the tilted face is x tan(tilt), to within 1e-5 m:
                // -2 mm at x = -0.2 and +2 mm at x = +0.2
                let expected = x * 0.01f32.tan();
                assert!(
                    (f.separation - expected).abs() < 2e-4,
                    "x {x}: separation {} expected {expected}",
                    f.separation
                );
            }
        }
    }

    #[test]
    fn crossed_edges_meet_in_one_point() {
        // two unit cubes turned 45 degrees about perpendicular axes, edge above edge
        let half = Vec3::splat(0.5);
        let reach = 0.5 * 2f32.sqrt();
        let lower = cuboid(
            half,
            Vec3::ZERO,
            Quat::from_rotation_x(std::f32::consts::FRAC_PI_4),
        );
        let upper = cuboid(
            half,
            Vec3::new(0.0, 2.0 * reach - 0.01, 0.0),
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_4),
        );
        let mut out = Vec::new();
        box_box(&lower, half, &upper, half, 0.02, &mut out);
        assert_eq!(out.len(), 1, "{out:?}");
        let f = out[0];
        assert!((f.normal - Vec3::Y).length() < 1e-4, "{:?}", f.normal);
        assert!((f.separation + 0.01).abs() < 1e-4, "{}", f.separation);
        assert!(
            (f.point_a - Vec3::new(0.0, reach, 0.0)).length() < 1e-4,
            "{:?}",
            f.point_a
        );
    }

    #[test]
    fn separated_boxes_give_nothing() {
        let half = Vec3::splat(0.5);
        let a = cuboid(half, Vec3::ZERO, Quat::IDENTITY);
        let b = cuboid(half, Vec3::new(1.2, 0.3, 0.0), Quat::from_rotation_y(0.3));
        let mut out = Vec::new();
        box_box(&a, half, &b, half, 0.02, &mut out);
        assert!(out.is_empty(), "{out:?}");
    }
}
