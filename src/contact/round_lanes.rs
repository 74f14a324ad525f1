//! Sphere and capsule pairs' shape tests W at a time: [`narrowphase::capsule_capsule`]'s
//! early outs and closest points, and [`narrowphase::capsule_gap`]'s bound, one pair per lane.
//!
//! In a settled pile most tested pairs are capsule pairs, and their scalar test was about a
//! fifth of detection: dependent divisions, and branches on the segments' configuration that
//! no predictor learns. Here every branch is computed and selected, with the scalar code's
//! operations in its order, so each lane gives the scalar result to the bit (the unit test
//! below checks it on random pairs): which pairs may touch, their closest points, and the gap
//! bound of those that cannot. Nearly parallel segments (the scalar code's two-point case)
//! are left to the scalar code, as is making the point.
//!
//! [`narrowphase::capsule_capsule`]: super::narrowphase::capsule_capsule
//! [`narrowphase::capsule_gap`]: super::narrowphase::capsule_gap

use super::collider::Collider;
use crate::lanes::{not, padded, Lane, LaneWidth, LaneWork, V3};
use crate::math::Vec3;
use crate::shape::Shape;
use crate::with_lane_type;

/// What the lanes found for one sphere or capsule pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RoundTest {
    /// The scalar code must test it (nearly parallel segments, or not a round pair).
    Scalar,
    /// No point: the shapes are out of reach.
    Apart {
        /// A lower bound on the shapes' distance (m).
        gap: f32,
    },
    /// The closest points of the two segments are within reach: the scalar code makes the
    /// point from them (`sphere_sphere`), or, if it makes none, takes `gap`.
    Close {
        /// Closest point on a's segment.
        on_a: Vec3,
        /// Closest point on b's segment.
        on_b: Vec3,
        /// A lower bound on the shapes' distance (m).
        gap: f32,
    },
}

/// What the lanes wrote for one pair ([`RoundResult::test`] reads it): a record the lanes
/// write without a branch (choosing [`RoundTest`]'s variant per lane, the branches on the
/// lanes' masks were mispredicted about every other pair, half of the lanes' time in the
/// landing rain).
#[derive(Clone, Copy, Debug, Default)]
pub struct RoundResult {
    /// [`SCALAR`], [`APART`] or [`CLOSE`].
    kind: u32,
    gap: f32,
    on_a: Vec3,
    on_b: Vec3,
}

/// [`RoundResult::kind`]s: [`RoundTest::Scalar`], [`RoundTest::Apart`], [`RoundTest::Close`].
const SCALAR: u32 = 0;
const APART: u32 = 1;
const CLOSE: u32 = 2;

impl RoundResult {
    /// What the lanes found.
    #[inline]
    pub fn test(&self) -> RoundTest {
        match self.kind {
            SCALAR => RoundTest::Scalar,
            APART => RoundTest::Apart { gap: self.gap },
            _ => RoundTest::Close {
                on_a: self.on_a,
                on_b: self.on_b,
                gap: self.gap,
            },
        }
    }
}

/// A pair to test: its two bodies and its reach (contact margin plus how far it may close).
#[derive(Clone, Copy, Debug)]
pub struct RoundPair {
    /// Body a.
    pub a: u32,
    /// Body b.
    pub b: u32,
    /// How far apart (m) the surfaces may be and still make a point.
    pub reach: f32,
}

/// The radius of a sphere or capsule.
#[inline]
pub fn round_radius(shape: &Shape) -> Option<f32> {
    match *shape {
        Shape::Sphere { radius } | Shape::Capsule { radius, .. } => Some(radius),
        _ => None,
    }
}

/// Tests `pairs` (both bodies spheres or capsules), `width` lanes at a time, appending one
/// result each to `out`.
pub fn test_pairs(
    width: LaneWidth,
    colliders: &[Collider],
    pairs: &[RoundPair],
    out: &mut Vec<RoundResult>,
) {
    struct Test<'a> {
        colliders: &'a [Collider],
        pairs: &'a [RoundPair],
        out: &'a mut Vec<RoundResult>,
    }
    impl<L: Lane> LaneWork<L> for Test<'_> {
        type Output = ();
        #[inline(always)]
        fn run(self) {
            for batch in self.pairs.chunks(L::W) {
                test_batch::<L>(self.colliders, batch, self.out);
            }
        }
    }
    let work = Test {
        colliders,
        pairs,
        out,
    };
    with_lane_type!(width, L => L::dispatch(work))
}

