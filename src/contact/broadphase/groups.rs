//! Rebuilding the kept pairs group by group: a crowd of ragdolls is a thousand groups of a dozen
//! bodies, and the pairs of two bodies come only from two groups whose boxes overlap.
//!
//! 1. Each group's bodies are a run of consecutive proxies, as a ragdoll's are built (else,
//!    or where the groups are too small or one too large, the grid's rebuild runs instead). A
//!    group's box holds its bodies' fat boxes.
//! 2. The groups' boxes are swept along the axis their centres spread most on: the group pairs.
//! 3. Each body is tested, W at a time in lanes, against the bodies after it in its own group
//!    and against every body of each overlapping group after its own.
//!
//! Every body's partners come out in index order (its own group's first, then each later
//! group's, in order), and the groups are taken in order, so the pairs come out sorted, with
//! no sort: the same pairs in the same order as the grid's rebuild, which the kept pairs'
//! incremental updates and the gap bounds' carry read (tested). Nothing is entered in the grid:
//! the next incremental update enters the fat boxes first ([`BroadPhase::grid_stale`]).
//!
//! On the 1000-ragdoll landing rain (rod spines: 1192 groups, 1000 of them ragdolls of 11
//! bodies) the grid's rebuild entered 24 000 boxes in its cells and swept them for 84 000
//! pairs; the groups make 8 300 group pairs and about 80 000 tests of one body against 16,
//! three in four of which find none. The broad phase's update with a rebuild (`cargo bench
//! --bench drop -- rain`, 2 threads): 1.42 ms by groups against 2.29 by the grid (rod), 1.65
//! against 2.82 (chain3), for the same pairs.

use super::grid::{fill_column, Aabb};
use super::rebuild::{code_lane, ALL_CODE_BITS, IN_EVERY_CELL};
use super::{BroadPhase, Budget, CellBox, CellLanes, Joined, Proxy};
use crate::lanes::{Lane, LaneWidth, LaneWork, MAX_LANES};
use crate::with_lane_type;

/// Groups rebuild the pairs only when they hold this many bodies on average: a world of loose
/// bodies, one a group, would be swept along one axis, which grows as `n^1.5`.
const MIN_MEAN_GROUP: usize = 4;

/// Nor when a group holds more bodies than this: a group's bodies are tested against each
/// other, which grows as the square of its size (a rope of a thousand links).
const MAX_GROUP: usize = 64;

/// Proxies from which the groups' bodies are tested on several threads.
const PARALLEL_GROUPS: usize = 2048;

/// Pairs from which the chunks' pairs are copied out on several threads.
const PARALLEL_COPY: usize = 16_384;

/// One group: its proxies `start..end`.
#[derive(Clone, Copy, Debug, Default)]
struct Span {
    start: u32,
    end: u32,
}

/// What a rebuild by groups reuses from one rebuild to the next.
#[derive(Clone, Debug, Default)]
pub(super) struct Groups {
    layout: Layout,
    /// Each chunk of spans' pairs, in order, and its scratch.
    chunks: Vec<ChunkOut>,
}

/// One chunk of spans' pairs (as arrays, whose layout the AVX-512 stores rely on) and the
/// scratch of its spans' tests.
#[derive(Clone, Debug, Default)]
struct ChunkOut {
    pairs: Vec<[u32; 2]>,
    scratch: Scratch,
}

/// A span's tests ([`Layout::pairs_of_span`]): the words, W bodies each (first body, and the end
/// of its group), and each of the span's bodies' masks over them.
#[derive(Clone, Debug, Default)]
struct Scratch {
    words: Vec<[u32; 2]>,
    masks: Vec<u32>,
}

/// The groups, their overlaps and their bodies' boxes.
#[derive(Clone, Debug, Default)]
struct Layout {
    spans: Vec<Span>,
    /// Scratch: the span of each group seen so far, by the group's id (a body index).
    span_of: Vec<u32>,
    /// The group boxes in the sweep (`index`: the span), sorted by their lower bound along the
    /// sweep's axis, which is moved to `fat.min[0]`, and their bounds in lanes.
    sweep: Vec<CellBox>,
    lanes: CellLanes,
    /// The overlapping group pairs (lower span first); then, for span `s`, the spans after it
    /// that overlap it: `neighbours[first[s]..first[s + 1]]`, ascending.
    pairs: Vec<(u32, u32)>,
    first: Vec<u32>,
    neighbours: Vec<u32>,
    /// Every proxy's fat box and code, one column each.
    bodies: BodyLanes,
}

/// Every proxy's fat box bounds and [`CellBox::code`] (as [`code_lane`], with every cell bit
/// set), one column each, padded by a lane width of boxes that meet nothing.
#[derive(Clone, Debug, Default)]
struct BodyLanes {
    min: [Vec<f32>; 3],
    max: [Vec<f32>; 3],
    code: Vec<f32>,
}

