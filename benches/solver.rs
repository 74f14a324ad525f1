//! Criterion benchmarks: ns per ball-and-socket solve (cheap, exact, exact with limits) and one
//! passive-bending step. Run with `cargo bench --bench solver`.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use rodlab::body::{Body, BodyKind};
use rodlab::constraint::{AngularLimit, BallSocket, Constraint, JointFlavour};
use rodlab::math::{Quat, Vec3};
use rodlab::scene::Scene;
use rodlab::shape::{Axis, Shape};
use rodlab::sim::{self, NoObserver};

const JOINTS: usize = 64;

/// A chain of capsules, each displaced and turned off its joint, so every solve does real work.
fn dislocated_chain(flavour: JointFlavour, limits: bool) -> (Vec<Body>, Vec<Constraint>) {
    let mut bodies = Vec::new();
    let mut constraints = Vec::new();
    for i in 0..=JOINTS {
        let centre = Vec3::new(0.0, -0.2 * i as f32, 0.0);
        bodies.push(
            Body::new(
                format!("b{i}"),
                BodyKind::Dynamic,
                Shape::Capsule {
                    half_height: 0.08,
                    radius: 0.03,
                    axis: Axis::Y,
                },
                1.0,
            )
            .with_pose(centre, Quat::IDENTITY),
        );
    }
    for i in 0..JOINTS {
        let anchor = Vec3::new(0.0, -0.2 * i as f32 - 0.1, 0.0);
        let mut joint = BallSocket::at_world_anchor(
            format!("j{i}"),
            &bodies,
            rodlab::body::BodyId(i as u32),
            rodlab::body::BodyId(i as u32 + 1),
            anchor,
            Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2),
        )
        .with_flavour(flavour);
        if limits {
            joint = joint.with_limit(AngularLimit::cone(0.3, -0.2, 0.2));
        }
        constraints.push(Constraint::BallSocket(joint));
    }
    for (i, body) in bodies.iter_mut().enumerate() {
        let wobble = (i as f32 * 1.7).sin();
        let pose_offset = Vec3::new(0.02 * wobble, 0.01, -0.015 * wobble);
        let position = body.position + pose_offset;
        body.set_pose(
            position,
            Quat::from_rotation_z(0.5 * wobble) * Quat::from_rotation_x(0.3),
        );
    }
    (bodies, constraints)
}

fn joint_solves(c: &mut Criterion) {
    let mut group = c.benchmark_group("ball_socket_solve");
    group.throughput(Throughput::Elements(JOINTS as u64));
    for (label, flavour, limits) in [
        ("cheap", JointFlavour::Cheap, false),
        ("exact", JointFlavour::Exact, false),
        ("exact_with_limits", JointFlavour::Exact, true),
    ] {
        let (bodies, constraints) = dislocated_chain(flavour, limits);
        group.bench_function(label, |b| {
            b.iter_batched_ref(
                || bodies.clone(),
                |bodies| {
                    for constraint in &constraints {
                        constraint.solve(bodies);
                    }
                },
                BatchSize::SmallInput,
            )
        });
    }
    group.finish();
}

fn passive_bending_step(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml");
    let scene = Scene::load(path).unwrap();
    let mut group = c.benchmark_group("passive_bending_step");
    for flavour in [JointFlavour::Cheap, JointFlavour::Exact] {
        let mut def_scene = scene.clone();
        rodlab::sim::Overrides {
            joint_flavour: Some(flavour),
            ..Default::default()
        }
        .apply(&mut def_scene.def);
        let mut world = def_scene.build().unwrap();
        sim::run(&mut world, 30, &mut NoObserver).unwrap(); // get it moving
        let label = format!("{flavour:?}_20_iterations").to_lowercase();
        group.bench_function(label, |b| {
            b.iter_batched_ref(
                || world.clone(),
                |w| w.step().unwrap(),
                BatchSize::SmallInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, joint_solves, passive_bending_step);
criterion_main!(benches);
