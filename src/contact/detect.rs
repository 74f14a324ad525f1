//! Contact detection, once per frame (step 1 of the solver): bodies to [`Collider`] records,
//! the broad phase's candidate pairs (never two joined bodies: [`Joined`]), the group and mask
//! filter, then the narrow phase of each pair and its new points, which inherit from last
//! step's ([`Handover`]).
//!
//! The narrow phase runs the pairs in chunks on several threads, each chunk into its own reused
//! buffer, concatenated in pair order, so the points come out the same for any thread count.
//! A chunk lists the pairs it must test, runs the shape tests of its sphere and capsule pairs
//! W at a time ([`round_lanes`], the scalar results to the bit), then makes every pair's
//! points in pair order.

use super::broadphase::gaps::{self, Motion};
use super::broadphase::{BroadPhase, Joined, UpdateTiming};
use super::collider::{self, Collider, PARALLEL_BODIES};
use super::feature::Feature;
use super::handover::Handover;
use super::round_lanes::{self, round_radius, RoundPair, RoundResult, RoundTest};
use super::{manifold, narrowphase, ContactPoint, PARALLEL_PAIRS};
use crate::body::{Body, BodyId};
use crate::constraint::Constraints;
use std::time::Instant;

/// How many kept pairs' work one of the others (a large box's or a half-space's pair: all
/// tested, most of them touching) is, to balance the narrow phase's chunks. With chunks of
/// equal pair counts the settled rain's last chunk, which holds the others, took 0.72 ms
/// against 0.40 for each of the rest, and one thread waited on it.
const OTHER_WORK: usize = 3;

/// What detection keeps from step to step (reused storage, and the broad phase's pairs).
#[derive(Clone, Debug, Default)]
pub struct Detection {
    /// What detection reads of each body this step, and read last step.
    colliders: Vec<Collider>,
    previous: Vec<Collider>,
    /// How each body moved since last step ([`gaps`]).
    motions: Vec<Motion>,
    handover: Handover,
    broad_phase: BroadPhase,
    /// The candidate pairs after the broad phase's kept ones ([`BroadPhase::report_others`]).
    others: Vec<(u32, u32)>,
    chunks: Vec<ChunkOut>,
    /// Where each chunk's candidates start, and where the last ends.
    starts: Vec<usize>,
    /// The constraints ([`Constraints::stamp`]) and body count the broad phase's [`Joined`]
    /// pairs were built for.
    joined_for: Option<(u64, usize)>,
    profile: DetectionProfile,
}

/// Where the last detection's wall time went, piece by piece (as Box2D's `b2Profile` splits
/// its broad phase from its narrow phase), and what it did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DetectionProfile {
    /// The bodies' records (s).
    pub records: f64,
    /// The broad phase's update (s): the tight and fat boxes, the kept pairs brought up to date
    /// or rebuilt, and the large boxes' and half-spaces' pairs listed; beside `handover` on
    /// several threads, after it on one.
    pub broad_phase: f64,
    /// Of `broad_phase`: the boxes, and the kept pairs ([`UpdateTiming`]).
    pub broad_phase_parts: UpdateTiming,
    /// Last step's points handed over and the bodies' motions measured (s).
    pub handover: f64,
    /// The narrow phase (s), on all threads: the kept pairs' report, the shape tests and the
    /// points.
    pub narrow_phase: f64,
    /// The narrow phase's work by part, summed over its threads.
    pub narrow_phase_work: NarrowPhaseWork,
    /// The chunks' points copied into one list (s).
    pub concatenate: f64,
    /// Whether the broad phase rebuilt its kept pairs (a crowd in motion), rather than
    /// updating the few bodies that moved.
    pub rebuilt: bool,
    /// Pairs the narrow phase tested (the skipped ones not counted).
    pub pairs_tested: usize,
    /// Pairs the gap bounds skipped as proven out of reach ([`gaps`]).
    pub pairs_skipped: usize,
}

