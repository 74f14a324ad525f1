//! Analytic check: a small-amplitude physical pendulum on an exact ball-and-socket joint swings
//! with period T = 2 pi sqrt(I_pivot / (m g L)) within 1% at dt = 1/240.

use rodlab::body::{Body, BodyKind};
use rodlab::constraint::{BallSocket, JointFlavour};
use rodlab::math::{Quat, Vec3};
use rodlab::shape::Shape;
use rodlab::world::{Settings, World};

fn pendulum(dt: f32, length: f32, amplitude: f32) -> World {
    let mut world = World::new(Settings {
        dt,
        iterations: 10,
        ..Settings::default()
    });
    let pivot = Vec3::new(0.0, 2.0, 0.0);
    let anchor = world.add_body(
        Body::new(
            "pivot",
            BodyKind::Fixed,
            Shape::Sphere { radius: 0.02 },
            1.0,
        )
        .with_pose(pivot, Quat::IDENTITY),
    );
    let bob_position = pivot + length * Vec3::new(amplitude.sin(), -amplitude.cos(), 0.0);
    let bob = world.add_body(
        Body::new(
            "bob",
            BodyKind::Dynamic,
            Shape::Sphere { radius: 0.05 },
            1.0,
        )
        .with_pose(bob_position, Quat::IDENTITY),
    );
    let joint =
        BallSocket::at_world_anchor("hinge", &world.bodies, anchor, bob, pivot, Quat::IDENTITY)
            .with_flavour(JointFlavour::Exact);
    world.add_constraint(joint);
    world
}

/// Mean period from upward zero crossings of the bob's x coordinate.
fn measured_period(world: &mut World, seconds: f32) -> f64 {
    let bob = world.find_body("bob").unwrap();
    let steps = (seconds / world.settings.dt) as usize;
    let mut crossings = Vec::new();
    let mut previous = world.body(bob).position.x;
    for _ in 0..steps {
        world.step().unwrap();
        let x = world.body(bob).position.x;
        if previous < 0.0 && x >= 0.0 {
            // linear interpolation of the crossing time
            let fraction = previous / (previous - x);
            crossings.push(world.time - world.settings.dt as f64 * (1.0 - fraction as f64));
        }
        previous = x;
    }
    assert!(crossings.len() >= 3, "too few swings: {crossings:?}");
    (crossings.last().unwrap() - crossings[0]) / (crossings.len() - 1) as f64
}

#[test]
fn small_amplitude_period_matches_analytic() {
    let (length, radius, mass, g) = (1.0f64, 0.05f64, 1.0f64, 9.81f64);
    let inertia_pivot = 0.4 * mass * radius * radius + mass * length * length;
    let analytic = 2.0 * std::f64::consts::PI * (inertia_pivot / (mass * g * length)).sqrt();
    let mut world = pendulum(1.0 / 240.0, length as f32, 0.05);
    let measured = measured_period(&mut world, 12.0);
    let error = (measured - analytic).abs() / analytic;
    assert!(
        error < 0.01,
        "period {measured:.5} s vs analytic {analytic:.5} s ({:.3}%)",
        100.0 * error
    );
}

#[test]
fn pendulum_keeps_its_length() {
    let mut world = pendulum(1.0 / 240.0, 1.0, 0.5);
    let bob = world.find_body("bob").unwrap();
    for _ in 0..2400 {
        world.step().unwrap();
        let length = (world.body(bob).position - Vec3::new(0.0, 2.0, 0.0)).length();
        assert!((length - 1.0).abs() < 1e-4, "length drifted to {length}");
    }
}
