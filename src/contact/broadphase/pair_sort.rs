//! Sorting the kept pairs after a grid rebuild: the sweeps hand their pairs over in runs by
//! first index ([`IndexRuns`]), and each run is sorted on its own ([`sort_pairs`]), the runs
//! on several threads.

/// Proxy indices below `n` in `count` runs of consecutive indices of about equal length, an
/// index's run found with one multiply (the sweeps sort their pairs into runs by first index,
/// so that [`sort_pairs`] can sort each run on its own).
#[derive(Clone, Copy, Debug)]
pub(super) struct IndexRuns {
    /// `2^32 count / n`, rounded up: `a`'s run is `a * magic / 2^32` (at most `count - 1`,
    /// which it can pass only when `n^2 >= 2^32 count`).
    magic: u64,
    count: usize,
    n: usize,
}

impl IndexRuns {
    pub(super) fn new(n: usize, count: usize) -> IndexRuns {
        let count = count.max(1);
        let magic = ((count as u64) << 32) / n.max(1) as u64 + 1;
        IndexRuns { magic, count, n }
    }

    pub(super) fn count(self) -> usize {
        self.count
    }

    /// The run of index `a`.
    #[inline]
    pub(super) fn of(self, a: u32) -> usize {
        (((a as u64 * self.magic) >> 32) as usize).min(self.count - 1)
    }

    /// The first index of run `r` (`n` for `r = count`): the least `a` with `a * magic >= r
    /// 2^32`.
    fn start(self, r: usize) -> usize {
        match r < self.count {
            true => (((r as u64) << 32).div_ceil(self.magic) as usize).min(self.n),
            false => self.n,
        }
    }
}

/// A list of proxy index pairs.
type PairList = Vec<(u32, u32)>;

/// The pairs of proxy indices below `n` (`runs.n`) sorted by (first, second) into `pairs`, as
/// `sort_unstable` would order them (the pairs are distinct). Each part holds its pairs by the
/// run of their first index (`run(part, r)`), so each run is sorted on its own, by two stable
/// counting passes (by second, then first), the runs on several threads, each into its own
/// part of `pairs`. About 90 000 pairs at each grid rebuild of the landing rain (rod; 130 000
/// chain3): the comparison sort took 0.8-1.6 ms on two threads, the same passes over the whole
/// list on one thread 0.69-0.76 ms with the parts' concatenation, and by runs on two threads
/// 0.40-0.47 ms. (Counting by first index alone and sorting each index's pairs by second with
/// insertion was slower: 0.66-0.78 ms, the pairs of one index come in no order.) `scratch` and
/// `counts` are reused storage.
pub(super) fn sort_pairs<T: Sync>(
    parts: &[T],
    run: impl Fn(&T, usize) -> &[(u32, u32)] + Sync,
    runs: IndexRuns,
    (pairs, scratch): (&mut PairList, &mut PairList),
    counts: &mut Vec<u32>,
) {
    let (n, run) = (runs.n, &run);
    let each = || {
        parts
            .iter()
            .flat_map(|p| (0..runs.count).map(move |r| run(p, r)))
    };
    let total: usize = each().map(<[_]>::len).sum();
    pairs.clear();
    if n > 1 << 16 || total < 4096 {
        each().for_each(|pairs_of| pairs.extend_from_slice(pairs_of));
        pairs.sort_unstable();
        return;
    }
    pairs.resize(total, (0, 0));
    scratch.clear();
    scratch.resize(total, (0, 0));
    // each run's first indices' counts, then each run's second indices' (those from its start)
    let seconds = |r: usize| n - runs.start(r);
    counts.clear();
    counts.resize(n + (0..runs.count).map(seconds).sum::<usize>(), 0);
    let (firsts, seconds_counts) = counts.split_at_mut(n);
    let sort_run = |r: usize, (out, scratch): Slices, (firsts, seconds): Counts| {
        let first = runs.start(r) as u32;
        let from = parts.iter().flat_map(|part| run(part, r).iter().copied());
        counting_pass(from, scratch, seconds, |(_, b)| (b - first) as usize);
        let from = scratch.iter().copied();
        counting_pass(from, out, firsts, |(a, _)| (a - first) as usize);
    };
    let run_len = |r: usize| parts.iter().map(|p| run(p, r).len()).sum::<usize>();
    let sizes = RunSizes {
        start: &|r| runs.start(r),
        pairs: &run_len,
        seconds: &seconds,
    };
    let slices = (&mut pairs[..], &mut scratch[..]);
    split_runs(
        0..runs.count,
        slices,
        (firsts, seconds_counts),
        &sizes,
        &sort_run,
    );
}

