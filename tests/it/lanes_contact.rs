//! Contact points W at a time (`contact::lanes`, W = 4, 8, 16, and batches padded to W) against
//! the scalar `ContactPoint::solve`: the same bodies after one projection to rounding, for points that penetrate and slide (normal
//! push and friction, sticking and sliding), points still apart, and a static floor shared by
//! every lane; hard and soft (XPBD compliance and damping); and stacked capsule pairs with
//! stacking's inverse-mass scales.

use rodlab::body::{Body, BodyKind};
use rodlab::contact::{lanes, ContactPoint, Contacts, Softness, Stacking};
use rodlab::math::{Quat, Vec3};
use rodlab::shape::{Axis, Shape};
use rodlab::solver::body::{pair_mut, SharedBodies, SolverBody};

/// Eight capsules just above a floor, each tilted and spinning a little; their first contact
/// point each (found speculatively), and the solver bodies moved to a preview that penetrates
/// and slides by `slide` (m); the points soft as `soft` says.
fn setup(slide: f32, soft: Softness) -> (Vec<SolverBody>, Vec<ContactPoint>) {
    let mut bodies = vec![Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0)];
    for i in 0..8 {
        let x = i as f32;
        let shape = Shape::Capsule {
            half_height: 0.2,
            radius: 0.05,
            axis: Axis::X,
        };
        let mut body = Body::new(format!("c{i}"), BodyKind::Dynamic, shape, 1.0 + 0.3 * x)
            .with_pose(
                Vec3::new(x, 0.06, 0.0),
                Quat::from_rotation_z(0.05 * (x - 3.0)) * Quat::from_rotation_x(0.2 * x),
            );
        body.linear_velocity = Vec3::new(0.3 * (x - 4.0), -1.0, 0.1 * x);
        body.static_friction = 0.2 + 0.1 * x;
        body.dynamic_friction = 0.15 + 0.08 * x;
        bodies.push(body);
    }
    let mut contacts = Contacts::default();
    contacts.detect(&bodies, &Default::default(), 1.0 / 60.0, 0.05);
    contacts.begin_substep(
        &bodies,
        1.0 / 60.0,
        f32::INFINITY,
        soft,
        Stacking::default(),
    );
    let mut points: Vec<ContactPoint> = Vec::new();
    for p in &contacts.points {
        if !points.iter().any(|q| q.body_b == p.body_b) {
            points.push(*p);
        }
    }
    assert_eq!(points.len(), 8, "one point per capsule");
    let mut solver: Vec<SolverBody> = bodies.iter().map(SolverBody::from_body).collect();
    for (i, body) in solver.iter_mut().enumerate().skip(1) {
        // lanes 0-1 stay apart (no push), the others penetrate by up to 3 cm
        let depth = if i <= 2 {
            -0.05
        } else {
            0.005 * i as f32 - 0.01
        };
        body.position += Vec3::new(slide * (i as f32 - 4.0), -0.01 - depth, 0.3 * slide);
    }
    (solver, points)
}

/// Eight pairs of crossed capsules, each upper one resting on its lower one (no floor), their
/// one contact point each with stacking at `rate` (1/m), and the upper bodies' previews moved
/// down into the lower ones and sideways by `slide` (m).
fn stacked_pairs(slide: f32, rate: f32) -> (Vec<SolverBody>, Vec<ContactPoint>) {
    let capsule = |axis| Shape::Capsule {
        half_height: 0.2,
        radius: 0.05,
        axis,
    };
    let mut bodies = Vec::new();
    for i in 0..8 {
        let x = i as f32;
        let lower = Body::new(
            format!("l{i}"),
            BodyKind::Dynamic,
            capsule(Axis::X),
            1.0 + x,
        )
        .with_pose(Vec3::new(x, 0.0, 0.0), Quat::IDENTITY);
        let mut upper = Body::new(format!("u{i}"), BodyKind::Dynamic, capsule(Axis::Z), 2.0)
            .with_pose(Vec3::new(x, 0.101, 0.0), Quat::from_rotation_y(0.1 * x));
        upper.static_friction = 0.3 + 0.05 * x;
        upper.dynamic_friction = 0.2 + 0.05 * x;
        bodies.push(lower);
        bodies.push(upper);
    }
    let mut contacts = Contacts::default();
    contacts.detect(&bodies, &Default::default(), 1.0 / 60.0, 0.05);
    let stacking = Stacking {
        up: Vec3::Y,
        rate,
        max_ratio: f32::INFINITY,
    };
    contacts.begin_substep(
        &bodies,
        1.0 / 60.0,
        f32::INFINITY,
        Softness::default(),
        stacking,
    );
    let points = contacts.points.clone();
    assert_eq!(points.len(), 8, "one point per pair");
    let mut solver: Vec<SolverBody> = bodies.iter().map(SolverBody::from_body).collect();
    for (i, body) in solver.iter_mut().enumerate().skip(1).step_by(2) {
        body.position += Vec3::new(slide, -0.002 * i as f32, 0.5 * slide);
    }
    (solver, points)
}

