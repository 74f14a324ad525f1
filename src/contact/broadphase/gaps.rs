//! Gap bounds: for each kept pair, a lower bound on how far apart its two shapes are, carried
//! from step to step and lowered each step by how far the two bodies may have moved toward each
//! other, so a pair whose shapes are proven out of reach skips the narrow phase (conservative
//! advancement). The narrow phase of a pair whose boxes overlap but whose shapes are apart
//! costs its two records' loads and the shape test; in the settled 1000-ragdoll rain about
//! 30 000 capsule pairs a step are such pairs, most of them centimetres apart while their
//! bodies move millimetres.
//!
//! A bound is only ever a lower bound, and a pair is skipped only when its bound clears the
//! largest reach the narrow phase could give it by [`SLACK`], so the points found are the same,
//! to the bit, as with every pair tested: skipped pairs are pairs that make no point.
//!
//! - The bound comes from the narrow phase of a pair of spheres or capsules, or of a box and a
//!   sphere or capsule, that made no point ([`crate::contact::narrowphase::gap`]); any other
//!   pair, and any pair that touches, gets [`UNKNOWN`] and is tested every step.
//! - Each step it falls by the relative shift of the two centres plus what each body's turn
//!   moves a point at its bounding radius ([`Motion`]); a pair whose tight boxes do not overlap
//!   is not looked at and forgets its bound.
//! - A pair is out of reach when its bound exceeds `margin + dt (s_a + s_b) + SLACK`, with
//!   `s = |v| + spin bound`: the pair's reach `margin + dt (|v_a - v_b| + spins)` is never
//!   more.

use crate::contact::collider::Collider;
use crate::math::Vec3;

/// The bound of a pair that must be tested (touching, not round, new, or not looked at).
pub const UNKNOWN: f32 = f32::NEG_INFINITY;

/// How far (m) a bound must clear the reach to skip its pair: the rounding of the distances
/// and motions (about 1e-6 m at these coordinates) many times over.
pub const SLACK: f32 = 1e-3;

/// How a body moved since the last detection, and how fast it moves now.
#[derive(Clone, Copy, Debug)]
pub struct Motion {
    /// The centre's shift (m).
    shift: Vec3,
    /// How far the turn moved a point at the bounding radius (m): the chord `2 R sin(theta/2)`.
    turn: f32,
    /// `|v| + spin bound` (m/s): the body's share of a pair's reach.
    speed: f32,
}

impl Motion {
    /// A body with no record last step: every bound on it is dropped.
    pub const UNKNOWN: Motion = Motion {
        shift: Vec3::ZERO,
        turn: f32::INFINITY,
        speed: f32::INFINITY,
    };

    /// The motion from `before` to `now`, records of one body at two steps ([`Motion::UNKNOWN`]
    /// if its shape changed in between).
    pub fn between(before: &Collider, now: &Collider) -> Motion {
        if before.shape != now.shape {
            return Motion::UNKNOWN;
        }
        // |xyz| of the relative turn is sin(theta/2), exact to rounding for small turns (the
        // cosine form loses them below 1e-4 rad)
        let turn = now.orientation * before.orientation.inverse();
        let half_sine = Vec3::new(turn.x, turn.y, turn.z).length();
        Motion {
            shift: now.position - before.position,
            turn: 2.0 * now.bounding_radius * half_sine * (1.0 + 1e-5) + 1e-7,
            speed: now.linear_velocity.length() + now.spin_bound,
        }
    }
}

/// The bound after one more step of motion of the pair's bodies.
#[inline]
pub fn advance(gap: f32, a: &Motion, b: &Motion) -> f32 {
    gap - ((a.shift - b.shift).length() * (1.0 + 1e-5) + a.turn + b.turn)
}

/// Whether a pair with bound `gap` cannot make a point this step.
#[inline]
pub fn out_of_reach(gap: f32, a: &Motion, b: &Motion, margin: f32, dt: f32) -> bool {
    gap > margin + dt * (a.speed + b.speed) + SLACK
}

