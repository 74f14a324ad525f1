//! The angular speed limit (`angular_speed_limit`, Jolt's `mMaxAngularVelocity`, PhysX's
//! `maxAngularVelocity`): a faster spin is scaled down to the limit each substep, a slower one
//! is untouched, and the limit turns a spin-up in the drop's pile, which the paper's method
//! stops as an explosion, into a finished run.

use rodlab::body::{Body, BodyKind};
use rodlab::constraint::JointFlavour;
use rodlab::math::Vec3;
use rodlab::ragdoll::SpineKind;
use rodlab::shape::Shape;
use rodlab::sim::{self, Overrides};
use rodlab::world::{Settings, SolverKind, World};

/// A free brick spinning about its major principal axis (a steady spin: the gyroscopic term
/// keeps it) at `spin` rad/s, after one frame under `limit`: its angular speed.
fn spin_after_one_frame(spin: f32, limit: f32) -> f32 {
    let mut world = World::new(Settings {
        gravity: Vec3::ZERO,
        angular_speed_limit: limit,
        ..Settings::default()
    });
    let shape = Shape::Cuboid {
        half_extents: Vec3::new(0.4, 0.2, 0.1),
    };
    let mut body = Body::new("brick", BodyKind::Dynamic, shape, 3.0);
    body.angular_velocity = Vec3::new(0.0, 0.0, spin);
    let id = world.add_body(body);
    world.step().unwrap();
    world.body(id).angular_velocity.length()
}

#[test]
fn the_limit_scales_a_faster_spin_down_and_leaves_a_slower_one() {
    // 150 rad/s turns 2.5 rad a 1/60 s frame: under half a turn, so the velocity derived from
    // the poses can still tell it (past pi/h it aliases, as every position-based solver's does)
    let unlimited = spin_after_one_frame(150.0, f32::INFINITY);
    assert!(
        (unlimited - 150.0).abs() < 1e-3,
        "a free steady spin kept: {unlimited}"
    );
    let limited = spin_after_one_frame(150.0, 100.0);
    assert!(
        (limited - 100.0).abs() < 1e-3,
        "150 rad/s limited to 100: {limited}"
    );
    assert_eq!(
        spin_after_one_frame(50.0, 100.0),
        spin_after_one_frame(50.0, f32::INFINITY),
        "a spin under the limit is untouched, bit for bit"
    );
}

/// The drop at 4 substeps of 1 iteration with exact joints, 30 Hz soft contacts and stacking
/// (the sweep's rod line that spins limbs up toward the 500 rad/s explosion bound,
/// docs/landings.md): with a 100 rad/s limit the landing runs its 150 frames, and ends in its
/// committed state (one pile is a chaotic sample: the hash pins it).
#[test]
fn the_limit_carries_the_drops_known_spin_up_through() {
    let run = |limit: f32| {
        let (mut lab, frames) = crate::common::lab_with(
            "ragdoll_drop",
            Overrides {
                spine: Some(SpineKind::Rod),
                substeps: Some(4),
                iterations: Some(1),
                joint_flavour: Some(JointFlavour::Exact),
                solver: Some(SolverKind::Simd),
                contact_hertz: Some(30.0),
                contact_stacking: Some(10.0),
                angular_speed_limit: Some(limit),
                frames: Some(150),
                ..Default::default()
            },
        );
        sim::run(&mut lab, frames, &mut sim::NoObserver)
    };
    let report = run(100.0).expect("the 100 rad/s limit keeps the pile from exploding");
    assert_eq!(report.total_dislocation_cm.len(), 150);
    crate::common::assert_state_hash(
        "the limited landing",
        report.state_hash,
        0x566c_9562_d368_c37b,
    );
}