impl BodyLanes {
    fn fill(&mut self, proxies: &[Proxy]) {
        let padded = proxies.len() + MAX_LANES;
        for k in 0..3 {
            // a large proxy (kept apart, paired by the large pass) meets nothing here
            let min = |p: &Proxy| if p.large { f32::INFINITY } else { p.fat.min[k] };
            let max = |p: &Proxy| {
                if p.large {
                    f32::NEG_INFINITY
                } else {
                    p.fat.max[k]
                }
            };
            fill_column(
                &mut self.min[k],
                proxies.iter().map(min),
                padded,
                f32::INFINITY,
            );
            let pad = f32::NEG_INFINITY;
            fill_column(&mut self.max[k], proxies.iter().map(max), padded, pad);
        }
        let code = |p: &Proxy| code_lane(IN_EVERY_CELL | p.flags.code());
        fill_column(
            &mut self.code,
            proxies.iter().map(code),
            padded,
            code_lane(0),
        );
    }

    /// The bounds and codes of bodies `from..from + W`, those at or past `end` masked off.
    #[inline(always)]
    fn lanes<L: Lane>(&self, from: usize, end: usize) -> Lanes<L> {
        // (no closures: their bodies would compile outside `Lane::dispatch`'s function)
        let (min, max) = (&self.min, &self.max);
        Lanes {
            min: [
                L::load(&min[0][from..]),
                L::load(&min[1][from..]),
                L::load(&min[2][from..]),
            ],
            max: [
                L::load(&max[0][from..]),
                L::load(&max[1][from..]),
                L::load(&max[2][from..]),
            ],
            code: L::load(&self.code[from..]),
            within: match end - from {
                n if n >= L::W => u32::MAX >> (32 - L::W),
                n => (1u32 << n) - 1,
            },
        }
    }

    /// The bits of `lanes`' bodies whose boxes overlap body `a`'s and that make a pair with it.
    #[inline(always)]
    fn meeting<L: Lane>(&self, lanes: &Lanes<L>, a: usize) -> u32 {
        let all_codes = L::splat(code_lane(ALL_CODE_BITS));
        let mut overlap = all_codes.le(lanes.code | L::splat(self.code[a]));
        for k in 0..3 {
            overlap = overlap
                & lanes.min[k].le(L::splat(self.max[k][a]))
                & L::splat(self.min[k][a]).le(lanes.max[k]);
        }
        overlap.bitmask() & lanes.within
    }
}

/// W bodies' bounds and codes ([`BodyLanes::lanes`]).
struct Lanes<L> {
    min: [L; 3],
    max: [L; 3],
    code: L,
    within: u32,
}

/// The pairs of a run of spans ([`Layout::pairs_of_span`]), in one lane type.
struct SpanPairs<'a> {
    layout: &'a Layout,
    spans: std::ops::Range<usize>,
    proxies: &'a [Proxy],
    joined: &'a Joined,
    budget: &'a Budget,
    out: &'a mut ChunkOut,
}

impl<L: Lane> LaneWork<L> for SpanPairs<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        let ChunkOut { pairs, scratch } = self.out;
        let mut paid = 0;
        for s in self.spans {
            (self.layout).pairs_of_span::<L>(s, self.proxies, self.joined, scratch, pairs);
            if pairs.len() - paid >= Budget::BATCH {
                if !self.budget.take(pairs.len() - paid) {
                    return;
                }
                paid = pairs.len();
            }
        }
        self.budget.take(pairs.len() - paid);
    }
}

/// The overlapping group pairs from the sorted group boxes ([`Layout::sweep_spans`]).
struct SweepPairs<'a> {
    lanes: &'a CellLanes,
    sweep: &'a [CellBox],
    pairs: &'a mut Vec<(u32, u32)>,
}

impl<L: Lane> LaneWork<L> for SweepPairs<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for (i, a) in self.sweep.iter().enumerate() {
            self.lanes.meeting::<L>(i, a.fat.max[0], |j| {
                let (s, t) = (a.index, self.sweep[j].index);
                self.pairs.push((s.min(t), s.max(t)));
            });
        }
    }
}

