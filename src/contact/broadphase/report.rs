//! What the broad phase reports each step: the kept fat pairs whose tight boxes overlap (in
//! ranges, so several threads can report parts), optionally skipping those whose gap bound
//! ([`super::gaps`]) proves them out of reach, then the large boxes' and half-spaces' pairs.

use super::{gaps, BroadPhase};
use crate::contact::collider::Collider;
use crate::math::Vec3;

impl BroadPhase {
    /// How many fat pairs are kept: [`Self::report_kept`]'s range.
    pub fn kept_len(&self) -> usize {
        self.fat_pairs.len()
    }

    /// Reports the kept pairs `range` (of [`Self::kept_len`]) whose tight boxes overlap, in
    /// order: ranges that split the kept pairs report them in parts, on several threads.
    pub fn report_kept(&self, range: std::ops::Range<usize>, mut pair: impl FnMut(u32, u32)) {
        let (proxies, tight) = (&self.proxies, &self.tight);
        for &(a, b) in &self.fat_pairs[range] {
            if tight[a as usize].overlaps(&tight[b as usize]) {
                pair(proxies[a as usize].body, proxies[b as usize].body);
            }
        }
    }

    /// [`Self::report_kept`] with the kept pairs' gap bounds ([`gaps`]): `bounds` is the
    /// bounds of `range` (from [`Self::take_gaps`]), `motions` each body's since the last
    /// step. A pair proven out of reach is skipped (its bound advanced); every other pair
    /// whose tight boxes overlap is appended to `tested` as `(a, b, place in range)`, its
    /// bound left [`gaps::UNKNOWN`] for the caller to write. Returns how many pairs were
    /// skipped.
    ///
    /// Whether a pair is skipped or tested is about even in a settled pile, so the choice is
    /// made without a branch: every overlapping pair is written to `tested`, and the count
    /// moves on only past the tested ones.
    pub fn report_kept_bounded(
        &self,
        range: std::ops::Range<usize>,
        bounds: &mut [f32],
        motions: &[gaps::Motion],
        (margin, dt): (f32, f32),
        tested: &mut Vec<(u32, u32, u32)>,
    ) -> usize {
        let (proxies, tight) = (&self.proxies, &self.tight);
        let mut skipped = 0;
        tested.reserve(range.len());
        let start = tested.len();
        let spare = &mut tested.spare_capacity_mut()[..range.len()];
        let mut count = 0;
        for (slot, (&(a, b), gap)) in self.fat_pairs[range].iter().zip(bounds).enumerate() {
            if !tight[a as usize].overlaps(&tight[b as usize]) {
                *gap = gaps::UNKNOWN;
                continue;
            }
            let (a, b) = (proxies[a as usize].body, proxies[b as usize].body);
            let (ma, mb) = (&motions[a as usize], &motions[b as usize]);
            let advanced = gaps::advance(*gap, ma, mb);
            let skip = gaps::out_of_reach(advanced, ma, mb, margin, dt);
            *gap = if skip { advanced } else { gaps::UNKNOWN };
            spare[count].write((a, b, slot as u32));
            count += !skip as usize;
            skipped += skip as usize;
        }
        // SAFETY: the first `count` of the spare slots were written (each slot is written
        // before the count may move past it)
        unsafe { tested.set_len(start + count) };
        skipped
    }

    /// The kept pairs' bounds, to hand back with [`Self::restore_gaps`] (the narrow phase
    /// writes them chunk by chunk while it reads the rest of the broad phase).
    pub fn take_gaps(&mut self) -> Vec<f32> {
        std::mem::take(&mut self.gaps)
    }

    /// Hands back [`Self::take_gaps`]'s bounds (their first [`Self::kept_len`]).
    pub fn restore_gaps(&mut self, mut gaps: Vec<f32>) {
        gaps.truncate(self.fat_pairs.len());
        self.gaps = gaps;
    }

    /// Reports the pairs after the kept ones: the large boxes' and the half-spaces'.
    pub fn report_others(&self, bodies: &[Collider], mut pair: impl FnMut(u32, u32)) {
        let (proxies, tight) = (&self.proxies, &self.tight);
        for (i, &large) in self.large.iter().enumerate() {
            let a = &proxies[large as usize];
            for (index, b) in proxies.iter().enumerate() {
                // large-large pairs once, from the earlier of the two in `large`
                let other_large = self.large.binary_search(&(index as u32));
                if index as u32 == large || other_large.is_ok_and(|j| j <= i) {
                    continue;
                }
                if a.flags.may_touch(b.flags) && tight[large as usize].overlaps(&tight[index]) {
                    pair(a.body.min(b.body), a.body.max(b.body));
                }
            }
        }
        for &plane in &self.half_spaces {
            let plane_body = &bodies[plane as usize];
            let normal = plane_body.orientation * Vec3::Y;
            let height = normal.dot(plane_body.position);
            for (proxy, tight) in proxies.iter().zip(tight) {
                if !(proxy.flags.dynamic && proxy.flags.active) {
                    continue;
                }
                // the box's lowest corner along the normal, less the half margin the box does
                // not hold (the pair's reach has all of it on the body's side): above the
                // plane, no contact
                let centre = 0.5 * (Vec3::from(tight.min) + Vec3::from(tight.max));
                let half = 0.5 * (Vec3::from(tight.max) - Vec3::from(tight.min));
                if normal.dot(centre) - normal.abs().dot(half) - 0.5 * self.margin <= height {
                    pair(plane, proxy.body);
                }
            }
        }
    }
}
