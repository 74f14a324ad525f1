//! Substeps (Macklin et al. 2019, "Small Steps in Physics Simulation"): at a fixed budget of
//! constraint solves per frame, smaller steps hold a heavy chain together better than more
//! iterations; the pendulum's period holds with substeps; the sweep's residual falls with
//! substeps for every method.

use rodlab::body::{Body, BodyKind};
use rodlab::constraint::{BallSocket, JointFlavour};
use rodlab::math::{Quat, Vec3};
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::shape::{Axis, Shape};
use rodlab::sweep::{self, SettingLists, SweepConfig};
use rodlab::world::{ContactDetection, Settings, SolverKind, World};

const LINKS: usize = 20;
const HALF: f32 = 0.05;
const LOAD_RADIUS: f32 = 0.1;

/// 20 capsules of 0.1 kg hanging straight down from a fixed support on exact ball-and-socket
/// joints, a 50 kg sphere on the last one: a 1:500 mass ratio, which iterations alone cannot
/// hold in a frame (the load's pull has to travel 21 joints to the support). The stretch is
/// what is measured, so a joint may come further apart than the health check's default
/// allows (at one step of 20 iterations the last joint stretches to about half a metre).
fn heavy_chain(substeps: u32, iterations: u32, solver: SolverKind) -> World {
    let mut world = World::new(Settings {
        substeps,
        iterations,
        solver,
        max_separation: 2.0,
        ..Settings::default()
    });
    let top = Vec3::new(0.0, 3.0, 0.0);
    let support = Body::new(
        "support",
        BodyKind::Fixed,
        Shape::Sphere { radius: 0.03 },
        1.0,
    );
    let mut previous = world.add_body(support.with_pose(top, Quat::IDENTITY));
    let mut bottom = top;
    for i in 0..LINKS {
        let centre = top - Vec3::Y * (HALF * (2 * i + 1) as f32);
        let capsule = Shape::Capsule {
            half_height: HALF,
            radius: 0.02,
            axis: Axis::Y,
        };
        let link = Body::new(format!("link{i}"), BodyKind::Dynamic, capsule, 0.1);
        let link = world.add_body(link.with_pose(centre, Quat::IDENTITY));
        let anchor = centre + Vec3::Y * HALF;
        let joint = BallSocket::at_world_anchor(
            format!("j{i}"),
            &world.bodies,
            previous,
            link,
            anchor,
            Quat::IDENTITY,
        );
        world.add_constraint(joint.with_flavour(JointFlavour::Exact));
        previous = link;
        bottom = centre - Vec3::Y * HALF;
    }
    let sphere = Shape::Sphere {
        radius: LOAD_RADIUS,
    };
    let load = Body::new("load", BodyKind::Dynamic, sphere, 50.0);
    let centre = bottom - Vec3::Y * LOAD_RADIUS;
    let load = world.add_body(load.with_pose(centre, Quat::IDENTITY));
    let joint = BallSocket::at_world_anchor(
        "load",
        &world.bodies,
        previous,
        load,
        bottom,
        Quat::IDENTITY,
    );
    world.add_constraint(joint.with_flavour(JointFlavour::Exact));
    // a small push sideways, so that the chain swings rather than only hangs
    world.body_mut(load).linear_velocity = Vec3::new(0.5, 0.0, 0.0);
    world
}

/// The total dislocation (cm) of all joints after each frame, averaged over `frames` frames.
fn mean_stretch_cm(substeps: u32, iterations: u32, solver: SolverKind, frames: usize) -> f64 {
    let mut world = heavy_chain(substeps, iterations, solver);
    let mut sum = 0.0f64;
    for _ in 0..frames {
        world.step().unwrap();
        let total: f32 = world
            .constraints
            .iter()
            .map(|c| c.violation(&world.bodies).dislocation)
            .sum();
        sum += 100.0 * total as f64;
    }
    sum / frames as f64
}