impl Layout {
    /// The groups' spans of consecutive proxies; false if a group's proxies are not
    /// consecutive, a group is too large ([`MAX_GROUP`]) or the groups hold too few bodies
    /// ([`MIN_MEAN_GROUP`]).
    fn find_spans(&mut self, proxies: &[Proxy]) -> bool {
        self.spans.clear();
        let ids = proxies
            .iter()
            .map(|p| p.group as usize + 1)
            .max()
            .unwrap_or(0);
        self.span_of.clear();
        self.span_of.resize(ids, u32::MAX);
        for (i, p) in proxies.iter().enumerate() {
            let span = &mut self.span_of[p.group as usize];
            if *span == u32::MAX {
                *span = self.spans.len() as u32;
                self.spans.push(Span {
                    start: i as u32,
                    end: i as u32,
                });
            } else if *span as usize != self.spans.len() - 1 {
                return false; // the group came back after another
            }
            let span = self.spans.last_mut().expect("pushed");
            span.end = i as u32 + 1;
            if (span.end - span.start) as usize > MAX_GROUP {
                return false;
            }
        }
        self.spans.len() * MIN_MEAN_GROUP <= proxies.len()
    }

    /// The overlapping group pairs: the groups' boxes swept along the axis their centres
    /// spread most on, W at a time in lanes ([`CellLanes::meeting`]).
    fn sweep_spans(&mut self, proxies: &[Proxy], width: LaneWidth) {
        self.sweep.clear();
        for (index, span) in (0..).zip(&self.spans) {
            let members = &proxies[span.start as usize..span.end as usize];
            let mut fat = Aabb {
                min: [f32::INFINITY; 3],
                max: [f32::NEG_INFINITY; 3],
            };
            let mut code = IN_EVERY_CELL;
            for p in members.iter().filter(|p| !p.large) {
                for k in 0..3 {
                    fat.min[k] = fat.min[k].min(p.fat.min[k]);
                    fat.max[k] = fat.max[k].max(p.fat.max[k]);
                }
                code |= p.flags.code();
            }
            if fat.min[0] <= fat.max[0] {
                self.sweep.push(CellBox {
                    index,
                    body: 0,
                    group: index,
                    code,
                    fat,
                });
            }
        }
        let spread = |k: usize| {
            let centres = self.sweep.iter().map(|b| b.fat.min[k] + b.fat.max[k]);
            let (low, high) = centres.fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), c| {
                (l.min(c), h.max(c))
            });
            high - low
        };
        let axis = (0..3).fold(0, |best, k| if spread(k) > spread(best) { k } else { best });
        let order = [axis, (axis + 1) % 3, (axis + 2) % 3];
        for b in &mut self.sweep {
            (b.fat.min, b.fat.max) = (order.map(|k| b.fat.min[k]), order.map(|k| b.fat.max[k]));
        }
        self.sweep
            .sort_unstable_by(|a, b| a.fat.min[0].total_cmp(&b.fat.min[0]));
        self.lanes.fill(&self.sweep);
        self.pairs.clear();
        let work = SweepPairs {
            lanes: &self.lanes,
            sweep: &self.sweep,
            pairs: &mut self.pairs,
        };
        with_lane_type!(width, L => L::dispatch(work))
    }

    /// Each span's overlapping spans after it, ascending ([`Self::neighbours`]).
    fn list_neighbours(&mut self) {
        // each list's end, then filled from its end down to its start
        let spans = self.spans.len();
        self.first.clear();
        self.first.resize(spans + 1, 0);
        for &(s, _) in &self.pairs {
            self.first[s as usize] += 1;
        }
        for s in 1..spans {
            self.first[s] += self.first[s - 1];
        }
        self.first[spans] = self.pairs.len() as u32;
        self.neighbours.clear();
        self.neighbours.resize(self.pairs.len(), 0);
        for &(s, t) in &self.pairs {
            let at = &mut self.first[s as usize];
            *at -= 1;
            self.neighbours[*at as usize] = t;
        }
        // (a few dozen each)
        for s in 0..self.spans.len() {
            let (from, to) = (self.first[s] as usize, self.first[s + 1] as usize);
            self.neighbours[from..to].sort_unstable();
        }
    }

    /// Appends the pairs whose first body is in span `s`, sorted: each body's partners after
    /// it in its own group (unless joined), then in each overlapping group after its own.
    /// Each W bodies ("word") of those groups are tested against each body of span `s` in turn
    /// (their bounds loaded once) into `scratch`'s masks, a row of words per body; then each
    /// body's pairs are read out of its row, skipping the empty words (three in four on the
    /// landing rain) W at a time.
    #[inline(always)]
    fn pairs_of_span<L: Lane>(
        &self,
        s: usize,
        proxies: &[Proxy],
        joined: &Joined,
        scratch: &mut Scratch,
        out: &mut Vec<[u32; 2]>,
    ) {
        let span = self.spans[s];
        let (first, last) = (self.first[s] as usize, self.first[s + 1] as usize);
        let others = self.neighbours[first..last]
            .iter()
            .map(|&t| self.spans[t as usize]);
        let Scratch { words, masks } = scratch;
        words.clear();
        for group in std::iter::once(span).chain(others) {
            let bases = (group.start..group.end).step_by(L::W);
            words.extend(bases.map(|base| [base, group.end]));
        }
        let (members, row) = (span.start as usize..span.end as usize, words.len());
        masks.clear();
        masks.resize(members.len() * row, 0);
        for (w, &[base, end]) in words.iter().enumerate() {
            let lanes = self.bodies.lanes::<L>(base as usize, end as usize);
            for (i, a) in members.clone().enumerate() {
                masks[i * row + w] = self.bodies.meeting(&lanes, a);
            }
        }
        let own_words = (members.len()).div_ceil(L::W);
        for (i, a) in members.enumerate() {
            if proxies[a].large {
                continue;
            }
            let masks = &masks[i * row..(i + 1) * row];
            // its own group: the bodies after it, not joined to it
            let body = proxies[a].body;
            for (&[base, _], &mask) in words.iter().zip(masks).take(own_words) {
                let after = match a.checked_sub(base as usize) {
                    None => u32::MAX,
                    Some(d) if d >= L::W => 0,
                    Some(d) => !((2u32 << d) - 1),
                };
                let mut bits = mask & after;
                while bits != 0 {
                    let b = base as usize + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    if !joined.contains(body, proxies[b].body) {
                        out.push([a as u32, b as u32]);
                    }
                }
            }
            // the later groups' words that hold a partner
            let (words, masks) = (&words[own_words..], &masks[own_words..]);
            for (c, chunk) in masks.chunks(L::W).enumerate() {
                let nonzero = chunk.iter().enumerate();
                let mut held = nonzero.fold(0u32, |bits, (k, &m)| bits | ((m != 0) as u32) << k);
                while held != 0 {
                    let w = held.trailing_zeros() as usize;
                    held &= held - 1;
                    L::push_pairs(out, a as u32, words[c * L::W + w][0], chunk[w]);
                }
            }
        }
    }
}