/// One batch of one to W pairs (lanes past the last repeat the first).
#[inline(always)]
fn test_batch<L: Lane>(colliders: &[Collider], batch: &[RoundPair], out: &mut Vec<RoundResult>) {
    let pair = |i: usize| *padded(batch, i);
    let body = |i: usize, first: bool| {
        let p = pair(i);
        &colliders[if first { p.a } else { p.b } as usize]
    };
    let radius = |c: &Collider| round_radius(&c.shape).unwrap_or(0.0);
    let centre_a = V3::<L>::from_fn(|i| body(i, true).position);
    let centre_b = V3::<L>::from_fn(|i| body(i, false).position);
    let axis_a = V3::<L>::from_fn(|i| body(i, true).half_axis);
    let axis_b = V3::<L>::from_fn(|i| body(i, false).half_axis);
    let ra = L::from_fn(|i| radius(body(i, true)));
    let rb = L::from_fn(|i| radius(body(i, false)));
    let bound_a = L::from_fn(|i| body(i, true).bounding_radius);
    let bound_b = L::from_fn(|i| body(i, false).bounding_radius);
    let margin = L::from_fn(|i| pair(i).reach);

    // capsule_capsule: the bounding spheres
    let centres = centre_b - centre_a;
    let sphere_reach = bound_a + bound_b + margin;
    let spheres_apart = centres.length_squared().gt(sphere_reach * sphere_reach);
    // the segments (Collider::segment), and the scalar code's tests on them
    let (a0, a1) = (centre_a - axis_a, centre_a + axis_a);
    let (b0, b1) = (centre_b - axis_b, centre_b + axis_b);
    let touch = ra + rb + margin;
    let beyond = touch * touch * L::splat(1.0 + 1e-3);
    let (da, db) = (a1 - a0, b1 - b0);
    let (la, lb) = (da.length_squared(), db.length_squared());
    let c = da.cross(db);
    let maybe_parallel = c.length_squared().le(L::splat(2e-6) * la * lb);
    let across = centres.dot(c);
    let bound = L::splat(1.01) * (ra + rb + margin) + L::splat(1e-3) * (bound_a + bound_b);
    let line_apart = not(maybe_parallel) & (across * across).gt(bound * bound * c.length_squared());
    let (on_a, on_b) = closest_points(a0, a1, b0, b1);
    let close = (on_b - on_a).length_squared().le(beyond);
    // capsule_gap
    let spheres = centres.length() - bound_a - bound_b;
    let segments = (on_b - on_a).length() - ra - rb;
    let gap = spheres.gt(L::splat(0.1)).select(spheres, segments);

    // apart if the spheres are; else the scalar code's if nearly parallel; else apart if
    // the lines or the closest points are
    let apart = spheres_apart | (not(maybe_parallel) & (line_apart | not(close)));
    let (scalar, close) = (L::splat(SCALAR as f32), L::splat(CLOSE as f32));
    let kind = apart.select(L::splat(APART as f32), maybe_parallel.select(scalar, close));
    out.extend((0..batch.len()).map(|i| RoundResult {
        kind: kind.at(i) as u32,
        gap: gap.at(i),
        on_a: on_a.lane(i),
        on_b: on_b.lane(i),
    }));
}

/// [`super::feature::closest_points_on_segments`] per lane, every branch computed and
/// selected.
#[inline(always)]
fn closest_points<L: Lane>(p0: V3<L>, p1: V3<L>, q0: V3<L>, q1: V3<L>) -> (V3<L>, V3<L>) {
    let (zero, one, eps) = (L::zero(), L::splat(1.0), L::splat(1e-12));
    #[inline(always)]
    fn clamp<L: Lane>(x: L) -> L {
        let (zero, one) = (L::zero(), L::splat(1.0));
        let x = x.lt(zero).select(zero, x);
        x.gt(one).select(one, x)
    }
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let (a_small, e_small) = (a.le(eps), e.le(eps));
    let c = d1.dot(r);
    let b = d1.dot(d2);
    let denom = a * e - b * b;
    // segments of length: s from the lines' closest points, then t, each clamped
    let s = denom.gt(eps).select(clamp((b * f - c * e) / denom), zero);
    let t = (b * s + f) / e;
    let s_at_q0 = clamp(-c / a);
    let s_at_q1 = clamp((b - c) / a);
    let (below, above) = (t.lt(zero), t.gt(one));
    let s = below.select(s_at_q0, above.select(s_at_q1, s));
    let t = below.select(zero, above.select(one, t));
    // a point for segment q: s against it; a point for segment p: t against it; two points
    let s = e_small.select(s_at_q0, s);
    let t = e_small.select(zero, t);
    let s = a_small.select(zero, s);
    let t = a_small.select(e_small.select(zero, clamp(f / e)), t);
    (p0 + d1.scale(s), q0 + d2.scale(t))
}