/// A stable counting pass of `from` into `to` by `digit`, whose values' `counts` start at 0.
fn counting_pass(
    from: impl Iterator<Item = (u32, u32)> + Clone,
    to: &mut [(u32, u32)],
    counts: &mut [u32],
    digit: impl Fn((u32, u32)) -> usize,
) {
    for pair in from.clone() {
        counts[digit(pair)] += 1;
    }
    let mut at = 0;
    for c in counts.iter_mut() {
        (*c, at) = (at, at + *c);
    }
    for pair in from {
        let place = &mut counts[digit(pair)];
        to[*place as usize] = pair;
        *place += 1;
    }
}

/// A run's output and scratch pairs.
type Slices<'a> = (&'a mut [(u32, u32)], &'a mut [(u32, u32)]);
/// A run's first and second indices' counts.
type Counts<'a> = (&'a mut [u32], &'a mut [u32]);

/// Where the runs' storage splits: each run's first index, its pairs' count and its second
/// indices' count.
struct RunSizes<'a> {
    start: &'a (dyn Fn(usize) -> usize + Sync),
    pairs: &'a (dyn Fn(usize) -> usize + Sync),
    seconds: &'a (dyn Fn(usize) -> usize + Sync),
}

/// Runs `sort_run(r, slices, counts)` for each run `r` in `runs`, given its own part of the
/// storage, halves on two threads.
fn split_runs<R>(
    runs: std::ops::Range<usize>,
    (out, scratch): Slices,
    (firsts, seconds): Counts,
    sizes: &RunSizes,
    sort_run: &R,
) where
    R: Fn(usize, Slices, Counts) + Sync,
{
    if runs.len() == 1 {
        return sort_run(runs.start, (out, scratch), (firsts, seconds));
    }
    let mid = (runs.start + runs.end) / 2;
    let (low, high) = (runs.start..mid, mid..runs.end);
    let low_pairs: usize = low.clone().map(sizes.pairs).sum();
    let (low_out, high_out) = out.split_at_mut(low_pairs);
    let (low_scratch, high_scratch) = scratch.split_at_mut(low_pairs);
    let low_firsts = (sizes.start)(mid) - (sizes.start)(low.start);
    let (low_firsts, high_firsts) = firsts.split_at_mut(low_firsts);
    let low_seconds = low.clone().map(sizes.seconds).sum();
    let (low_seconds, high_seconds) = seconds.split_at_mut(low_seconds);
    let (low_slices, high_slices) = ((low_out, low_scratch), (high_out, high_scratch));
    rayon::join(
        || split_runs(low, low_slices, (low_firsts, low_seconds), sizes, sort_run),
        || {
            split_runs(
                high,
                high_slices,
                (high_firsts, high_seconds),
                sizes,
                sort_run,
            )
        },
    );
}

#[cfg(test)]
mod tests {
    use super::super::grid::tests::xorshift;
    use super::*;

    /// Every index's run is below the count, runs are in index order, and each run starts
    /// where its first index is.
    #[test]
    fn index_runs_cover_the_indices_in_order() {
        for (n, count) in [
            (1, 1),
            (7, 3),
            (11_192, 4),
            (13_193, 16),
            (65_536, 32),
            (100, 200),
            (300_000, 8), // n^2 > 2^32 count: the last indices' runs clamped
        ] {
            let runs = IndexRuns::new(n, count);
            let of: Vec<usize> = (0..n as u32).map(|a| runs.of(a)).collect();
            assert!(of.windows(2).all(|w| w[0] <= w[1]) && of[n - 1] < count);
            for r in 0..=count {
                let first = of.partition_point(|&run| run < r);
                assert_eq!(runs.start(r), first, "n {n}, {count} runs, run {r}");
            }
        }
    }

    #[test]
    fn sort_pairs_orders_as_the_comparison_sort() {
        let n = 3000;
        let mut below = xorshift(12345);
        let mut next = move || below(n as u64) as u32;
        let mut pairs: Vec<(u32, u32)> = (0..20_000)
            .map(|_| {
                let (a, b) = (next(), next());
                (a.min(b), a.max(b))
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        let sorted = pairs.clone();
        pairs.reverse();
        pairs.swap(10, 5000);
        // in parts of 777 (each kept in runs by first index), with one run and with several,
        // one of them empty (no first index above n - 100)
        pairs.retain(|&(a, _)| a < n as u32 - 100);
        let sorted: Vec<_> = sorted
            .into_iter()
            .filter(|&(a, _)| a < n as u32 - 100)
            .collect();
        for count in [1, 3, 32] {
            let runs = IndexRuns::new(n, count);
            let parts: Vec<Vec<Vec<(u32, u32)>>> = (pairs.chunks(777))
                .map(|part| {
                    let mut by_run = vec![Vec::new(); count];
                    part.iter().for_each(|&p| by_run[runs.of(p.0)].push(p));
                    by_run
                })
                .collect();
            let (mut out, mut scratch, mut counts) = (Vec::new(), Vec::new(), Vec::new());
            sort_pairs(
                &parts,
                |p, r| &p[r],
                runs,
                (&mut out, &mut scratch),
                &mut counts,
            );
            assert_eq!(out, sorted, "{count} runs");
        }
    }
}
