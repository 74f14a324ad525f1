//! Residual measures (paper Fig. 8), taken after a frame's iterations:
//! - dislocation: distance between a joint's two world anchors, summed per ragdoll, in cm;
//! - angular violation: how far hard angular constraints (joint limits) are violated, summed
//!   per ragdoll, in rad;
//! - energy: kinetic plus gravitational potential (zero at y = 0), in J;
//! - per rod: psi, tau, length and curve violation; per skeleton and bone-mapping method: bone
//!   length error and chest-end gap (cm).

use crate::constraint::{RodState, Violation};
use crate::lab::Lab;
use crate::ragdoll::Ragdoll;
use crate::skeleton::{BoneError, BoneMethod};
use crate::world::World;

/// Ragdolls from which a frame's measures run on several threads.
const PARALLEL_RAGDOLLS: usize = 64;

/// Residual of one ragdoll in the units the paper plots.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Residual {
    /// Dislocation summed over the ragdoll's constraints (cm).
    pub dislocation_cm: f32,
    /// Angular violation summed over the ragdoll's constraints (rad).
    pub angular_rad: f32,
    /// Mean distance of the ragdoll's bodies from their starting positions (cm): the deviation
    /// from the target pose in the controllability experiment (Fig. 7).
    pub pose_deviation_cm: f32,
}

/// The residual of `ragdoll`'s constraints at the bodies' poses, and its pose deviation.
pub fn ragdoll_residual(world: &World, ragdoll: &Ragdoll) -> Residual {
    let mut total = Violation::default();
    for constraint in &world.constraints[ragdoll.constraints.clone()] {
        total += constraint.violation(&world.bodies);
    }
    let deviation: f32 = ragdoll
        .body_ids()
        .zip(&ragdoll.target_positions)
        .map(|(id, target)| (world.body(id).position - *target).length())
        .sum();
    Residual {
        dislocation_cm: 100.0 * total.dislocation,
        angular_rad: total.angular,
        pose_deviation_cm: 100.0 * deviation / ragdoll.target_positions.len().max(1) as f32,
    }
}

/// The bone errors of `ragdoll` (index `i`), one per bone-mapping method of its skeleton.
fn skeleton_errors<'a>(
    world: &'a World,
    i: usize,
    ragdoll: &'a Ragdoll,
) -> impl Iterator<Item = (usize, BoneMethod, BoneError)> + 'a {
    ragdoll.skeleton.iter().flat_map(move |skeleton| {
        skeleton.methods().iter().map(move |&method| {
            let posed = skeleton.pose(world, method);
            (i, method, skeleton.error(world, &posed))
        })
    })
}

/// Everything measured on one frame.
#[derive(Clone, Debug, Default)]
pub struct FrameMetrics {
    /// One per ragdoll, in `lab.ragdolls` order.
    pub ragdolls: Vec<Residual>,
    /// Kinetic energy of all bodies (J).
    pub kinetic_energy: f32,
    /// Gravitational potential energy of all bodies (J), zero at the origin.
    pub potential_energy: f32,
    /// One per rod constraint, in constraint order.
    pub rods: Vec<RodState>,
    /// Per ragdoll with a skeleton, per bone-mapping method: (ragdoll index, method, error).
    pub bones: Vec<(usize, BoneMethod, BoneError)>,
    /// Deepest contact penetration (cm) at the solver's contact points, reported apart from
    /// the joints' residual.
    pub max_penetration_cm: f32,
    /// Deepest overlap of the shapes (cm), found by a detection of its own on the final poses
    /// ([`crate::contact::Contacts::deepest_overlap`]): what the contact points miss when
    /// bodies slide over each other within a frame. Zero without contacts.
    pub max_overlap_cm: f32,
    /// The detection's storage for `max_overlap_cm`, kept from frame to frame.
    overlap_probe: crate::contact::Contacts,
}