/// The narrow phase's work by part (s), summed over the threads that ran its chunks: where a
/// pair's cost goes, whatever the thread count.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NarrowPhaseWork {
    /// The kept pairs' report: their tight boxes and gap bounds.
    pub report: f64,
    /// The sphere and capsule pairs listed and tested in lanes.
    pub shape_tests: f64,
    /// Every tested pair's points made (and the other pairs' shape tests).
    pub points: f64,
}

impl NarrowPhaseWork {
    fn add(self, other: NarrowPhaseWork) -> NarrowPhaseWork {
        NarrowPhaseWork {
            report: self.report + other.report,
            shape_tests: self.shape_tests + other.shape_tests,
            points: self.points + other.points,
        }
    }
}

impl Detection {
    /// Replaces last step's `points` with those at the current poses.
    pub fn detect(
        &mut self,
        points: &mut Vec<ContactPoint>,
        bodies: &[Body],
        constraints: &Constraints,
        dt: f32,
        margin: f32,
    ) {
        let joined_for = Some((constraints.stamp(), bodies.len()));
        if self.joined_for != joined_for {
            self.broad_phase
                .set_joined(joined(bodies.len(), constraints));
            self.joined_for = joined_for;
        }
        // this step's records on all threads; then the broad phase on this thread, and last
        // step's points handed over and the bodies' motions measured (only the narrow phase
        // reads them) on the other. (With the records and the motions in the broad phase's
        // stretch, the settled rain's stretch took 0.96 ms against the handover's 0.47, the
        // other thread idle for the rest: in-step detection 2.96-3.07 -> 2.72-2.75 ms.)
        let records = Instant::now();
        std::mem::swap(&mut self.colliders, &mut self.previous);
        collider::build(bodies, &mut self.colliders);
        let records = records.elapsed().as_secs_f64();
        let (colliders, previous) = (&self.colliders, &self.previous);
        let (handover, motions) = (&mut self.handover, &mut self.motions);
        let (broad_phase, others) = (&mut self.broad_phase, &mut self.others);
        let mut broad = move || {
            // the kept pairs are reported chunk by chunk inside the narrow phase's parallel
            // loop; the few others (large boxes', half-spaces') are listed now, to come last
            let start = Instant::now();
            let rebuilds = broad_phase.rebuilds;
            others.clear();
            let moving = broad_phase.update(colliders, dt, margin);
            if moving {
                broad_phase.report_others(colliders, |a, b| others.push((a, b)));
            }
            let kept = if moving { broad_phase.kept_len() } else { 0 };
            let rebuilt = broad_phase.rebuilds != rebuilds;
            (kept, rebuilt, start.elapsed().as_secs_f64())
        };
        let last_points: &[ContactPoint] = points;
        let mut beside = move || {
            let start = Instant::now();
            handover.take(last_points, bodies.len());
            measure_motions(previous, colliders, motions);
            start.elapsed().as_secs_f64()
        };
        // (the handover waits for the other thread, which first finishes the joints' rows the
        // solver prepares beside detection)
        let ((kept, rebuilt, broad_seconds), handover_seconds) =
            if rayon::current_num_threads() > 1 && bodies.len() >= PARALLEL_BODIES {
                rayon::join(broad, beside)
            } else {
                let handover = beside();
                (broad(), handover)
            };
        points.clear();
        let total = kept + self.others.len();
        // (eight a thread: halves of halves balance the threads better than four; with the
        // weights below, the settled rain's in-step detection went 2.93, 2.81 -> 2.64, 2.48 ms)
        let chunks = if rayon::current_num_threads() > 1 && total >= PARALLEL_PAIRS {
            8 * rayon::current_num_threads()
        } else {
            1
        };
        if self.chunks.len() < chunks {
            self.chunks.resize_with(chunks, Default::default);
        }
        chunk_starts(kept, self.others.len(), chunks, &mut self.starts);
        let found = PairContext {
            colliders: &self.colliders,
            handover: &self.handover,
            dt,
            margin,
        };
        // the kept pairs' gap bounds, each chunk given its kept pairs'
        let mut bounds = self.broad_phase.take_gaps();
        let (broad_phase, others) = (&self.broad_phase, &self.others);
        let (motions, starts) = (&self.motions, &self.starts);
        // chunk c: candidates starts[c]..starts[c + 1] of the kept pairs followed by the others
        let run = |c: usize, out: &mut ChunkOut, bounds: &mut [f32]| {
            let start = Instant::now();
            let range = starts[c]..starts[c + 1];
            let kept_range = range.start.min(kept)..range.end.min(kept);
            // the pairs to test: the kept ones the gap bounds do not skip (with their bound's
            // place), then the others
            let tested = &mut out.tested;
            tested.clear();
            out.skipped =
                broad_phase.report_kept_bounded(kept_range, bounds, motions, (margin, dt), tested);
            for &(a, b) in &others[range.start.max(kept) - kept..range.end.max(kept) - kept] {
                if !broad_phase.joined(a, b) {
                    tested.push((a, b, u32::MAX));
                }
            }
            let reported = Instant::now();
            // their sphere and capsule pairs' shape tests in lanes, then every pair's points
            // in order
            out.round_pairs.clear();
            let round = tested.iter().filter(|&&(a, b, _)| found.is_round(a, b));
            let pairs = round.map(|&(a, b, _)| RoundPair {
                a,
                b,
                reach: found.reach(a, b),
            });
            out.round_pairs.extend(pairs);
            out.round_tests.clear();
            round_lanes::test_pairs(found.colliders, &out.round_pairs, &mut out.round_tests);
            let tested_in_lanes = Instant::now();
            out.points.clear();
            // the round pairs are the tested ones in order: the next one is this pair's, if any
            let mut round = out.round_pairs.iter().zip(&out.round_tests).peekable();
            for &(a, b, slot) in &out.tested {
                let next = round.next_if(|(pair, _)| (pair.a, pair.b) == (a, b));
                let (test, reach) = match next {
                    Some((pair, result)) => (result.test(), pair.reach),
                    None => (RoundTest::Scalar, found.reach(a, b)),
                };
                let gap = found.collide(a, b, (test, reach), &mut out.points, &mut out.features);
                if let Some(bound) = bounds.get_mut(slot as usize) {
                    *bound = gap;
                }
            }
            out.work = NarrowPhaseWork {
                report: (reported - start).as_secs_f64(),
                shape_tests: (tested_in_lanes - reported).as_secs_f64(),
                points: tested_in_lanes.elapsed().as_secs_f64(),
            };
        };
        let kept_start = |c: usize| starts[c].min(kept);
        let narrow_phase = Instant::now();
        each_chunk(
            0,
            &mut self.chunks[..chunks],
            &mut bounds,
            &kept_start,
            &run,
        );
        let narrow_phase = narrow_phase.elapsed().as_secs_f64();
        self.broad_phase.restore_gaps(bounds);
        let concatenation = Instant::now();
        concatenate(&self.chunks[..chunks], points);
        self.profile = DetectionProfile {
            records,
            broad_phase: broad_seconds,
            broad_phase_parts: self.broad_phase.timing(),
            handover: handover_seconds,
            narrow_phase,
            narrow_phase_work: (self.chunks[..chunks].iter())
                .fold(NarrowPhaseWork::default(), |sum, c| sum.add(c.work)),
            concatenate: concatenation.elapsed().as_secs_f64(),
            rebuilt,
            pairs_tested: self.chunks[..chunks].iter().map(|c| c.tested.len()).sum(),
            pairs_skipped: self.chunks[..chunks].iter().map(|c| c.skipped).sum(),
        };
    }

