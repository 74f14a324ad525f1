//! Criterion benchmarks: ns per constraint solve, scalar and SIMD (W = 4 and W = 8), for
//! ball-and-socket joints (cheap, exact, exact with limits) and the rod (bend, twist, curve and
//! length in one function), 64 independent constraints a batch; then one passive-bending step
//! per spine. After criterion's report, a summary table with the rod/cheap ratio per solver.
//! Run with `cargo bench --bench solver`.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use rodlab::body::{Body, BodyId, BodyKind};
use rodlab::constraint::{
    ball_socket_lanes, rod_lanes, AngularLimit, BallSocket, JointFlavour, JointRow, Rod, RodRow,
};
use rodlab::math::{Quat, Vec3};
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::shape::{Axis, Shape};
use rodlab::sim::{self, NoObserver, Overrides};
use rodlab::solver::body::{pair_mut, SharedBodies, SolverBody};
use rodlab::solver::RowBodies;
use std::time::Instant;

const COUNT: usize = 64;

fn capsule(name: String, mass: f32, radius: f32) -> Body {
    let shape = Shape::Capsule {
        half_height: 0.08,
        radius,
        axis: Axis::Y,
    };
    Body::new(name, BodyKind::Dynamic, shape, mass)
}

/// `COUNT` independent pairs of capsules joined at a shared anchor, each pair then displaced
/// and turned off its joint (and past its limits), so every solve does real work.
fn dislocated_joints(flavour: JointFlavour, limits: bool) -> (Vec<SolverBody>, Vec<JointRow>) {
    let mut bodies = Vec::new();
    let mut rows = Vec::new();
    for i in 0..COUNT {
        let x = i as f32;
        bodies.push(
            capsule(format!("a{i}"), 1.0, 0.03).with_pose(Vec3::new(x, 0.0, 0.0), Quat::IDENTITY),
        );
        bodies.push(
            capsule(format!("b{i}"), 1.0, 0.03).with_pose(Vec3::new(x, -0.2, 0.0), Quat::IDENTITY),
        );
        let frame = Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
        let ids = (BodyId(2 * i as u32), BodyId(2 * i as u32 + 1));
        let anchor = Vec3::new(x, -0.1, 0.0);
        let mut joint =
            BallSocket::at_world_anchor(format!("j{i}"), &bodies, ids.0, ids.1, anchor, frame)
                .with_flavour(flavour);
        if limits {
            joint = joint.with_limit(AngularLimit::cone(0.3, -0.2, 0.2));
        }
        let mut row = joint.prepare();
        let wobble = (x * 1.7).sin();
        let b = &mut bodies[2 * i + 1];
        let position = b.position + Vec3::new(0.02 * wobble, 0.01, -0.015 * wobble);
        b.set_pose(
            position,
            Quat::from_rotation_z(0.5 * wobble) * Quat::from_rotation_x(0.3),
        );
        row.begin_substep(&bodies);
        rows.push(row);
    }
    (bodies.iter().map(SolverBody::from_body).collect(), rows)
}

/// `COUNT` independent pelvis-chest pairs joined by rods, each bent, twisted and stretched off
/// its rest state.
fn perturbed_rods() -> (Vec<SolverBody>, Vec<RodRow>) {
    let mut bodies = Vec::new();
    let mut rows = Vec::new();
    for i in 0..COUNT {
        let x = i as f32;
        bodies.push(
            capsule(format!("p{i}"), 14.5, 0.1).with_pose(Vec3::new(x, 1.0, 0.0), Quat::IDENTITY),
        );
        bodies.push(
            capsule(format!("c{i}"), 18.1, 0.12)
                .with_pose(Vec3::new(x, 1.385, 0.0), Quat::IDENTITY),
        );
        let ids = (BodyId(2 * i as u32), BodyId(2 * i as u32 + 1));
        let mut rod = Rod::instantiate(format!("r{i}"), &bodies, ids.0, ids.1, Vec3::Z).unwrap();
        rod.alpha_bend = 0.1;
        rod.alpha_twist = 0.5;
        rows.push(rod.prepare());
        let wobble = (x * 1.7).sin();
        let chest = &mut bodies[2 * i + 1];
        let pose = chest.position + Vec3::new(0.01 * wobble, -0.02, 0.05);
        chest.set_pose(
            pose,
            Quat::from_rotation_x(0.4 + 0.1 * wobble) * Quat::from_rotation_y(0.2),
        );
    }
    (bodies.iter().map(SolverBody::from_body).collect(), rows)
}

#[derive(Clone, Copy, PartialEq)]
enum Width {
    Scalar,
    W4,
    W8,
}

const WIDTHS: [(&str, Width); 3] = [
    ("scalar", Width::Scalar),
    ("simd4", Width::W4),
    ("simd8", Width::W8),
];

