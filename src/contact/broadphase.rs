//! Broad phase: sort and sweep on the x axis. Each finite body gets an interval
//! `[x - extent, x + extent]`, its bounding radius grown by the distance it may travel this step
//! and the contact margin; sorting (insertion sort, nearly linear from frame to frame because the
//! order barely changes) and one sweep find the overlapping pairs, then the y and z extents prune
//! them. Half-spaces are unbounded and are paired with every movable body instead. Cost grows
//! about linearly with the number of bodies when they are spread out along x.

use crate::body::{Body, BodyKind};
use crate::shape::Shape;

#[derive(Clone, Copy, Debug, Default)]
struct Proxy {
    body: u32,
    min: [f32; 3],
    max: [f32; 3],
}

/// Reused storage, so the step does not allocate once warmed up.
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    proxies: Vec<Proxy>,
    half_spaces: Vec<u32>,
}

impl BroadPhase {
    /// Calls `pair(a, b)` for every candidate pair (a < b in the world's order for finite pairs;
    /// the half-space first for half-space pairs).
    pub fn find_pairs(
        &mut self,
        bodies: &[Body],
        dt: f32,
        margin: f32,
        mut pair: impl FnMut(u32, u32),
    ) {
        // refresh proxies, keeping the previous order as the starting point for the sort
        if self.proxies.len() + self.half_spaces.len() != bodies.len() {
            self.proxies.clear();
            self.half_spaces.clear();
            for (i, body) in bodies.iter().enumerate() {
                if matches!(body.shape, Shape::HalfSpace) {
                    self.half_spaces.push(i as u32);
                } else {
                    self.proxies.push(Proxy {
                        body: i as u32,
                        ..Default::default()
                    });
                }
            }
        }
        for proxy in &mut self.proxies {
            let body = &bodies[proxy.body as usize];
            let reach = body.shape.bounding_radius() + margin + dt * body.linear_velocity.length();
            let p = body.position.to_array();
            for k in 0..3 {
                proxy.min[k] = p[k] - reach;
                proxy.max[k] = p[k] + reach;
            }
        }
        // insertion sort on min x: linear when the order is nearly kept
        for i in 1..self.proxies.len() {
            let mut j = i;
            while j > 0 && self.proxies[j - 1].min[0] > self.proxies[j].min[0] {
                self.proxies.swap(j - 1, j);
                j -= 1;
            }
        }
        for i in 0..self.proxies.len() {
            let a = self.proxies[i];
            for b in &self.proxies[i + 1..] {
                if b.min[0] > a.max[0] {
                    break;
                }
                let overlap = (1..3).all(|k| a.min[k] <= b.max[k] && b.min[k] <= a.max[k]);
                let movable = bodies[a.body as usize].kind == BodyKind::Dynamic
                    || bodies[b.body as usize].kind == BodyKind::Dynamic;
                if overlap && movable {
                    pair(a.body.min(b.body), a.body.max(b.body));
                }
            }
        }
        for &plane in &self.half_spaces {
            for proxy in &self.proxies {
                if bodies[proxy.body as usize].kind == BodyKind::Dynamic {
                    pair(plane, proxy.body);
                }
            }
        }
    }
}