fn compare(slide: f32, soft: Softness) {
    compare_points(setup(slide, soft), slide);
}

fn compare_points((bodies, points): (Vec<SolverBody>, Vec<ContactPoint>), slide: f32) {
    let mut scalar = bodies.clone();
    let mut scalar_points = points.clone();
    for p in &mut scalar_points {
        let (a, b) = pair_mut(&mut scalar, p.body_a.index(), p.body_b.index());
        p.solve(a, b);
    }
    // (lanes, points a batch): 16 lanes take the eight points as one padded batch, and so do
    // 8 lanes given batches of five and three
    for (width, batch) in [(4usize, 4usize), (8, 8), (16, 8), (8, 5)] {
        let mut lanes_bodies = bodies.clone();
        let mut lanes_points = points.clone();
        let shared = SharedBodies::new(&mut lanes_bodies);
        for chunk in lanes_points.chunks_mut(batch) {
            at_width!(width, lanes::solve_lanes(chunk, shared));
        }
        let (mut position, mut orientation) = (0.0f32, 0.0f32);
        for (x, y) in scalar.iter().zip(&lanes_bodies) {
            position = position.max(x.position.distance(y.position));
            orientation = orientation.max((x.orientation - y.orientation).length());
        }
        let moved = bodies
            .iter()
            .zip(&scalar)
            .map(|(x, y)| x.position.distance(y.position))
            .fold(0.0, f32::max);
        println!("slide {slide}, W={width} ({batch} a batch): position {position:.1e} m, orientation {orientation:.1e} (the solve moved bodies up to {moved:.3} m)");
        assert!(moved > 1e-3, "the setup must make the solve work");
        assert!(position < 1e-5, "W={width}: positions {position} m apart");
        assert!(
            orientation < 1e-4,
            "W={width}: orientations {orientation} apart"
        );
        for (x, y) in bodies.iter().zip(&lanes_bodies) {
            if x.inverse_mass == 0.0 {
                assert_eq!(x.position, y.position, "an immovable body moved");
            }
        }
    }
}

#[test]
fn sticking_points_agree_with_the_scalar_solve() {
    compare(0.001, Softness::default());
}

#[test]
fn sliding_points_agree_with_the_scalar_solve() {
    compare(0.05, Softness::default());
}

#[test]
fn soft_points_agree_with_the_scalar_solve() {
    let soft = Softness {
        hertz: 20.0,
        damping_ratio: 0.7,
    };
    compare(0.001, soft);
    compare(0.05, soft);
}

/// Stacking's scales reach the lanes: stacked pairs solved in lanes move as the scalar solve
/// moves them, and the scales matter (the lower bodies move less than without stacking).
#[test]
fn stacked_points_agree_with_the_scalar_solve() {
    for slide in [0.001, 0.05] {
        compare_points(stacked_pairs(slide, 20.0), slide);
    }
    let lower_moved = |rate| {
        let (before, mut bodies) = {
            let (bodies, _) = stacked_pairs(0.001, rate);
            (bodies.clone(), bodies)
        };
        let (_, mut points) = stacked_pairs(0.001, rate);
        for p in &mut points {
            let (a, b) = pair_mut(&mut bodies, p.body_a.index(), p.body_b.index());
            p.solve(a, b);
        }
        (before.iter().zip(&bodies).step_by(2))
            .map(|(x, y)| x.position.distance(y.position))
            .fold(0.0, f32::max)
    };
    let (plain, stacked) = (lower_moved(0.0), lower_moved(20.0));
    println!("lower bodies moved {plain:.2e} m plain, {stacked:.2e} m stacked");
    assert!(plain > 1e-3 && stacked < 0.25 * plain);
}