    /// Where the last detection's time went ([`DetectionProfile`]).
    pub fn profile(&self) -> &DetectionProfile {
        &self.profile
    }

    /// How many candidate pairs the last detection skipped as proven out of reach
    /// ([`gaps`]): pairs whose boxes overlap but whose shapes cannot make a point.
    pub fn pairs_skipped(&self) -> usize {
        self.profile.pairs_skipped
    }
}

/// The body pairs that never collide ([`Constraints::pairs_kept_apart`]), as the broad phase
/// reads them.
pub fn joined(body_count: usize, constraints: &Constraints) -> Joined {
    let pairs = constraints.pairs_kept_apart().map(|(a, b)| (a.0, b.0));
    Joined::new(body_count, pairs)
}

/// Where each of `chunks` chunks of the candidates (`kept` kept pairs, then `others`) starts,
/// and where the last ends, each chunk about the same work ([`OTHER_WORK`]).
fn chunk_starts(kept: usize, others: usize, chunks: usize, starts: &mut Vec<usize>) {
    let work = kept + OTHER_WORK * others;
    starts.clear();
    starts.extend((0..=chunks).map(|c| {
        let w = work * c / chunks;
        match w <= kept {
            true => w,
            false => (kept + (w - kept).div_ceil(OTHER_WORK)).min(kept + others),
        }
    }));
}

