//! Overlap and its recovery: the push-out speed limit, a soft contact as a spring of its
//! frequency, an overlapping block of 27 boxes, the overlap found afresh, and the
//! penetration bound that stops a run.

use super::*;

/// Box2D's `maxContactPushSpeed` (`contact_push_speed`): a box started half sunk into the one
/// below is pushed out no faster than the limit, where the paper-era projection (no limit)
/// throws it out at twice the speed (measured 4.0 against 2.0 m/s); either way the overlap is
/// gone, and after 5 s both boxes are slower than the sleep threshold (boxes started
/// half overlapping were still moving after 5 s; measured 0 and 0.014 m/s).
#[test]
fn a_sunk_box_is_pushed_out_no_faster_than_the_push_speed() {
    let run = |push_speed: f32| {
        let mut world = World::new(Settings {
            contact_push_speed: push_speed,
            iterations: 20,
            ..settings()
        });
        plane(&mut world, Quat::IDENTITY);
        let below = sleepy_box(&mut world, "below", Vec3::new(0.0, 0.1, 0.0));
        // half its height into the box below, a little off centre
        let above = sleepy_box(&mut world, "above", Vec3::new(0.1, 0.2, 0.05));
        let mut fastest = 0.0f32;
        for _ in 0..300 {
            world.step().unwrap();
            for id in [below, above] {
                fastest = fastest.max(world.body(id).linear_velocity.length());
            }
        }
        let speed = [below, above].map(|id| world.body(id).linear_velocity.length());
        let overlap = world.contacts.max_penetration(&world.bodies);
        println!(
            "push speed {push_speed}: fastest {fastest:.2} m/s; after 5 s {speed:.3?} m/s, \
             {overlap:.4} m deep"
        );
        assert!(overlap < 0.01, "still {overlap} m deep");
        (fastest, speed[0].max(speed[1]))
    };
    let (unlimited, unlimited_after) = run(f32::INFINITY);
    let (limited, limited_after) = run(3.0);
    assert!(limited <= 3.0, "limited: {limited} m/s");
    assert!(
        unlimited > 1.5 * limited,
        "unlimited {unlimited} m/s, limited {limited} m/s"
    );
    // Both under Box2D's sleep threshold. The limited run used to creep on at 0.37 m/s after
    // 2 s; since contacts carry their friction anchors' slip by feature id it nearly stops.
    for after in [unlimited_after, limited_after] {
        assert!(after < 0.05, "still moving at {after} m/s");
    }
}

/// A ball set down touching the floor with soft contacts (`contact_hertz`, 8 substeps): its
/// height over 3 s, one sample per substep-sized frame.
fn soft_ball_heights(hertz: f32, damping_ratio: f32) -> (f32, Vec<f32>) {
    let dt = 1.0 / 480.0;
    let mut world = World::new(Settings {
        dt,
        contact_hertz: hertz,
        contact_damping_ratio: damping_ratio,
        ..settings()
    });
    plane(&mut world, Quat::IDENTITY);
    let radius = 0.1;
    let ball = world.add_body(
        Body::new("ball", BodyKind::Dynamic, Shape::Sphere { radius }, 1.0)
            .with_pose(Vec3::new(0.0, radius, 0.0), Quat::IDENTITY),
    );
    let heights = (0..1440)
        .map(|_| {
            world.step().unwrap();
            world.body(ball).position.y - radius
        })
        .collect();
    (dt, heights)
}

