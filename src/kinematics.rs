//! The kinematics of a chain of ball-and-socket joints against one rod (paper Fig. 6, §6).
//!
//! Everything is planar and purely geometric: a spine of length `L` leaves the origin along +y
//! and bends in the y-z plane by a total angle `psi`.
//! - rod: the circular arc of length `L` bent by `psi` (its chord is eq. 9);
//! - chain of `n` joints: `n + 1` straight segments, the end ones half as long (`L / 2n`, the
//!   body centres sit mid-segment) and the inner ones `L / n`; the joints share `psi` in the
//!   given proportions. With equal shares the chain's corners lie on the rod's tangent polygon,
//!   so its end traces nearly the rod's locus (chain a); with unequal shares it does not
//!   (chain b).

use crate::constraint::rod::arc_point;
use crate::math::Vec3;

/// Points of a chain (origin, corners, end) bent by `psi` shared in `weights` (summing to 1).
pub fn chain_points(length: f32, psi: f32, weights: &[f32]) -> Vec<Vec3> {
    let n = weights.len();
    let mut points = vec![Vec3::ZERO];
    let mut direction = Vec3::Y;
    let mut p = Vec3::ZERO;
    // half segments at the ends, whole ones between, each corner turning by its weight's share
    for (i, &weight) in weights.iter().enumerate() {
        let segment = if i == 0 { 0.5 } else { 1.0 } * length / n as f32;
        p += segment * direction;
        points.push(p);
        direction = crate::math::quat_from_rotation_x(psi * weight) * direction;
    }
    p += length / (2 * n) as f32 * direction;
    points.push(p);
    points
}

/// Points along the rod (arc) bent by `psi`.
pub fn rod_points(length: f32, psi: f32, samples: usize) -> Vec<Vec3> {
    let tb = crate::math::quat_from_rotation_x(psi) * Vec3::Y;
    (0..samples)
        .map(|i| {
            arc_point(
                Vec3::ZERO,
                Vec3::Y,
                tb,
                length,
                i as f32 / (samples - 1) as f32,
            )
        })
        .collect()
}

/// Equal shares for `n` joints.
pub fn equal_weights(n: usize) -> Vec<f32> {
    vec![1.0 / n as f32; n]
}

/// Bend `i` of `samples` (at least 2) spread evenly over [-`max_bend`, `max_bend`] (rad).
pub fn bend_at(max_bend: f32, i: usize, samples: usize) -> f32 {
    -max_bend + 2.0 * max_bend * i as f32 / (samples - 1) as f32
}

/// Largest distance (m) between the chain's end and the rod's end over bends in [-max, max].
pub fn max_end_gap(length: f32, weights: &[f32], max_bend: f32, samples: usize) -> f32 {
    (0..samples)
        .map(|i| {
            let psi = bend_at(max_bend, i, samples);
            let chain_end = *chain_points(length, psi, weights).last().unwrap();
            let rod_end = *rod_points(length, psi, 2).last().unwrap();
            (chain_end - rod_end).length()
        })
        .fold(0.0, f32::max)
}

/// The Fig. 6 comparison, computed once: three spines (the equal-angle chain, the
/// unequal-angle chain, the rod) at each bend of a sweep, and how far each chain's end lies
/// from the rod's. Recording only draws it.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Total bends (rad), evenly from `-max_bend` to `+max_bend`.
    pub bends: Vec<f32>,
    /// Per spine, its name and its points (root first) at each bend.
    pub spines: [(&'static str, Vec<Vec<Vec3>>); 3],
}

impl Comparison {
    /// Rod samples per bend: enough for a smooth arc at 150 degrees.
    pub const ROD_SAMPLES: usize = 32;

    /// The comparison for a spine of `length` (m) with `joints` joints, the unequal chain's
    /// bend shares `unequal` (any positive scale), swept over `bends` (at least 2) bends in
    /// [-`max_bend`, `max_bend`] (rad).
    pub fn new(length: f32, joints: usize, unequal: &[f32], max_bend: f32, bends: usize) -> Self {
        let bends = bends.max(2);
        let total: f32 = unequal.iter().sum();
        let unequal: Vec<f32> = unequal.iter().map(|w| w / total).collect();
        let equal = equal_weights(joints);
        let bends: Vec<f32> = (0..bends).map(|i| bend_at(max_bend, i, bends)).collect();
        let along =
            |shape: &dyn Fn(f32) -> Vec<Vec3>| bends.iter().map(|&psi| shape(psi)).collect();
        Comparison {
            spines: [
                (
                    "equal_chain",
                    along(&|psi| chain_points(length, psi, &equal)),
                ),
                (
                    "unequal_chain",
                    along(&|psi| chain_points(length, psi, &unequal)),
                ),
                (
                    "rod",
                    along(&|psi| rod_points(length, psi, Self::ROD_SAMPLES)),
                ),
            ],
            bends,
        }
    }

    /// Distance (m) from spine `spine`'s end to the rod's end at bend `bend`.
    pub fn end_gap(&self, spine: usize, bend: usize) -> f32 {
        let end = |s: usize| *self.spines[s].1[bend].last().expect("a spine has points");
        (end(spine) - end(2)).length()
    }

    /// Largest end gaps (m) over the sweep of the equal and the unequal chain.
    pub fn largest_gaps(&self) -> (f32, f32) {
        let largest = |s: usize| {
            (0..self.bends.len())
                .map(|i| self.end_gap(s, i))
                .fold(0.0, f32::max)
        };
        (largest(0), largest(1))
    }
}