impl BroadPhase {
    /// Rebuilds the fat pairs group by group (see the module docs) from the fat boxes
    /// [`Self::refresh_boxes`] set. Returns false, with the pairs untouched, where groups do
    /// not apply: a group's proxies are not consecutive, or the groups are too small.
    pub(super) fn rebuild_by_groups(&mut self, budget: &Budget) -> bool {
        let Groups {
            layout,
            chunks: outs,
        } = &mut self.groups;
        if !layout.find_spans(&self.proxies) {
            return false;
        }
        layout.bodies.fill(&self.proxies);
        let width = self.lane_width;
        layout.sweep_spans(&self.proxies, width);
        layout.list_neighbours();
        let threads = rayon::current_num_threads();
        let chunks = match threads > 1 && self.proxies.len() >= PARALLEL_GROUPS {
            true => 4 * threads,
            false => 1,
        };
        if outs.len() < chunks {
            outs.resize_with(chunks, Default::default);
        }
        // chunks of about equal proxies, at span boundaries
        let layout = &*layout;
        let n = self.proxies.len();
        let bound = |c: usize| {
            let at = n * c / chunks;
            layout.spans.partition_point(|s| (s.start as usize) < at)
        };
        let (proxies, joined) = (&self.proxies, &self.joined);
        let run = |c: usize, out: &mut ChunkOut| {
            out.pairs.clear();
            let spans = bound(c)..bound(c + 1);
            let work = SpanPairs {
                layout,
                spans,
                proxies,
                joined,
                budget,
                out,
            };
            with_lane_type!(width, L => L::dispatch(work))
        };
        if chunks > 1 {
            use rayon::prelude::*;
            let each = outs[..chunks].par_iter_mut().enumerate();
            each.for_each(|(c, out)| run(c, out));
        } else {
            run(0, &mut outs[0]);
        }
        if budget.spent() {
            return true; // no pairs: the caller keeps none
        }
        let total = outs[..chunks].iter().map(|c| c.pairs.len()).sum();
        self.fat_pairs.resize(total, (0, 0)); // (every pair is written over)
        concatenate(&outs[..chunks], &mut self.fat_pairs);
        true
    }
}

/// Copies the chunks' pairs into `to`, in order, halves on two threads when large.
fn concatenate(chunks: &[ChunkOut], to: &mut [(u32, u32)]) {
    if chunks.len() == 1 || to.len() < PARALLEL_COPY {
        let pairs = chunks.iter().flat_map(|c| &c.pairs);
        to.iter_mut()
            .zip(pairs)
            .for_each(|(to, &[a, b])| *to = (a, b));
        return;
    }
    let half = chunks.len() / 2;
    let (low, high) = to.split_at_mut(chunks[..half].iter().map(|c| c.pairs.len()).sum());
    rayon::join(
        || concatenate(&chunks[..half], low),
        || concatenate(&chunks[half..], high),
    );
}