#[cfg(test)]
mod tests {
    use super::super::feature::Feature;
    use super::super::narrowphase::{
        capsule_capsule, capsule_gap, lcg, random_round_pair, sphere_sphere,
    };
    use super::*;

    /// The scalar narrow phase of a round pair: its features, and its gap bound if none.
    fn scalar(a: &Collider, b: &Collider, reach: f32) -> (Vec<Feature>, Option<u32>) {
        let mut features = Vec::new();
        capsule_capsule(a, b, reach, &mut features);
        let gap = features.is_empty().then(|| capsule_gap(a, b).to_bits());
        (features, gap)
    }

    /// What detection makes of a lane's result (`Scalar` lanes take the scalar path).
    fn from_lanes(
        a: &Collider,
        b: &Collider,
        reach: f32,
        test: RoundTest,
    ) -> (Vec<Feature>, Option<u32>) {
        match test {
            RoundTest::Scalar => scalar(a, b, reach),
            RoundTest::Apart { gap } => (Vec::new(), Some(gap.to_bits())),
            RoundTest::Close { on_a, on_b, gap } => {
                let radius = |c: &Collider| round_radius(&c.shape).unwrap();
                let feature = sphere_sphere(a, b, (on_a, radius(a)), (on_b, radius(b)), reach, 0);
                let gap = feature.is_none().then_some(gap.to_bits());
                (feature.into_iter().collect(), gap)
            }
        }
    }

    /// The lanes give the scalar narrow phase's features and gap bounds to the bit, on the
    /// narrow phase's random pairs ([`random_round_pair`]: any angle, nearly parallel and
    /// parallel, distances around touching), in batches of every length up to W, at every
    /// width this CPU runs.
    #[test]
    fn the_lanes_give_the_scalar_points_and_gaps_to_the_bit() {
        for width in LaneWidth::available() {
            lanes_match_the_scalar_test(width);
        }
    }

    fn lanes_match_the_scalar_test(width: LaneWidth) {
        let mut random = lcg(99);
        let mut colliders = Vec::new();
        let mut pairs = Vec::new();
        for i in 0..100_000u32 {
            let (a, b, reach) = random_round_pair(i, &mut random);
            colliders.extend([a, b]);
            pairs.push(RoundPair {
                a: 2 * i,
                b: 2 * i + 1,
                reach,
            });
        }
        let mut tests = Vec::new();
        let mut start = 0;
        for length in (1..=width.lanes()).cycle() {
            if start >= pairs.len() {
                break;
            }
            let end = (start + length).min(pairs.len());
            test_pairs(width, &colliders, &pairs[start..end], &mut tests);
            start = end;
        }
        assert_eq!(tests.len(), pairs.len());
        let mut counts = [0; 4];
        for (i, (pair, result)) in pairs.iter().zip(&tests).enumerate() {
            let test = result.test();
            let (a, b) = (&colliders[pair.a as usize], &colliders[pair.b as usize]);
            let lanes = from_lanes(a, b, pair.reach, test);
            assert_eq!(lanes, scalar(a, b, pair.reach), "pair {i}: {test:?}");
            counts[match test {
                RoundTest::Scalar => 0,
                RoundTest::Apart { .. } => 1,
                RoundTest::Close { .. } if lanes.0.is_empty() => 2,
                RoundTest::Close { .. } => 3,
            }] += 1;
        }
        // every outcome is exercised: scalar, apart, close with a point, and close without
        // one (the 0.1% band the scalar code's squared-distance test lets through)
        let [scalar, apart, close_none, close_point] = counts;
        assert!(
            scalar > 1000 && apart > 1000 && close_point > 1000,
            "{counts:?}"
        );
        assert!(close_none > 0, "{counts:?}");
    }
}
