//! Stacks and pyramids of boxes that stand (a 10-box stack and a 10-wide pyramid within
//! 5 mm), warm starting, and contact stacking (the lower body of a contact counted heavier).

use super::*;

#[test]
fn stack_of_five_boxes_stays_standing() {
    let mut world = World::new(settings());
    plane(&mut world, Quat::IDENTITY);
    let half = Vec3::new(0.2, 0.1, 0.15);
    let boxes: Vec<_> = (0..5)
        .map(|i| {
            let y = half.y * (2 * i + 1) as f32;
            world.add_body(
                Body::new(
                    format!("box{i}"),
                    BodyKind::Dynamic,
                    Shape::Cuboid { half_extents: half },
                    4.0,
                )
                .with_pose(Vec3::new(0.0, y, 0.0), Quat::IDENTITY),
            )
        })
        .collect();
    for _ in 0..600 {
        world.step().unwrap();
    }
    for (i, &id) in boxes.iter().enumerate() {
        let body = world.body(id);
        let expected = half.y * (2 * i + 1) as f32;
        let offset = body.position - Vec3::new(0.0, expected, 0.0);
        // standing: heights kept to 2 mm (measured: the top box 1 mm low, the sum of five
        // contacts' residual penetration) and sideways to 1 cm (measured: 3 mm, all in the
        // first second; the friction anchors hold it after that)
        assert!(
            offset.y.abs() < 2e-3,
            "box {i} sank or rose by {} m",
            offset.y
        );
        assert!(
            Vec3::new(offset.x, 0.0, offset.z).length() < 0.01,
            "box {i} slid by {offset} m"
        );
        let tilt = (body.orientation * Vec3::Y).angle_between(Vec3::Y);
        assert!(tilt < 0.01, "box {i} tilted by {tilt} rad");
    }
}

/// A pyramid of boxes (a base of `base`, 0.5 m each, touching side by side) after 10 s: the
/// farthest any box moved sideways (m), the farthest any box moved at all (m) and the fastest
/// box (m/s).
fn box_pyramid_drift(
    base: usize,
    substeps: u32,
    iterations: u32,
    warm: f32,
) -> (f32, f32, f32, u64) {
    let mut world = World::new(Settings {
        contact_warm_start: warm,
        substeps,
        iterations,
        ..settings()
    });
    plane(&mut world, Quat::IDENTITY);
    let half = Vec3::splat(0.25);
    let mut boxes = Vec::new();
    for row in 0..base {
        for k in 0..base - row {
            let x = (k as f32 - (base - 1 - row) as f32 * 0.5) * 0.5;
            let start = Vec3::new(x, 0.25 + 0.5 * row as f32, 0.0);
            let body = Body::new(
                format!("box{row}_{k}"),
                BodyKind::Dynamic,
                Shape::Cuboid { half_extents: half },
                1.0,
            );
            boxes.push((world.add_body(body.with_pose(start, Quat::IDENTITY)), start));
        }
    }
    for _ in 0..600 {
        world.step().unwrap();
    }
    let (drift, moved, fastest) = (boxes.iter()).fold(
        (0.0f32, 0.0f32, 0.0f32),
        |(drift, moved, speed), &(id, start)| {
            let b = world.body(id);
            let d = b.position - start;
            let sideways = Vec3::new(d.x, 0.0, d.z).length();
            let fastest = speed.max(b.linear_velocity.length());
            (drift.max(sideways), moved.max(d.length()), fastest)
        },
    );
    (drift, moved, fastest, world.state_hash())
}

/// Warm starting: each substep's contacts start from a quarter of the impulse they
/// ended the last one with. A pyramid's corners then share the load from the first iteration
/// instead of the first-solved corner taking it, and the pyramid holds still. Measured: 0.37 mm
/// sideways and at rest after 10 s, against 21 mm without warm starting (the paper's method).
#[test]
fn warm_started_contacts_hold_a_box_pyramid() {
    let (cold, _, _, cold_hash) = box_pyramid_drift(6, 1, 20, 0.0);
    let (warm, _, fastest, warm_hash) = box_pyramid_drift(6, 1, 20, 0.25);
    crate::common::assert_state_hash("pyramid of 6, cold", cold_hash, 0x2a06_6518_a15e_3ca1);
    crate::common::assert_state_hash("pyramid of 6, warm", warm_hash, 0x95d1_fce9_6e49_326b);
    assert!(warm < 1e-3, "pyramid crept {warm} m");
    assert!(fastest < 1e-3, "a box still moves at {fastest} m/s");
    assert!(warm < cold, "warm {warm} m against cold {cold} m");
}