/// Runs `run(c, out, bounds)` for the chunks `first..` whose outputs are `outs`, each given its
/// kept pairs' `bounds` (those from `kept_start(c)` on), halves on two threads.
fn each_chunk<R, S>(
    first: usize,
    outs: &mut [ChunkOut],
    bounds: &mut [f32],
    kept_start: &S,
    run: &R,
) where
    R: Fn(usize, &mut ChunkOut, &mut [f32]) + Sync,
    S: Fn(usize) -> usize + Sync,
{
    if let [out] = outs {
        return run(first, out, bounds);
    }
    let half = outs.len() / 2;
    let (low, high) = outs.split_at_mut(half);
    let at = kept_start(first + half) - kept_start(first);
    let (low_bounds, high_bounds) = bounds.split_at_mut(at);
    rayon::join(
        || each_chunk(first, low, low_bounds, kept_start, run),
        || each_chunk(first + half, high, high_bounds, kept_start, run),
    );
}

/// Appends the chunks' points to `points` in chunk order, large outputs copied on several
/// threads (the rain's 20 000 points are 2.6 MB).
fn concatenate(chunks: &[ChunkOut], points: &mut Vec<ContactPoint>) {
    use std::mem::MaybeUninit;
    fn copy(parts: &[ChunkOut], to: &mut [MaybeUninit<ContactPoint>]) {
        if parts.len() == 1 || to.len() < PARALLEL_PAIRS {
            for (to, p) in to.iter_mut().zip(parts.iter().flat_map(|c| &c.points)) {
                to.write(*p);
            }
            return;
        }
        let half = parts.len() / 2;
        let (low, high) = to.split_at_mut(parts[..half].iter().map(|c| c.points.len()).sum());
        rayon::join(|| copy(&parts[..half], low), || copy(&parts[half..], high));
    }
    let added: usize = chunks.iter().map(|c| c.points.len()).sum();
    points.reserve(added);
    let len = points.len();
    copy(chunks, &mut points.spare_capacity_mut()[..added]);
    // SAFETY: `copy` wrote all `added` elements after `len` (the chunks' lengths sum to it)
    unsafe { points.set_len(len + added) };
}

/// One chunk's output of the narrow phase, reused from frame to frame.
#[derive(Clone, Debug, Default)]
struct ChunkOut {
    points: Vec<ContactPoint>,
    features: Vec<Feature>,
    /// The pairs to test, each with its gap bound's place in the chunk (`u32::MAX` for the
    /// large boxes' and half-spaces' pairs, which have none).
    tested: Vec<(u32, u32, u32)>,
    /// The tested pairs of spheres and capsules, and what the lanes found for each.
    round_pairs: Vec<RoundPair>,
    round_tests: Vec<RoundResult>,
    /// Pairs whose gap bound proved them out of reach this step.
    skipped: usize,
    /// This chunk's share of [`DetectionProfile::narrow_phase_work`].
    work: NarrowPhaseWork,
}

/// What the narrow phase of one pair reads.
struct PairContext<'a> {
    colliders: &'a [Collider],
    handover: &'a Handover,
    dt: f32,
    margin: f32,
}

