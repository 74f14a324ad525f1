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
//!
//! The chunks' bookkeeping is in `chunks`; one pair's narrow phase and points in `pair`.

mod chunks;
mod pair;

use super::broadphase::gaps::Motion;
use super::broadphase::{BroadPhase, Joined, UpdateTiming};
use super::collider::{self, Collider, PARALLEL_BODIES};
use super::handover::Handover;
use super::round_lanes::{self, RoundPair, RoundTest};
use super::{ContactPoint, PARALLEL_PAIRS};
use crate::body::Body;
use crate::constraint::Constraints;
use crate::lanes::LaneWidth;
use chunks::{chunk_starts, concatenate, each_chunk, ChunkOut};
use pair::PairContext;
use std::time::Instant;

/// What detection keeps from step to step (reused storage, and the broad phase's pairs).
#[derive(Clone, Debug, Default)]
pub struct Detection {
    /// What detection reads of each body this step, and read last step.
    colliders: Vec<Collider>,
    previous: Vec<Collider>,
    /// How each body moved since last step ([`gaps`](super::broadphase::gaps)).
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
    lane_width: LaneWidth,
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
    /// Pairs the gap bounds skipped as proven out of reach ([`gaps`](super::broadphase::gaps)).
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
    /// Runs the lanes `width` at a time (the broad phase's box tests and the round pairs'
    /// shape tests): the same points at every width.
    pub fn set_lane_width(&mut self, width: LaneWidth) {
        self.lane_width = width;
        self.broad_phase.lane_width = width;
    }

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
        let lane_width = self.lane_width;
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
            let (pairs, tests) = (&out.round_pairs, &mut out.round_tests);
            round_lanes::test_pairs(lane_width, found.colliders, pairs, tests);
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

    /// Detections so far that stopped at the broad phase's pair budget, with no points
    /// ([`BroadPhase::update`]).
    pub fn pair_overflows(&self) -> u64 {
        self.broad_phase.overflows
    }

    /// Where the last detection's time went ([`DetectionProfile`]).
    pub fn profile(&self) -> &DetectionProfile {
        &self.profile
    }

    /// How many candidate pairs the last detection skipped as proven out of reach
    /// ([`gaps`](super::broadphase::gaps)): pairs whose boxes overlap but whose shapes cannot
    /// make a point.
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
