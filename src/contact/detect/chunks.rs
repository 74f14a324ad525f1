//! The narrow phase's chunks: where each starts (about the same work each), running them on
//! two threads by halves, each with its own kept pairs' gap bounds, and their points copied
//! into one list in chunk order.

use super::NarrowPhaseWork;
use crate::contact::feature::Feature;
use crate::contact::round_lanes::{RoundPair, RoundResult};
use crate::contact::{ContactPoint, PARALLEL_PAIRS};

/// How many kept pairs' work one of the others (a large box's or a half-space's pair: all
/// tested, most of them touching) is, to balance the narrow phase's chunks. With chunks of
/// equal pair counts the settled rain's last chunk, which holds the others, took 0.72 ms
/// against 0.40 for each of the rest, and one thread waited on it.
pub(super) const OTHER_WORK: usize = 3;

/// Where each of `chunks` chunks of the candidates (`kept` kept pairs, then `others`) starts,
/// and where the last ends, each chunk about the same work ([`OTHER_WORK`]).
pub(super) fn chunk_starts(kept: usize, others: usize, chunks: usize, starts: &mut Vec<usize>) {
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
pub(super) fn each_chunk<R, S>(
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
pub(super) fn concatenate(chunks: &[ChunkOut], points: &mut Vec<ContactPoint>) {
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
pub(super) struct ChunkOut {
    pub(super) points: Vec<ContactPoint>,
    pub(super) features: Vec<Feature>,
    /// The pairs to test, each with its gap bound's place in the chunk (`u32::MAX` for the
    /// large boxes' and half-spaces' pairs, which have none).
    pub(super) tested: Vec<(u32, u32, u32)>,
    /// The tested pairs of spheres and capsules, and what the lanes found for each.
    pub(super) round_pairs: Vec<RoundPair>,
    pub(super) round_tests: Vec<RoundResult>,
    /// Pairs whose gap bound proved them out of reach this step.
    pub(super) skipped: usize,
    /// This chunk's share of [`super::DetectionProfile::narrow_phase_work`].
    pub(super) work: NarrowPhaseWork,
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
