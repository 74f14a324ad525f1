//! rodlab's integration tests, as one binary: each file below was a test binary of its own,
//! and each linked the `rerun` crate. Run one file's tests with
//! `cargo test --release --test it <file>::`.

#[macro_use]
mod common;
mod chain;
mod character;
mod cli_set;
mod conservation;
mod contact_gaps;
mod contacts;
mod controllability;
mod hinge;
mod humanoid;
mod io_faults;
mod kinematics;
mod lanes_contact;
mod lanes_joint;
mod lanes_rod;
mod methods;
mod override_bounds;
mod passive_bending;
#[cfg(feature = "rapier")]
mod peer;
mod pendulum;
mod product_text;
mod ragdoll_drop;
mod ragdoll_rain;
mod recording;
mod rod;
mod rod_stiffness;
mod save_guard;
mod scalar_simd;
mod scene_errors;
mod scene_fuzz;
mod scene_limits;
mod skeleton;
mod spin_limit;
mod stress;
mod substeps;
mod sweep;
mod tune;