/// A pyramid ten wide (55 boxes), every box within 5 mm of its start after 10 s. With
/// a quarter warm start it holds at 4 substeps of 5 iterations (measured 1.3 mm) and at 2 of 10
/// (2.8 mm), against 49 and 122 mm without warm starting. At the paper's one step of 20
/// iterations it is at the bound and depends on the order contacts are solved in: 5.8 mm
/// with the pairs sorted by body (the broad phase's order since it keeps pairs), 2.2 mm in
/// the earlier cell order, 8.6 mm in reverse body order; 4.7 mm with half the warm start.
/// (The ten-box stack is not held awake: it leans 17-150 mm over 10 s at these
/// budgets; it holds when it may sleep, `a_ten_box_stack_that_may_sleep_stands_within_five_millimetres`.)
#[test]
fn a_ten_wide_box_pyramid_stands_within_five_millimetres() {
    for (substeps, iterations, hash) in [
        (4, 5, 0x5866_b4ff_d50a_7871),
        (2, 10, 0xbfd7_87f0_e03a_754f),
    ] {
        let (_, moved, fastest, end) = box_pyramid_drift(10, substeps, iterations, 0.25);
        let what = format!("pyramid of 10, {substeps}x{iterations}");
        crate::common::assert_state_hash(&what, end, hash);
        assert!(
            moved < 5e-3,
            "{substeps}x{iterations}: a box moved {moved} m"
        );
        assert!(
            fastest < 0.01,
            "{substeps}x{iterations}: a box moves at {fastest} m/s"
        );
    }
}

/// A ten-box stack: at 8 substeps of 4 iterations with a quarter warm start and
/// sleeping on, every box stays within 5 mm of its start for 10 s (measured 2.3 mm), because
/// the stack falls asleep after its first 0.5 s, while it is still within a few millimetres.
/// Awake it does not hold: the solver's corner order tilts it a little each step, and over
/// 10 s the top drifts 17-150 mm at every method measured (1x20 to 8x4, warm 0 to 0.5;
/// docs/contacts.md, Warm starting). 4 substeps of 10 iterations hold it at 4.1 mm asleep.
#[test]
fn a_ten_box_stack_that_may_sleep_stands_within_five_millimetres() {
    let mut world = World::new(Settings {
        contact_warm_start: 0.25,
        substeps: 8,
        iterations: 4,
        sleep: true,
        ..settings()
    });
    plane(&mut world, Quat::IDENTITY);
    let boxes: Vec<_> = (0..10)
        .map(|i| {
            let start = Vec3::new(0.0, 0.25 + 0.5 * i as f32, 0.0);
            let body = Body::new(
                format!("box{i}"),
                BodyKind::Dynamic,
                Shape::Cuboid {
                    half_extents: Vec3::splat(0.25),
                },
                1.0,
            );
            (world.add_body(body.with_pose(start, Quat::IDENTITY)), start)
        })
        .collect();
    let mut worst = 0.0f32;
    for _ in 0..600 {
        world.step().unwrap();
        for &(id, start) in &boxes {
            worst = worst.max((world.body(id).position - start).length());
        }
    }
    crate::common::assert_state_hash("ten-box stack", world.state_hash(), 0xddc2_28d8_eb2c_66da);
    assert_eq!(world.awake_bodies, 0, "the stack is not asleep after 10 s");
    assert!(worst < 5e-3, "a box moved {worst} m from its start");
}

/// A 100 kg box resting on a 0.5 kg slab on the floor, 20 iterations a frame, with stacking at
/// `rate` (1/m): after 2 s, how far the heavy box sits below where it would rest (m) and the
/// fastest either box moves (m/s).
fn heavy_box_on_a_light_slab(rate: f32) -> (f32, f32) {
    let mut world = World::new(Settings {
        contact_stacking: rate,
        ..settings()
    });
    plane(&mut world, Quat::IDENTITY);
    let (slab, heavy) = (Vec3::new(0.25, 0.02, 0.25), Vec3::new(0.2, 0.1, 0.2));
    let cuboid = |half_extents| Shape::Cuboid { half_extents };
    let slab_id = world.add_body(
        Body::new("slab", BodyKind::Dynamic, cuboid(slab), 0.5)
            .with_pose(Vec3::new(0.0, slab.y, 0.0), Quat::IDENTITY),
    );
    let rest = 2.0 * slab.y + heavy.y;
    let heavy_id = world.add_body(
        Body::new("heavy", BodyKind::Dynamic, cuboid(heavy), 100.0)
            .with_pose(Vec3::new(0.0, rest, 0.0), Quat::IDENTITY),
    );
    for _ in 0..120 {
        world.step().unwrap();
    }
    let speed = [slab_id, heavy_id]
        .map(|id| world.body(id).linear_velocity.length())
        .into_iter()
        .fold(0.0, f32::max);
    (rest - world.body(heavy_id).position.y, speed)
}