/// `new_gaps` for the sorted `new_pairs`: the bound a pair had among the sorted `old_pairs`,
/// or [`UNKNOWN`] for a pair new to the list. A long list is carried in parts on several
/// threads, each part from where its first pair falls among the old ones (a landing crowd
/// rebuilds the grid every step, and the carry of its 100 000 pairs stood alone on the
/// detection's serial stretch).
pub fn carry(
    old_pairs: &[(u32, u32)],
    old_gaps: &[f32],
    new_pairs: &[(u32, u32)],
    new_gaps: &mut Vec<f32>,
) {
    new_gaps.clear();
    new_gaps.resize(new_pairs.len(), UNKNOWN);
    let part = |(new_pairs, new_gaps): (&[(u32, u32)], &mut [f32])| {
        let key = |&(a, b): &(u32, u32)| (a as u64) << 32 | b as u64;
        let Some(first) = new_pairs.first() else {
            return;
        };
        let mut j = old_pairs.partition_point(|p| key(p) < key(first));
        for (pair, gap) in new_pairs.iter().zip(new_gaps) {
            while j < old_pairs.len() && key(&old_pairs[j]) < key(pair) {
                j += 1;
            }
            if j < old_pairs.len() && old_pairs[j] == *pair {
                *gap = old_gaps[j];
            }
        }
    };
    let threads = rayon::current_num_threads();
    if threads > 1 && new_pairs.len() >= PARALLEL_CARRY {
        use rayon::prelude::*;
        let len = new_pairs.len().div_ceil(2 * threads);
        let parts = new_pairs.par_chunks(len).zip(new_gaps.par_chunks_mut(len));
        parts.for_each(part);
    } else {
        part((new_pairs, new_gaps));
    }
}

/// Pairs from which [`carry`] runs in parts on several threads.
const PARALLEL_CARRY: usize = 16_384;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{Body, BodyKind};
    use crate::math::Quat;
    use crate::shape::{Axis, Shape};

    fn capsule(position: Vec3, orientation: Quat) -> Collider {
        let shape = Shape::Capsule {
            half_height: 0.2,
            radius: 0.05,
            axis: Axis::Y,
        };
        Collider::new(
            &Body::new("c", BodyKind::Dynamic, shape, 1.0).with_pose(position, orientation),
        )
    }

    /// The turn's chord bounds how far every surface point moved, for tiny turns too.
    #[test]
    fn the_motion_bounds_every_surface_point() {
        let start = Quat::from_axis_angle(Vec3::new(0.3, 1.0, -0.2).normalize(), 0.9);
        for angle in [1e-6, 1e-5, 1e-4, 1e-3, 0.1, 1.0] {
            let turn = Quat::from_axis_angle(Vec3::new(1.0, 0.2, 0.4).normalize(), angle);
            let (p0, p1) = (Vec3::new(3.0, 1.0, -2.0), Vec3::new(3.001, 0.999, -2.0));
            let (before, now) = (capsule(p0, start), capsule(p1, turn * start));
            let motion = Motion::between(&before, &now);
            let moved = |local: Vec3| (now.world_point(local) - before.world_point(local)).length();
            for local in [
                Vec3::new(0.0, 0.25, 0.0),
                Vec3::new(0.05, -0.2, 0.0),
                Vec3::ZERO,
            ] {
                let bound = motion.shift.length() + motion.turn;
                assert!(
                    moved(local) <= bound,
                    "angle {angle}: {} > {bound}",
                    moved(local)
                );
            }
        }
    }

    #[test]
    fn carry_keeps_the_bounds_of_pairs_kept_and_forgets_new_ones() {
        let old = [(0, 1), (0, 3), (2, 5)];
        let mut gaps = Vec::new();
        carry(
            &old,
            &[0.1, 0.2, 0.3],
            &[(0, 1), (0, 2), (2, 5), (4, 4)],
            &mut gaps,
        );
        assert_eq!(gaps, [0.1, UNKNOWN, 0.3, UNKNOWN]);
    }

    /// A long list, carried in parts on several threads, against a search per pair.
    #[test]
    fn a_long_list_carried_in_parts_keeps_every_bound() {
        let mut state = 99u32;
        let mut pairs = |count: usize| {
            let mut list: Vec<(u32, u32)> = (0..count)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 17;
                    state ^= state << 5;
                    (state % 3000, state / 3000 % 3000)
                })
                .collect();
            list.sort_unstable();
            list.dedup();
            list
        };
        // last step's pairs, a third of them gone and as many new ones come
        let old = pairs(60_000);
        let mut new: Vec<(u32, u32)> = old.iter().copied().step_by(3).collect();
        new.extend(old.iter().copied().skip(1).step_by(3));
        new.extend(pairs(20_000));
        new.sort_unstable();
        new.dedup();
        let old_gaps: Vec<f32> = (0..old.len()).map(|i| i as f32).collect();
        let mut gaps = Vec::new();
        carry(&old, &old_gaps, &new, &mut gaps);
        assert!(new.len() > PARALLEL_CARRY);
        let expected: Vec<f32> = (new.iter())
            .map(|p| old.binary_search(p).map_or(UNKNOWN, |j| old_gaps[j]))
            .collect();
        assert_eq!(gaps, expected);
        assert!(gaps.iter().filter(|g| **g != UNKNOWN).count() > 30_000);
    }
}
