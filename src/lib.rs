//! rodlab: the SCA 2013 paper *Rod Constraints for Simplified Ragdolls* as a physics lab.
//!
//! ```text
//! scene file (TOML) -> scene::Scene::build -> Lab { world: World (physics only), ragdolls }
//!                                                |
//!        solver::Solver::step: detect once, N substeps x M iterations over rows per kind,
//!        coloured, scalar or SIMD lanes, on rayon's threads (no rerun, no allocation)
//!                                                |
//!                        metrics (residuals, energies)  ->  sim::run (the loop)
//!                                                |
//!                        record (the only rerun user) -> recordings/<scene>.rrd
//! ```
//!
//! Module map:
//! - [`math`]: glam re-exports, exponential map, swing-twist helpers;
//! - [`shape`], [`body`]: shapes, mass and inertia, rigid bodies;
//! - [`solver_body`]: the solver's hot 96-byte body; [`lanes`]: W-wide SIMD maths (Lane, V3, Q),
//!   the lane width chosen at run time; [`machine`]: the CPU named beside timings;
//! - [`constraint`]: one file per constraint kind (prepare, solve, measure), plus its `*_lanes`
//!   batched solve;
//! - [`contact`]: broad phase, narrow phase and contact points with friction;
//! - [`solver`]: the step, its order written as a numbered list; [`solver::graph`]: colouring;
//! - [`sleep`]: islands of still bodies taken out of the step;
//! - [`world`]: bodies + constraints + contacts + settings, failure detection; physics only;
//! - [`ragdoll`]: the reference humanoid builder (spines chain3 | single | rod);
//! - [`rig`]: game rigs, their animations and animation skeletons, read from Jolt's text object
//!   streams;
//! - [`skeleton`]: the animation bones posed back from the physics (§6);
//! - [`lab`]: the world plus what the experiments measure and draw (ragdolls, their skeletons
//!   and target poses); what scenes build and the run loop, metrics and recorder take;
//! - [`playback`]: a character's clip played on kinematic bodies until its handover (§6);
//! - [`scene`]: TOML scene definitions and their checks;
//! - [`kinematics`]: chain-versus-rod end loci (Fig. 6);
//! - [`metrics`]: residual dislocation (cm) and angular violation (rad), energy;
//! - [`sim`]: the run loop and its observer hook;
//! - [`sweep`]: speed against accuracy over methods and iterations; [`chart`]: its SVG chart;
//! - [`tune`]: the rod's bend and twist settings side by side, and matching a bend;
//! - [`shard`]: a sweep's or a tuning grid's combinations split between processes;
//! - [`stress`]: the stability suite, a verdict per method;
//! - [`record`]: Rerun recording; [`cli`]: the command line.

// `!(x > 0.0)` is how this crate rejects NaN along with the out-of-range values: on purpose,
// so clippy's advice to write `x <= 0.0` (which lets NaN through) is off.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
#![deny(missing_docs)]

pub mod body;
#[cfg(feature = "record")]
pub mod chart;
#[cfg(feature = "record")]
pub mod cli;
pub mod constraint;
pub mod contact;
pub mod csv_table;
pub mod kinematics;
pub mod lab;
pub mod lanes;
pub mod machine;
pub mod math;
pub mod metrics;
/// Rapier as a peer engine for the sweep (feature `rapier`).
#[cfg(feature = "rapier")]
pub mod peer;
pub mod playback;
pub mod ragdoll;
#[cfg(feature = "record")]
pub mod record;
pub mod rig;
pub mod scene;
pub mod shape;
pub mod shard;
pub mod sim;
pub mod skeleton;
pub mod sleep;
pub mod solver;
pub mod solver_body;
pub mod stress;
#[cfg(feature = "record")]
pub mod sweep;
#[cfg(feature = "record")]
pub mod tune;
pub mod world;