/// 20 joint solves per frame, spent as 1x20, 2x10 and 4x5: the chain stretches less as the
/// substeps rise, with either row solver.
#[test]
fn at_equal_solves_per_frame_substeps_stretch_a_heavy_chain_less() {
    for solver in [SolverKind::Scalar, SolverKind::Simd] {
        let budgets = [(1, 20), (2, 10), (4, 5)];
        let stretch: Vec<f64> = budgets
            .iter()
            .map(|&(substeps, iterations)| mean_stretch_cm(substeps, iterations, solver, 300))
            .collect();
        println!(
            "{solver}: mean total dislocation over 5 s, 1x20 {:.3} cm, 2x10 {:.3} cm, 4x5 {:.3} cm",
            stretch[0], stretch[1], stretch[2]
        );
        assert!(
            stretch[0] > stretch[1] && stretch[1] > stretch[2],
            "{solver}: stretch {stretch:?} cm should fall from 1x20 to 2x10 to 4x5"
        );
    }
}

/// A physical pendulum (1 m, 1 kg bob) on an exact joint: the small-amplitude period matches
/// T = 2 pi sqrt(I_pivot / (m g L)) within 1% at 1 and at 4 substeps of a 1/240 s frame.
#[test]
fn pendulum_period_holds_with_substeps() {
    let (length, radius, mass, g) = (1.0f64, 0.05f64, 1.0f64, 9.81f64);
    let inertia_pivot = 0.4 * mass * radius * radius + mass * length * length;
    let analytic = 2.0 * std::f64::consts::PI * (inertia_pivot / (mass * g * length)).sqrt();
    for substeps in [1, 4] {
        let dt = 1.0 / 240.0;
        let mut world = World::new(Settings {
            dt,
            iterations: 10,
            substeps,
            ..Settings::default()
        });
        let pivot = Vec3::new(0.0, 2.0, 0.0);
        let fixed = Body::new(
            "pivot",
            BodyKind::Fixed,
            Shape::Sphere { radius: 0.02 },
            1.0,
        );
        let anchor = world.add_body(fixed.with_pose(pivot, Quat::IDENTITY));
        let amplitude = 0.05f32;
        let start = pivot + length as f32 * Vec3::new(amplitude.sin(), -amplitude.cos(), 0.0);
        let bob = Body::new(
            "bob",
            BodyKind::Dynamic,
            Shape::Sphere { radius: 0.05 },
            1.0,
        );
        let bob = world.add_body(bob.with_pose(start, Quat::IDENTITY));
        let joint =
            BallSocket::at_world_anchor("hinge", &world.bodies, anchor, bob, pivot, Quat::IDENTITY);
        world.add_constraint(joint.with_flavour(JointFlavour::Exact));
        // mean period from upward zero crossings of the bob's x over 12 s
        let mut crossings = Vec::new();
        let mut previous = world.body(bob).position.x;
        for _ in 0..(12.0 / dt) as usize {
            world.step().unwrap();
            let x = world.body(bob).position.x;
            if previous < 0.0 && x >= 0.0 {
                let fraction = (previous / (previous - x)) as f64;
                crossings.push(world.time - dt as f64 * (1.0 - fraction));
            }
            previous = x;
        }
        assert!(crossings.len() >= 3, "substeps {substeps}: {crossings:?}");
        let period = (crossings.last().unwrap() - crossings[0]) / (crossings.len() - 1) as f64;
        let error = (period - analytic).abs() / analytic;
        println!(
            "substeps {substeps}: period {period:.5} s, analytic {analytic:.5} s ({:.3}%)",
            100.0 * error
        );
        assert!(
            error < 0.01,
            "substeps {substeps}: period {period:.5} s vs analytic {analytic:.5} s ({:.3}%)",
            100.0 * error
        );
    }
}