/// Stacking (PBD's mass scaling by height) carries a heavy load down through a light body in a
/// fixed number of sweeps: the paper's contacts leave a 100 kg box sunk into the 0.5 kg slab
/// under it (Gauss-Seidel moves the light slab, not the box), stacking holds it up, and both
/// stay at rest.
#[test]
fn stacking_carries_a_heavy_box_on_a_light_slab() {
    let (plain, plain_speed) = heavy_box_on_a_light_slab(0.0);
    // the box's centre is 12 cm above the slab's: at k = 40 it counts e^4.8 = 120 times lighter
    // than the slab in their contact, so the slab is the heavier one (measured: 40 mm sunk
    // plain; at k = 10 / 20 / 40 / 80, 12.5 / 2.9 / 0.002 / 0.000 mm)
    let (stacked, stacked_speed) = heavy_box_on_a_light_slab(40.0);
    println!(
        "heavy box sunk {:.2} mm plain, {:.3} mm stacked; fastest {plain_speed:.4} / \
         {stacked_speed:.4} m/s",
        1e3 * plain,
        1e3 * stacked
    );
    assert!(
        plain > 5e-3,
        "the setup must sink without stacking: {plain} m"
    );
    assert!(stacked < 5e-4 && stacked < 0.05 * plain, "sunk {stacked} m");
    assert!(stacked_speed < 0.01, "moving at {stacked_speed} m/s");
}

/// Stacking's scales come from the bodies' heights, so each body has one mass in all its
/// contacts: the scale between two bodies is the product of the scales through a third, the
/// higher body keeps its mass, and without gravity nothing is scaled.
#[test]
fn stacking_scales_are_consistent_through_a_third_body() {
    use rodlab::contact::Stacking;
    let stacking = Stacking {
        up: Vec3::Y,
        rate: 15.0,
        max_ratio: f32::INFINITY,
    };
    let [p, q, r] = [0.1f32, 0.25, 0.33].map(|y| Vec3::new(0.3 * y, y, -y));
    // the inverse-mass ratio lower : upper of a pair, as a mass ratio upper-relative
    let ratio = |a: Vec3, b: Vec3| {
        let (sa, sb) = stacking.scales(a, b);
        sb / sa
    };
    let (pq, qr, pr) = (ratio(p, q), ratio(q, r), ratio(p, r));
    assert!((pr - pq * qr).abs() < 1e-4 * pr, "{pr} against {pq} x {qr}");
    assert_eq!(
        stacking.scales(q, p).0,
        1.0,
        "the upper body keeps its mass"
    );
    assert!((ratio(q, p) * pq - 1.0).abs() < 1e-6);
    let weightless = Stacking {
        up: Vec3::ZERO,
        rate: 15.0,
        max_ratio: f32::INFINITY,
    };
    assert_eq!(weightless.scales(p, r), (1.0, 1.0));
}

/// A cap on the ratio holds the lower body at most `max_ratio` times heavier, from the height
/// where `e^(k dh)` reaches it, and leaves the scales below that height alone.
#[test]
fn a_capped_stacking_ratio_stops_growing_at_its_height() {
    use rodlab::contact::Stacking;
    let uncapped = Stacking {
        up: Vec3::Y,
        rate: 10.0,
        max_ratio: f32::INFINITY,
    };
    let capped = Stacking {
        max_ratio: std::f32::consts::E,
        ..uncapped
    };
    for dh in [0.02f32, 0.05, 0.099, 0.101, 0.2, 0.5, 2.0] {
        let (lower, upper) = capped.scales(Vec3::ZERO, dh * Vec3::Y);
        assert_eq!(upper, 1.0);
        let expected = (-10.0 * dh.min(0.1)).exp();
        assert!(
            (lower - expected).abs() < 1e-6,
            "dh {dh}: {lower} against {expected}"
        );
        if dh < 0.1 {
            assert_eq!((lower, upper), uncapped.scales(Vec3::ZERO, dh * Vec3::Y));
        }
    }
}