impl FrameMetrics {
    /// Measures `lab` into `self`, reusing its storage.
    pub fn measure(&mut self, lab: &Lab) {
        use rayon::prelude::*;
        let world = &lab.world;
        let FrameMetrics {
            ragdolls,
            kinetic_energy,
            potential_energy,
            rods,
            bones,
            max_penetration_cm,
            max_overlap_cm,
            overlap_probe,
        } = self;
        // a crowd's per-ragdoll measures on several threads, beside the overlap's detection
        // (the rain's frame measured in 7 ms on one thread, longer than its step); each item
        // is computed alone and kept in order, so the results do not depend on the threads
        let parallel = lab.ragdolls.len() >= PARALLEL_RAGDOLLS && rayon::current_num_threads() > 1;
        let mut overlap = || match world.settings.contacts {
            true => 100.0 * overlap_probe.deepest_overlap(&world.bodies, &world.constraints),
            false => 0.0,
        };
        let mut rest = || {
            let residual = |ragdoll| ragdoll_residual(world, ragdoll);
            ragdolls.clear();
            match parallel {
                true => ragdolls.par_extend(lab.ragdolls.par_iter().map(residual)),
                false => ragdolls.extend(lab.ragdolls.iter().map(residual)),
            }
            *kinetic_energy = world.kinetic_energy();
            *potential_energy = world.potential_energy();
            *max_penetration_cm = 100.0 * world.contacts.max_penetration(&world.bodies);
            rods.clear();
            rods.extend(world.rod_states());
            let skeleton_errors = |(i, ragdoll)| skeleton_errors(world, i, ragdoll);
            bones.clear();
            match parallel {
                true => bones.par_extend(
                    (lab.ragdolls.par_iter().enumerate()).flat_map_iter(skeleton_errors),
                ),
                false => bones.extend(lab.ragdolls.iter().enumerate().flat_map(skeleton_errors)),
            }
        };
        *max_overlap_cm = match parallel {
            true => rayon::join(overlap, rest).0,
            false => {
                rest();
                overlap()
            }
        };
    }

    /// Sums over all ragdolls: (dislocation cm, angular rad).
    pub fn totals(&self) -> (f32, f32) {
        self.ragdolls.iter().fold((0.0, 0.0), |(d, a), r| {
            (d + r.dislocation_cm, a + r.angular_rad)
        })
    }

    /// Kinetic plus potential energy (J).
    pub fn total_energy(&self) -> f32 {
        self.kinetic_energy + self.potential_energy
    }
}

/// Running statistics of a residual series, for printed summaries.
#[derive(Clone, Copy, Debug, Default)]
pub struct Summary {
    /// Frames added so far.
    pub frames: u32,
    /// Sum of the dislocations (cm).
    pub dislocation_sum: f64,
    /// Largest dislocation (cm).
    pub dislocation_max: f32,
    /// Sum of the angular violations (rad).
    pub angular_sum: f64,
    /// Largest angular violation (rad).
    pub angular_max: f32,
    /// Sum of the pose deviations (cm).
    pub deviation_sum: f64,
    /// Largest pose deviation (cm).
    pub deviation_max: f32,
}

impl Summary {
    /// Adds one frame's residual.
    pub fn add(&mut self, r: Residual) {
        self.frames += 1;
        self.dislocation_sum += r.dislocation_cm as f64;
        self.dislocation_max = self.dislocation_max.max(r.dislocation_cm);
        self.angular_sum += r.angular_rad as f64;
        self.angular_max = self.angular_max.max(r.angular_rad);
        self.deviation_sum += r.pose_deviation_cm as f64;
        self.deviation_max = self.deviation_max.max(r.pose_deviation_cm);
    }

    /// Mean pose deviation over the frames added (cm).
    pub fn mean_pose_deviation_cm(&self) -> f64 {
        self.deviation_sum / self.frames.max(1) as f64
    }

    /// Mean dislocation over the frames added (cm).
    pub fn mean_dislocation_cm(&self) -> f64 {
        self.dislocation_sum / self.frames.max(1) as f64
    }

    /// Mean angular violation over the frames added (rad).
    pub fn mean_angular_rad(&self) -> f64 {
        self.angular_sum / self.frames.max(1) as f64
    }
}
