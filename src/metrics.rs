//! Residual measures (paper Fig. 8), taken after a frame's iterations:
//! - dislocation: distance between a joint's two world anchors, summed per ragdoll, in cm;
//! - angular violation: how far hard angular constraints (joint limits) are violated, summed
//!   per ragdoll, in rad;
//! - energy: kinetic plus gravitational potential (zero at y = 0), in J.

use crate::constraint::Violation;
use crate::ragdoll::Ragdoll;
use crate::world::World;

/// Residual of one ragdoll in the units the paper plots.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Residual {
    pub dislocation_cm: f32,
    pub angular_rad: f32,
}

pub fn ragdoll_residual(world: &World, ragdoll: &Ragdoll) -> Residual {
    let mut total = Violation::default();
    for constraint in &world.constraints[ragdoll.constraints.clone()] {
        total += constraint.violation(&world.bodies);
    }
    Residual {
        dislocation_cm: 100.0 * total.dislocation,
        angular_rad: total.angular,
    }
}

/// Everything measured on one frame.
#[derive(Clone, Debug, Default)]
pub struct FrameMetrics {
    /// One per ragdoll, in `world.ragdolls` order.
    pub ragdolls: Vec<Residual>,
    pub kinetic_energy: f32,
    pub potential_energy: f32,
}

impl FrameMetrics {
    /// Measures `world` into `self`, reusing its storage.
    pub fn measure(&mut self, world: &World) {
        self.ragdolls.clear();
        self.ragdolls
            .extend(world.ragdolls.iter().map(|r| ragdoll_residual(world, r)));
        self.kinetic_energy = world.kinetic_energy();
        self.potential_energy = world.potential_energy();
    }

    pub fn total_energy(&self) -> f32 {
        self.kinetic_energy + self.potential_energy
    }
}

/// Running statistics of a residual series, for printed summaries.
#[derive(Clone, Copy, Debug, Default)]
pub struct Summary {
    pub frames: u32,
    pub dislocation_sum: f64,
    pub dislocation_max: f32,
    pub angular_sum: f64,
    pub angular_max: f32,
}

impl Summary {
    pub fn add(&mut self, r: Residual) {
        self.frames += 1;
        self.dislocation_sum += r.dislocation_cm as f64;
        self.dislocation_max = self.dislocation_max.max(r.dislocation_cm);
        self.angular_sum += r.angular_rad as f64;
        self.angular_max = self.angular_max.max(r.angular_rad);
    }

    pub fn mean_dislocation_cm(&self) -> f64 {
        self.dislocation_sum / self.frames.max(1) as f64
    }

    pub fn mean_angular_rad(&self) -> f64 {
        self.angular_sum / self.frames.max(1) as f64
    }
}