/// Solves `rows` once: one by one with the scalar kernel, or W at a time with a lane kernel.
fn solve_rows<T: RowBodies>(
    rows: &mut [T],
    bodies: &mut [SolverBody],
    width: Width,
    scalar: fn(&T, &mut SolverBody, &mut SolverBody),
    lanes: [fn(&mut [T], SharedBodies); 2],
) {
    let (kernel, w) = match width {
        Width::Scalar => {
            for row in rows.iter() {
                let (a, b) = row.bodies();
                let (a, b) = pair_mut(bodies, a as usize, b as usize);
                scalar(row, a, b);
            }
            return;
        }
        Width::W4 => (lanes[0], 4),
        Width::W8 => (lanes[1], 8),
    };
    let shared = SharedBodies::new(bodies);
    rows.chunks_exact_mut(w).for_each(|c| kernel(c, shared));
}

/// One benchmarked batch: `COUNT` independent constraints of one kind and their bodies.
#[derive(Clone)]
enum Batch {
    Joints(Vec<SolverBody>, Vec<JointRow>),
    Rods(Vec<SolverBody>, Vec<RodRow>),
}

impl Batch {
    /// Joints of a flavour, with or without limits; `None`: rods.
    fn new(joint: Option<(JointFlavour, bool)>) -> Self {
        match joint {
            Some((flavour, limits)) => {
                let (bodies, rows) = dislocated_joints(flavour, limits);
                Batch::Joints(bodies, rows)
            }
            None => {
                let (bodies, rows) = perturbed_rods();
                Batch::Rods(bodies, rows)
            }
        }
    }

    fn solve(&mut self, width: Width) {
        match self {
            Batch::Joints(bodies, rows) => solve_rows(
                rows,
                bodies,
                width,
                JointRow::solve,
                [
                    ball_socket_lanes::solve_lanes::<wide::f32x4>,
                    ball_socket_lanes::solve_lanes::<wide::f32x8>,
                ],
            ),
            Batch::Rods(bodies, rows) => solve_rows(
                rows,
                bodies,
                width,
                RodRow::solve,
                [
                    rod_lanes::solve_lanes::<wide::f32x4>,
                    rod_lanes::solve_lanes::<wide::f32x8>,
                ],
            ),
        }
    }
}

/// The benchmarked kinds: a joint flavour and whether it has limits, or the rod.
fn cases() -> Vec<(&'static str, Option<(JointFlavour, bool)>)> {
    vec![
        ("cheap", Some((JointFlavour::Cheap, false))),
        ("exact", Some((JointFlavour::Exact, false))),
        ("exact_with_limits", Some((JointFlavour::Exact, true))),
        ("rod", None),
    ]
}

fn constraint_solves(c: &mut Criterion) {
    let mut group = c.benchmark_group("constraint_solve");
    group.throughput(Throughput::Elements(COUNT as u64));
    for (label, joint) in cases() {
        let batch = Batch::new(joint);
        for (solver, width) in WIDTHS {
            group.bench_function(format!("{label}/{solver}"), |b| {
                b.iter_batched_ref(
                    || batch.clone(),
                    |batch| batch.solve(width),
                    BatchSize::SmallInput,
                )
            });
        }
    }
    group.finish();
    summary();
}

/// ns per constraint: the fastest of many timed rounds of 64 solves (each on a fresh copy).
fn ns_per_solve(mut round: impl FnMut() -> std::time::Duration) -> f64 {
    (0..2000).map(|_| round()).min().unwrap().as_nanos() as f64 / COUNT as f64
}

/// The side-by-side table the issue asks for: scalar and SIMD per kind, and rod/cheap.
fn summary() {
    println!(
        "\nns per constraint (fastest of 2000 rounds of {COUNT}), machine: {}",
        rodlab::sweep::machine_name()
    );
    println!(
        "{:<20} {:>8} {:>8} {:>8}",
        "kind", "scalar", "simd4", "simd8"
    );
    let mut table = Vec::new();
    for (label, joint) in cases() {
        let batch = Batch::new(joint);
        let mut row = Vec::new();
        for (_, width) in WIDTHS {
            row.push(ns_per_solve(|| {
                let mut fresh = batch.clone();
                let start = Instant::now();
                fresh.solve(width);
                let time = start.elapsed();
                std::hint::black_box(&fresh);
                time
            }));
        }
        println!(
            "{:<20} {:>8.1} {:>8.1} {:>8.1}",
            label, row[0], row[1], row[2]
        );
        table.push(row);
    }
    let (cheap, rod) = (&table[0], &table[3]);
    println!(
        "rod/cheap: scalar {:.2}, simd4 {:.2}, simd8 {:.2} (paper §7: 60/20 = 3)",
        rod[0] / cheap[0],
        rod[1] / cheap[1],
        rod[2] / cheap[2]
    );
    println!(
        "simd speed-up over scalar: cheap {:.2}x/{:.2}x, exact {:.2}x/{:.2}x, limits {:.2}x/{:.2}x, rod {:.2}x/{:.2}x (W=4/W=8)\n",
        table[0][0] / table[0][1], table[0][0] / table[0][2],
        table[1][0] / table[1][1], table[1][0] / table[1][2],
        table[2][0] / table[2][1], table[2][0] / table[2][2],
        table[3][0] / table[3][1], table[3][0] / table[3][2],
    );
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
        let mut lab = variant.build().unwrap();
        sim::run(&mut lab, 30, &mut NoObserver).unwrap(); // get it moving
        let world = lab.world;
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

criterion_group!(benches, constraint_solves, passive_bending_step);
criterion_main!(benches);
