//! Criterion benchmarks: ns per constraint solve (ball-and-socket cheap, exact, exact with
//! limits; the rod with bend and twist) in one group, and one passive-bending step per spine. Run with `cargo bench --bench solver`.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use rodlab::body::BodyId;
use rodlab::body::{Body, BodyKind};
use rodlab::constraint::{AngularLimit, BallSocket, Constraint, JointFlavour, Rod};
use rodlab::math::{Quat, Vec3};
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::shape::{Axis, Shape};
use rodlab::sim::{self, NoObserver, Overrides};

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

/// `JOINTS` independent pelvis-chest pairs joined by rods, each bent, twisted and stretched off
/// its rest state.
fn perturbed_rods() -> (Vec<Body>, Vec<Constraint>) {
    let mut bodies = Vec::new();
    let mut constraints = Vec::new();
    for i in 0..JOINTS {
        let x = i as f32;
        let pelvis = Body::new(
            format!("p{i}"),
            BodyKind::Dynamic,
            Shape::Capsule {
                half_height: 0.07,
                radius: 0.1,
                axis: Axis::X,
            },
            14.5,
        )
        .with_pose(Vec3::new(x, 1.0, 0.0), Quat::IDENTITY);
        let chest = Body::new(
            format!("c{i}"),
            BodyKind::Dynamic,
            Shape::Capsule {
                half_height: 0.07,
                radius: 0.12,
                axis: Axis::X,
            },
            18.1,
        )
        .with_pose(Vec3::new(x, 1.385, 0.0), Quat::IDENTITY);
        bodies.push(pelvis);
        bodies.push(chest);
        let mut rod = Rod::instantiate(
            format!("r{i}"),
            &bodies,
            BodyId(2 * i as u32),
            BodyId(2 * i as u32 + 1),
            Vec3::Z,
        )
        .unwrap();
        rod.alpha_bend = 0.1;
        rod.alpha_twist = 0.5;
        constraints.push(Constraint::Rod(rod));
        let wobble = (x * 1.7).sin();
        let chest = &mut bodies[2 * i + 1];
        let pose = chest.position + Vec3::new(0.01 * wobble, -0.02, 0.05);
        chest.set_pose(
            pose,
            Quat::from_rotation_x(0.4 + 0.1 * wobble) * Quat::from_rotation_y(0.2),
        );
    }
    (bodies, constraints)
}

fn joint_solves(c: &mut Criterion) {
    let mut group = c.benchmark_group("constraint_solve");
    group.throughput(Throughput::Elements(JOINTS as u64));
    for (label, flavour, limits) in [
        ("cheap", JointFlavour::Cheap, false),
        ("exact", JointFlavour::Exact, false),
        ("exact_with_limits", JointFlavour::Exact, true),
        ("rod", JointFlavour::Exact, false),
    ] {
        let (bodies, constraints) = if label == "rod" {
            perturbed_rods()
        } else {
            dislocated_chain(flavour, limits)
        };
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

/// One 20-iteration step of the passive-bending scene with both ragdolls given one spine.
fn passive_bending_step(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml");
    let scene = Scene::load(path).unwrap();
    let mut group = c.benchmark_group("passive_bending_step");
    for (label, spine, flavour) in [
        ("chain3_cheap", SpineKind::Chain3, JointFlavour::Cheap),
        ("chain3_exact", SpineKind::Chain3, JointFlavour::Exact),
        ("rod_cheap_limbs", SpineKind::Rod, JointFlavour::Cheap),
    ] {
        let mut variant = scene.clone();
        Overrides {
            spine: Some(spine),
            joint_flavour: Some(flavour),
            ..Default::default()
        }
        .apply(&mut variant.def);
        let mut world = variant.build().unwrap();
        sim::run(&mut world, 30, &mut NoObserver).unwrap(); // get it moving
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