impl PairContext<'_> {
    /// Whether both bodies are spheres or capsules ([`round_lanes`]).
    fn is_round(&self, a: u32, b: u32) -> bool {
        let round = |i: u32| round_radius(&self.colliders[i as usize].shape).is_some();
        round(a) && round(b)
    }

    /// How far the pair's surfaces may be apart and still make a point: the margin plus how
    /// far they may close this frame, the relative speed of the centres plus what spin adds at
    /// the farthest surface point (a limb spinning at 20 rad/s moves its tip 5 cm a frame
    /// further than its centre).
    fn reach(&self, a: u32, b: u32) -> f32 {
        let (ca, cb) = (&self.colliders[a as usize], &self.colliders[b as usize]);
        let closing =
            (ca.linear_velocity - cb.linear_velocity).length() + ca.spin_bound + cb.spin_bound;
        self.margin + self.dt * closing
    }

    /// The contact points of the pair (a, b) within `reach` ([`Self::reach`]; filtered, then
    /// the narrow phase, or what the lanes found, `test`) onto `points`, and a lower bound on
    /// the distance of its shapes if it made none ([`gaps`]).
    fn collide(
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

/// Each body's motion from its record last step to this step's (unknown for all when the
/// bodies changed), on several threads for a large world.
fn measure_motions(previous: &[Collider], now: &[Collider], motions: &mut Vec<Motion>) {
    motions.clear();
    if previous.len() != now.len() {
        motions.resize(now.len(), Motion::UNKNOWN);
    } else if now.len() >= PARALLEL_BODIES && rayon::current_num_threads() > 1 {
        use rayon::prelude::*;
        let each = previous.par_iter().zip(now);
        motions.par_extend(each.map(|(before, now)| Motion::between(before, now)));
    } else {
        let each = previous.iter().zip(now);
        motions.extend(each.map(|(before, now)| Motion::between(before, now)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chunks cover the candidates in order, and their work (a kept pair 1, another
    /// OTHER_WORK) is within two other pairs' of an even share.
    #[test]
    fn chunks_cover_the_candidates_with_even_work() {
        let mut starts = Vec::new();
        for (kept, others) in [
            (0, 0),
            (10, 0),
            (0, 10),
            (1000, 37),
            (5, 200),
            (69_000, 2500),
        ] {
            for chunks in [1, 3, 16] {
                chunk_starts(kept, others, chunks, &mut starts);
                assert_eq!(starts.len(), chunks + 1);
                assert_eq!((starts[0], starts[chunks]), (0, kept + others));
                assert!(starts.windows(2).all(|w| w[0] <= w[1]), "{starts:?}");
                let work = |i: usize| i.min(kept) + OTHER_WORK * i.saturating_sub(kept);
                let share = work(kept + others) as f64 / chunks as f64;
                for c in 0..chunks {
                    let done = (work(starts[c + 1]) - work(starts[c])) as f64;
                    assert!(
                        (done - share).abs() <= 2.0 * OTHER_WORK as f64,
                        "kept {kept}, others {others}, chunk {c} of {chunks}: {done} of {share}"
                    );
                }
            }
        }
    }

    /// Each chunk is run once, with exactly its own kept pairs' bounds, whatever the split.
    #[test]
    fn each_chunk_gets_its_own_bounds() {
        let (kept, others) = (1000, 300);
        for chunks in [1, 2, 5, 16] {
            let mut starts = Vec::new();
            chunk_starts(kept, others, chunks, &mut starts);
            let mut bounds: Vec<f32> = (0..kept).map(|i| i as f32).collect();
            let mut outs = vec![ChunkOut::default(); chunks];
            let kept_start = |c: usize| starts[c].min(kept);
            let run = |c: usize, out: &mut ChunkOut, bounds: &mut [f32]| {
                out.skipped = c + 1; // ran, once
                let expected = (kept_start(c)..kept_start(c + 1)).map(|i| i as f32);
                assert!(bounds.iter().copied().eq(expected), "chunk {c} of {chunks}");
                bounds.iter_mut().for_each(|b| *b = -1.0);
            };
            each_chunk(0, &mut outs, &mut bounds, &kept_start, &run);
            assert!(outs.iter().enumerate().all(|(c, o)| o.skipped == c + 1));
            assert!(bounds.iter().all(|&b| b == -1.0));
        }
    }
}
