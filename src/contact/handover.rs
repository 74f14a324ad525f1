//! What last step's contact points hand on to this step's: a point found again (same body pair,
//! same feature id, [`super::manifold`]) takes its predecessor's friction anchors, if it stuck,
//! and its normal impulse.
//!
//! The solver leaves the points in colour order, so the predecessors of one pair lie anywhere
//! among 20 000 points of 130 bytes: looking them up through sorted `(pair, index)` keys cost
//! a binary search and a cache miss per pair that touches (a fifth of the settled rain's
//! detection). Instead the few fields a successor reads are copied once per step (one pass
//! over the points) and grouped by the pair's second body by a counting sort, so a pair's
//! predecessors are a scan of a handful of points away. Ties keep the points' order, as the
//! successor takes the first with its id.

use super::feature::FeatureId;
use super::ContactPoint;
use crate::math::Vec3;

/// One of last step's points, as its successor reads it.
///
/// Laid out in this order on purpose: glam reads a `Vec3` field into a 4-lane SSE register
/// with one 16-byte load, so the 4 bytes after it ride along in the unused lane and go through
/// the arithmetic. Left to the compiler, `sticking` followed `anchor_b`: a `true` there is the
/// float bits `0x0000_0001`, a subnormal, and every multiply of the carried anchors then took
/// the processor's slow path for subnormals. On the landing rain that was half the narrow
/// phase (its pairs' work 5.5 -> 2.2 ms of one core a step with `normal_impulse` there
/// instead, the same results to the bit). Each `Vec3` here is followed by a float.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct Handed {
    /// The pair's first body (the group is the second's).
    first: u32,
    /// The pair's second body, and its place in last step's points (the tie-break).
    second: u32,
    index: u32,
    /// The touching features, which the successor must match.
    pub id: FeatureId,
    /// Friction anchor in body a's space.
    pub anchor_a: Vec3,
    /// Friction anchor in body b's space.
    pub anchor_b: Vec3,
    /// Normal impulse accumulated in its last substep (kg m), for warm starting.
    pub normal_impulse: f32,
    /// It stuck to the end of the step (its anchors are carried).
    pub sticking: bool,
}

/// Last step's points by body pair, rebuilt every step into reused storage.
#[derive(Clone, Debug, Default)]
pub struct Handover {
    /// The points of the pairs whose second body is `b`: `handed[start[b]..start[b + 1]]`, in
    /// last step's order, or sorted by first body when longer than [`SCAN`].
    start: Vec<u32>,
    handed: Vec<Handed>,
    /// The points copied in last step's order, before grouping.
    copied: Vec<Handed>,
}

/// A group longer than this is sorted and searched by bisection; shorter ones are scanned.
const SCAN: usize = 16;

impl Handover {
    /// Takes last step's points, of the world's first `body_count` bodies (a point of a body
    /// beyond them, gone since, is dropped).
    pub fn take(&mut self, points: &[ContactPoint], body_count: usize) {
        // one pass over the 130-byte points copies what a successor reads and counts the
        // groups, at start[b + 2]; summed, start[b + 1] begins group b, and placing a point
        // moves it on, leaving it at the group's end, where group b + 1 begins
        self.start.clear();
        self.start.resize(body_count + 2, 0);
        self.copied.clear();
        let kept = |p: &&ContactPoint| p.body_a.index().max(p.body_b.index()) < body_count;
        for (index, p) in (0..).zip(points).filter(|(_, p)| kept(p)) {
            self.start[p.body_b.index() + 2] += 1;
            self.copied.push(Handed {
                first: p.body_a.0,
                second: p.body_b.0,
                index,
                id: p.id,
                sticking: p.sticking,
                normal_impulse: p.normal_impulse,
                anchor_a: p.anchor_a,
                anchor_b: p.anchor_b,
            });
        }
        for b in 2..self.start.len() {
            self.start[b] += self.start[b - 1];
        }
        self.handed.clear();
        self.handed.resize(self.copied.len(), Handed::default());
        for h in &self.copied {
            let at = &mut self.start[h.second as usize + 1];
            self.handed[*at as usize] = *h;
            *at += 1;
        }
        for b in 0..body_count {
            let group = &mut self.handed[self.start[b] as usize..self.start[b + 1] as usize];
            if group.len() > SCAN {
                group.sort_unstable_by_key(|h| (h.first, h.index));
            }
        }
    }

    /// Last step's points of the pair `(first, second)`, in last step's order.
    pub fn of_pair(&self, first: u32, second: u32) -> impl Iterator<Item = &Handed> + Clone {
        let b = second as usize;
        let group = match b + 1 < self.start.len() {
            true => &self.handed[self.start[b] as usize..self.start[b + 1] as usize],
            false => &[], // a body added since
        };
        let group = match group.len() <= SCAN {
            true => group,
            false => {
                let begin = group.partition_point(|h| h.first < first);
                let count = group[begin..].iter().take_while(|h| h.first == first);
                &group[begin..begin + count.count()]
            }
        };
        group.iter().filter(move |h| h.first == first)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::BodyId;

    fn point(a: u32, b: u32, id: FeatureId, impulse: f32) -> ContactPoint {
        ContactPoint {
            body_a: BodyId(a),
            body_b: BodyId(b),
            id,
            static_friction: 0.5,
            dynamic_friction: 0.5,
            normal_impulse: impulse,
            ..ContactPoint::UNSOLVED
        }
    }

    /// The lane after each anchor holds a float (an anchor or the impulse), never the
    /// `sticking` flag, whose `true` reads as a subnormal float ([`Handed`]).
    #[test]
    fn a_float_follows_each_anchor() {
        crate::math::assert_float_follows!(Handed:
            anchor_a => anchor_b,
            anchor_b => normal_impulse,
        );
    }

    /// Every pair finds exactly its own points, in their order, whatever order the solver left
    /// them in: against a search of all points, for small groups and for one past [`SCAN`]
    /// (body 45 the second body of 40 pairs, two points each).
    #[test]
    fn a_pair_finds_its_points_in_their_order() {
        let mut points = Vec::new();
        for i in (0..40u32).rev() {
            points.push(point(i, 45, 0, i as f32));
            points.push(point(i, 45, 1, i as f32 + 0.5));
        }
        // pairs (a, b) in a scrambled order, some with two points, one repeated id
        for k in 0..200u32 {
            let (a, b) = (1 + (k * 7) % 13, 20 + (k * 11) % 17);
            points.push(point(a, b, k % 3, k as f32));
        }
        points.reverse();
        let mut handover = Handover::default();
        handover.take(&points, 50);
        assert_eq!(handover.of_pair(3, 45).count(), 2);
        for a in 0..50 {
            for b in 0..52 {
                let expected: Vec<(FeatureId, f32)> = (points.iter())
                    .filter(|p| (p.body_a.0, p.body_b.0) == (a, b))
                    .map(|p| (p.id, p.normal_impulse))
                    .collect();
                let found: Vec<(FeatureId, f32)> = (handover.of_pair(a, b))
                    .map(|h| (h.id, h.normal_impulse))
                    .collect();
                assert_eq!(found, expected, "pair ({a}, {b})");
            }
        }
    }
}
