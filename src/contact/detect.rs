//! Contact detection, once per frame (step 1 of the solver): bodies to [`Collider`] records,
//! the broad phase's candidate pairs, the filters (joined bodies, group and mask bits), then the
//! narrow phase of each pair and its new points, which inherit from last step's
//! ([`Handover`]).
//!
//! The narrow phase runs the pairs in chunks on several threads, each chunk into its own reused
//! buffer, concatenated in pair order, so the points come out the same for any thread count.

use super::broadphase::BroadPhase;
use super::collider::{self, Collider};
use super::feature::Feature;
use super::handover::Handover;
use super::{manifold, narrowphase, ContactPoint, PARALLEL_PAIRS};
use crate::body::{Body, BodyId};
use crate::constraint::Constraint;

/// What detection keeps from step to step (reused storage, and the broad phase's pairs).
#[derive(Clone, Debug, Default)]
pub struct Detection {
    /// What detection reads of each body this step.
    colliders: Vec<Collider>,
    handover: Handover,
    broad_phase: BroadPhase,
    pairs: Vec<(u32, u32)>,
    chunks: Vec<ChunkOut>,
    /// Bodies that never collide with body `i` (joined to it): `excluded[excluded_start[i]..
    /// excluded_start[i + 1]]`, a handful per body; and the constraint count they were built for.
    excluded: Vec<u32>,
    excluded_start: Vec<u32>,
    excluded_for: usize,
}

impl Detection {
    /// Replaces last step's `points` with those at the current poses.
    pub fn detect(
        &mut self,
        points: &mut Vec<ContactPoint>,
        bodies: &[Body],
        constraints: &[Constraint],
        dt: f32,
        margin: f32,
    ) {
        if self.excluded_for != constraints.len() || self.excluded_start.len() != bodies.len() + 1 {
            self.build_exclusions(bodies.len(), constraints);
        }
        self.handover.take(points, bodies.len());
        points.clear();
        collider::build(bodies, &mut self.colliders);
        self.pairs.clear();
        let pairs = &mut self.pairs;
        self.broad_phase
            .find_pairs(&self.colliders, dt, margin, |a, b| pairs.push((a, b)));
        let chunks = if rayon::current_num_threads() > 1 && self.pairs.len() >= PARALLEL_PAIRS {
            4 * rayon::current_num_threads()
        } else {
            1
        };
        let chunk_len = self.pairs.len().div_ceil(chunks).max(1);
        if self.chunks.len() < chunks {
            self.chunks.resize_with(chunks, Default::default);
        }
        let found = PairContext {
            colliders: &self.colliders,
            handover: &self.handover,
            excluded: &self.excluded,
            excluded_start: &self.excluded_start,
            dt,
            margin,
        };
        if chunks > 1 {
            use rayon::prelude::*;
            self.pairs
                .par_chunks(chunk_len)
                .zip(self.chunks.par_iter_mut())
                .for_each(|(pairs, out)| found.collide_all(pairs, out));
        } else {
            found.collide_all(&self.pairs, &mut self.chunks[0]);
        }
        let used = self.pairs.len().div_ceil(chunk_len).max(1);
        for out in &self.chunks[..used] {
            points.extend_from_slice(&out.points);
        }
    }

    /// Rebuilds the per-body lists of joined bodies (each pair under its lower body index).
    fn build_exclusions(&mut self, body_count: usize, constraints: &[Constraint]) {
        let joined = || {
            constraints.iter().filter_map(|c| {
                let connected = matches!(c, Constraint::BallSocket(j) if j.collide_connected);
                let (a, b) = c.bodies();
                (!connected).then_some((a.0.min(b.0), a.0.max(b.0)))
            })
        };
        self.excluded_start.clear();
        self.excluded_start.resize(body_count + 1, 0);
        for (low, _) in joined() {
            self.excluded_start[low as usize + 1] += 1;
        }
        for i in 0..body_count {
            self.excluded_start[i + 1] += self.excluded_start[i];
        }
        self.excluded.clear();
        self.excluded
            .resize(self.excluded_start[body_count] as usize, 0);
        let mut filled = self.excluded_start.clone();
        for (low, high) in joined() {
            self.excluded[filled[low as usize] as usize] = high;
            filled[low as usize] += 1;
        }
        self.excluded_for = constraints.len();
    }
}

/// One chunk's output of the narrow phase, reused from frame to frame.
#[derive(Clone, Debug, Default)]
struct ChunkOut {
    points: Vec<ContactPoint>,
    features: Vec<Feature>,
}

/// What the narrow phase of one pair reads.
struct PairContext<'a> {
    colliders: &'a [Collider],
    handover: &'a Handover,
    excluded: &'a [u32],
    excluded_start: &'a [u32],
    dt: f32,
    margin: f32,
}

impl PairContext<'_> {
    /// The contact points of `pairs` (filtered, then the narrow phase) into `out`.
    fn collide_all(&self, pairs: &[(u32, u32)], out: &mut ChunkOut) {
        out.points.clear();
        for &(a, b) in pairs {
            let (first, last) = (a.min(b) as usize, a.max(b));
            let range =
                self.excluded_start[first] as usize..self.excluded_start[first + 1] as usize;
            if self.excluded[range].contains(&last) {
                continue;
            }
            let (ca, cb) = (&self.colliders[a as usize], &self.colliders[b as usize]);
            if ca.collision_group & cb.collision_mask == 0
                || cb.collision_group & ca.collision_mask == 0
            {
                continue;
            }
            // how far the two surfaces may close this frame: the relative speed of the centres
            // plus what spin adds at the farthest surface point (a limb spinning at 20 rad/s
            // moves its tip 5 cm a frame further than its centre)
            let closing =
                (ca.linear_velocity - cb.linear_velocity).length() + ca.spin_bound + cb.spin_bound;
            let reach = self.margin + self.dt * closing;
            out.features.clear();
            if !narrowphase::collide(ca, cb, reach, &mut out.features) {
                continue;
            }
            let static_friction = (ca.static_friction * cb.static_friction).sqrt();
            let dynamic_friction = (ca.dynamic_friction * cb.dynamic_friction).sqrt();
            let restitution = ca.restitution.max(cb.restitution);
            let previous = self.handover.of_pair(a, b);
            manifold::reduce(&mut out.features, 0);
            for f in &out.features {
                let local_a = ca.orientation.inverse() * (f.point_a - ca.position);
                let local_b = cb.orientation.inverse() * (f.point_b - cb.position);
                let same = previous.iter().find(|p| p.id == f.id);
                let warm_impulse = same.map_or(0.0, |p| p.normal_impulse);
                let kept = same.filter(|p| p.sticking);
                let (anchor_a, anchor_b) = kept.map_or((local_a, local_b), |p| {
                    let anchors = (p.anchor_a, p.anchor_b);
                    manifold::carried_anchors(anchors, ca, cb, f.normal, (local_a, local_b))
                });
                out.points.push(ContactPoint {
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
                    sticking: true,
                    static_friction,
                    dynamic_friction,
                    restitution,
                    approach_speed: (cb.point_velocity(f.point_b) - ca.point_velocity(f.point_a))
                        .dot(f.normal),
                    allowed_penetration: 0.0,
                    compliance: 0.0,
                    damping: 0.0,
                    start_separation: 0.0,
                    normal_impulse: warm_impulse,
                    warm_impulse: 0.0,
                    friction_impulse: 0.0,
                });
            }
        }
    }
}