/// Soft contacts are damped springs of the stated frequency (XPBD compliance, Macklin
/// et al. 2016). Undamped at 2 Hz, a ball set down on the floor oscillates with period 0.5 s
/// about a sag of g / omega^2 = 62.1 mm; critically damped it
/// sinks to the same sag without overshoot (measured 0.500 s and 62.1 mm undamped; 62.1 mm
/// settled and deepest, critically damped).
#[test]
fn a_soft_contact_is_a_spring_of_its_frequency() {
    let hertz = 2.0;
    let omega = std::f32::consts::TAU * hertz;
    let sag = 9.81 / (omega * omega);
    let (dt, undamped) = soft_ball_heights(hertz, 0.0);
    // minima of the height: the deepest points of each swing
    let minima: Vec<usize> = (1..undamped.len() - 1)
        .filter(|&i| undamped[i] < undamped[i - 1] && undamped[i] <= undamped[i + 1])
        .collect();
    assert!(minima.len() >= 4, "{} swings", minima.len());
    let period = (minima[3] - minima[0]) as f32 * dt / 3.0;
    assert!(
        (period - 1.0 / hertz).abs() < 0.02 / hertz,
        "period {period} s"
    );
    let mean = -undamped.iter().sum::<f32>() / undamped.len() as f32;
    assert!(
        (mean - sag).abs() < 0.03 * sag,
        "mean sag {mean} m, expected {sag} m"
    );
    let (_, critical) = soft_ball_heights(hertz, 1.0);
    let settled = -critical.last().unwrap();
    let deepest = -critical.iter().copied().fold(f32::INFINITY, f32::min);
    assert!(
        (settled - sag).abs() < 0.01 * sag,
        "settled at {settled} m, expected {sag} m"
    );
    assert!(deepest < 1.02 * sag, "overshot to {deepest} m, sag {sag} m");
}

/// 27 boxes started in a 3x3x3 block, each overlapping its neighbours by half: the fastest box
/// over 10 s and the time from which every box stays under 0.05 m/s, with the push-out capped
/// at `push_speed` (m/s).
fn overlapping_block(push_speed: f32) -> (f32, Option<f32>, u64) {
    let mut world = World::new(Settings {
        contact_push_speed: push_speed,
        ..settings()
    });
    plane(&mut world, Quat::IDENTITY);
    let half = Vec3::splat(0.25);
    let mut boxes = Vec::new();
    for i in 0..27 {
        let cell = Vec3::new((i % 3) as f32, (i / 3 % 3) as f32, (i / 9) as f32);
        let body = Body::new(
            format!("box{i}"),
            BodyKind::Dynamic,
            Shape::Cuboid { half_extents: half },
            1.0,
        );
        let start = Vec3::new(0.0, 0.25, 0.0) + 0.25 * cell;
        boxes.push(world.add_body(body.with_pose(start, Quat::IDENTITY)));
    }
    let (mut peak, mut rest_since) = (0.0f32, None);
    for frame in 0..600 {
        world.step().unwrap();
        let fastest = (boxes.iter())
            .map(|&id| world.body(id).linear_velocity.length())
            .fold(0.0, f32::max);
        peak = peak.max(fastest);
        rest_since = match fastest < 0.05 {
            true => rest_since.or(Some(frame as f32 / 60.0)),
            false => None,
        };
    }
    (peak, rest_since, world.state_hash())
}

/// Boxes started overlapping by half separate no faster than 3 m/s and are at rest
/// within 3 s. A push-out cap of 1 m/s does it (measured: peak 1.7 m/s, at rest from 0.95 s).
/// Pushes compound up the block (a top box rides on boxes pushed out themselves), so the cap
/// must sit below the wanted peak: 1.5 and 3 m/s caps peak at 4.1 and 6.1 m/s. The paper's
/// projection, uncapped, throws a box out at 22 m/s and rests only after 5.9 s.
#[test]
fn an_overlapping_block_of_boxes_separates_gently_and_comes_to_rest() {
    let (peak, rest, hash) = overlapping_block(1.0);
    crate::common::assert_state_hash("block of 27 boxes", hash, 0x0eaa_517c_4be7_9e53);
    assert!(peak <= 3.0, "peak {peak} m/s");
    let rest = rest.expect("never at rest");
    assert!(rest <= 3.0, "at rest only from {rest} s");
    let (uncapped, _, _) = overlapping_block(f32::INFINITY);
    assert!(uncapped > 3.0 * peak, "uncapped peak {uncapped} m/s");
}

