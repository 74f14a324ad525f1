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
use crate::math::{Quat, Vec3};

/// Points of a chain (origin, corners, end) bent by `psi` shared in `weights` (summing to 1).
pub fn chain_points(length: f32, psi: f32, weights: &[f32]) -> Vec<Vec3> {
    let n = weights.len();
    let mut points = vec![Vec3::ZERO];
    let mut direction = Vec3::Y;
    let mut p = Vec3::ZERO;
    for i in 0..=n {
        let segment = if i == 0 || i == n {
            length / (2 * n) as f32
        } else {
            length / n as f32
        };
        p += segment * direction;
        points.push(p);
        if i < n {
            direction = Quat::from_rotation_x(psi * weights[i]) * direction;
        }
    }
    points
}

/// Points along the rod (arc) bent by `psi`.
pub fn rod_points(length: f32, psi: f32, samples: usize) -> Vec<Vec3> {
    let tb = Quat::from_rotation_x(psi) * Vec3::Y;
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

/// Largest distance (m) between the chain's end and the rod's end over bends in [-max, max].
pub fn max_end_gap(length: f32, weights: &[f32], max_bend: f32, samples: usize) -> f32 {
    (0..samples)
        .map(|i| {
            let psi = -max_bend + 2.0 * max_bend * i as f32 / (samples - 1) as f32;
            let chain_end = *chain_points(length, psi, weights).last().unwrap();
            let rod_end = *rod_points(length, psi, 2).last().unwrap();
            (chain_end - rod_end).length()
        })
        .fold(0.0, f32::max)
}