/// The sweep over substeps 1, 2, 4 at 4 iterations each: for every method the residual falls
/// with each doubling of the substeps; rows carry their substeps and method labels.
#[test]
fn sweep_residual_falls_with_substeps_for_every_method() {
    let scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/passive_bending.toml"
    ))
    .unwrap();
    let config = SweepConfig {
        settings: SettingLists {
            iterations: vec![4],
            substeps: vec![1, 2, 4],
            ..Default::default()
        },
        frames: Some(120),
        repeats: 1,
        ..Default::default()
    };
    let rows: Vec<_> = sweep::combinations(&scene.def, &config)
        .iter()
        .map(|o| sweep::run_one(&scene, o, 1).unwrap())
        .collect();
    assert_eq!(rows.len(), 3 * 2 * 3);
    for line in rows.chunks(3) {
        let base = &line[0].method;
        assert_eq!(
            [&line[1].method, &line[2].method],
            [&format!("{base} x2"), &format!("{base} x4")]
        );
        assert_eq!(
            line.iter().map(|r| r.settings.substeps).collect::<Vec<_>>(),
            [1, 2, 4]
        );
        let residual: Vec<f64> = line.iter().map(|r| r.mean_dislocation_cm).collect();
        println!("{base}: mean dislocation at 1, 2, 4 substeps of 4 iterations: {residual:.4?} cm");
        assert!(line.iter().all(|r| r.failed.is_none()), "{line:?}");
        assert!(
            residual[0] > residual[1] && residual[1] > residual[2],
            "{base}: residual {residual:?} should fall with substeps"
        );
    }
    // each (method, substeps) is its own line on the chart, through its iterations
    let chart = sweep::chart("passive_bending", &rows, "test");
    assert_eq!(chart.series.len(), rows.len());
}

/// The simd row solver is the same maths: in the sweep, its rows carry their own label and
/// land close to the scalar ones.
#[test]
fn sweep_solver_dimension_labels_simd_rows() {
    let scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/passive_bending.toml"
    ))
    .unwrap();
    let config = SweepConfig {
        settings: SettingLists {
            iterations: vec![8],
            solver: vec![SolverKind::Scalar, SolverKind::Simd],
            substeps: vec![2],
            ..Default::default()
        },
        spines: vec![SpineKind::Rod],
        joints: vec![JointFlavour::Exact],
        frames: Some(60),
        repeats: 1,
        ..Default::default()
    };
    let rows: Vec<_> = sweep::combinations(&scene.def, &config)
        .iter()
        .map(|o| sweep::run_one(&scene, o, 1).unwrap())
        .collect();
    let labels: Vec<(&str, SolverKind)> = rows
        .iter()
        .map(|r| (r.method.as_str(), r.settings.solver))
        .collect();
    assert_eq!(
        labels,
        [
            ("rod/exact x2", SolverKind::Scalar),
            ("rod/exact simd x2", SolverKind::Simd)
        ]
    );
    let (scalar, simd) = (rows[0].mean_dislocation_cm, rows[1].mean_dislocation_cm);
    assert!(
        (scalar - simd).abs() <= 0.05 * scalar.max(1e-6),
        "scalar {scalar} cm, simd {simd} cm"
    );
}

/// With one substep, detecting contacts every substep is detecting them once a frame: the same
/// poses, the same reach (dt), so the paper's method is unchanged bit for bit (the drop, 60
/// frames, both spines).
#[test]
fn one_substep_detecting_every_substep_is_the_papers_detection() {
    for spine in [SpineKind::Chain3, SpineKind::Rod] {
        let hash = |detection: ContactDetection| {
            let (mut lab, frames) = crate::common::lab_with(
                "ragdoll_drop",
                rodlab::sim::Overrides {
                    spine: Some(spine),
                    substeps: Some(1),
                    contact_detection: Some(detection),
                    frames: Some(60),
                    ..Default::default()
                },
            );
            let report = rodlab::sim::run(&mut lab, frames, &mut rodlab::sim::NoObserver);
            report.unwrap().state_hash
        };
        assert_eq!(
            hash(ContactDetection::Frame),
            hash(ContactDetection::Substep),
            "{spine}: one substep must detect as the paper does"
        );
    }
}