/// The overlap measure finds what the contact points cannot: the world's points are found once
/// a frame, so a ball moved by hand 3 cm into a wall has no point with the wall until the next
/// detection, and the points report the floor's contact only. A detection of its own on the
/// current poses ([`rodlab::contact::Contacts::deepest_overlap`]) finds the 3 cm.
#[test]
fn the_overlap_found_afresh_sees_what_the_points_miss() {
    let mut world = World::new(settings());
    plane(&mut world, Quat::IDENTITY);
    let half = 0.2;
    world.add_body(
        Body::new(
            "wall",
            BodyKind::Fixed,
            Shape::Cuboid {
                half_extents: Vec3::splat(half),
            },
            1.0,
        )
        .with_pose(Vec3::new(1.0, half, 0.0), Quat::IDENTITY),
    );
    let radius = 0.1;
    let ball = world.add_body(
        Body::new("ball", BodyKind::Dynamic, Shape::Sphere { radius }, 1.0)
            .with_pose(Vec3::new(0.0, radius, 0.0), Quat::IDENTITY),
    );
    for _ in 0..30 {
        world.step().unwrap();
    }
    let measure = |world: &World| {
        let mut probe = rodlab::contact::Contacts::default();
        let (bodies, constraints) = (&world.bodies, &world.constraints);
        (
            world.contacts.max_penetration(bodies),
            probe.deepest_overlap(bodies, constraints),
        )
    };
    let (points, afresh) = measure(&world);
    assert!(
        points < 1e-3 && afresh < 1e-3,
        "at rest: {points} m, {afresh} m"
    );
    // 3 cm into the wall's face at x = 1 - half, still resting on the floor
    let depth = 0.03;
    let x = 1.0 - half - radius + depth;
    world
        .body_mut(ball)
        .set_pose(Vec3::new(x, radius, 0.0), Quat::IDENTITY);
    let (points, afresh) = measure(&world);
    assert!(points < 1e-3, "the points see {points} m");
    assert!(
        (afresh - depth).abs() < 1e-4,
        "found afresh {afresh} m, expected {depth} m"
    );
}

/// The health check's contact bound (solver step 4): `n` boxes of 20 cm started 15 cm into the
/// floor, in a row. The push out of overlap is capped at 3 m/s, 5 cm a frame, so after the
/// first frame every box is still about 10 cm deep: past a `max_penetration` of 5 cm, the run
/// stops naming the first box in the world's order (whatever the thread count: 1200 boxes
/// make 4800 points, which the check scans beside the bodies on a second thread). A box made
/// non-finite as well is reported first: bodies, then joints, then contacts.
fn sunk_boxes(n: usize) -> World {
    let mut world = World::new(Settings {
        contact_push_speed: 3.0,
        max_penetration: 0.05,
        ..settings()
    });
    plane(&mut world, Quat::IDENTITY);
    let half = Vec3::splat(0.1);
    for i in 0..n {
        let at = Vec3::new(0.5 * (i % 40) as f32, half.y - 0.15, 0.5 * (i / 40) as f32);
        world.add_body(
            Body::new(
                format!("box{i}"),
                BodyKind::Dynamic,
                Shape::Cuboid { half_extents: half },
                1.0,
            )
            .with_pose(at, Quat::IDENTITY),
        );
    }
    world
}

#[test]
fn a_contact_driven_past_the_penetration_bound_stops_the_run_naming_both_bodies() {
    for n in [3, 1200] {
        let mut world = sunk_boxes(n);
        let error = world.step().expect_err("every box is still 10 cm deep");
        assert_eq!(error.frame, 1);
        assert_eq!(error.body, "box0", "{n} boxes: {error}");
        assert!(
            error.reason.starts_with("was driven 0.1") && error.reason.contains("\"floor\""),
            "{n} boxes: {error}"
        );

        let mut world = sunk_boxes(n);
        let last = world.bodies.len() - 1;
        world.bodies[last].linear_velocity.x = f32::NAN;
        let error = world.step().expect_err("a NaN body");
        assert_eq!(error.body, format!("box{}", n - 1), "{n} boxes: {error}");
        assert!(error.reason.contains("non-finite"), "{n} boxes: {error}");
    }
}
