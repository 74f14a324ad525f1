//! Sleeping islands: a body at rest sleeps, a contact wakes it, joined bodies sleep and wake
//! together, and the bodies that keep an island awake are named.

use super::*;

/// Sleeping: a box resting on the floor falls asleep once it has been still for
/// 0.5 s and then does not move at all; a ball dropped on it wakes it, and once the ball rests
/// on top the two fall asleep again, as one island.
#[test]
fn a_resting_box_sleeps_a_falling_ball_wakes_it_and_both_sleep_again() {
    use rodlab::sleep::TIME_TO_SLEEP;
    let mut world = World::new(Settings {
        sleep: true,
        ..settings()
    });
    plane(&mut world, Quat::IDENTITY);
    let crate_ = sleepy_box(&mut world, "crate", Vec3::new(0.0, 0.1, 0.0));
    let ball = world.add_body(ball(Vec3::new(0.05, 8.0, 0.0)));
    let mut fell_asleep = None;
    for frame in 1..=60 {
        world.step().unwrap();
        if fell_asleep.is_none() && world.body(crate_).is_asleep() {
            fell_asleep = Some(frame);
        }
    }
    // still from the first frame: asleep after 0.5 s (30 frames), give or take one
    let frame = fell_asleep.expect("the crate never fell asleep");
    let expected = (TIME_TO_SLEEP * 60.0).round() as i32;
    assert!((frame - expected).abs() <= 1, "asleep at frame {frame}");
    assert!(
        !world.body(ball).is_asleep(),
        "the falling ball fell asleep"
    );
    assert_eq!(world.awake_bodies, 1, "the ball alone is awake");
    // asleep, the crate does not move by a bit while the ball falls
    let pose = (world.body(crate_).position, world.body(crate_).orientation);
    let mut woke = None;
    for frame in 61..=300 {
        world.step().unwrap();
        let body = world.body(crate_);
        if woke.is_some() {
            continue;
        }
        if body.is_asleep() {
            assert_eq!(
                (body.position, body.orientation),
                pose,
                "a sleeping body moved"
            );
        } else {
            woke = Some(frame);
        }
    }
    // the ball falls 7.8 m in about 1.26 s (frame 76): it wakes the crate when it lands
    let woke = woke.expect("the ball never woke the crate");
    assert!((74..=80).contains(&woke), "woke at frame {woke}");
    for _ in 0..120 {
        world.step().unwrap();
    }
    let (c, b) = (world.body(crate_), world.body(ball));
    assert!(
        c.is_asleep() && b.is_asleep(),
        "not asleep again after 2 s at rest"
    );
    assert!(
        (b.position.y - 0.3).abs() < 0.01,
        "ball at y = {}",
        b.position.y
    );
    assert_eq!(world.awake_bodies, 0);
}

/// Joined bodies sleep as one island and wake as one: a force on one wakes the other through
/// the joint, and the pair moves off; with sleeping off nothing ever sleeps.
#[test]
fn joined_bodies_sleep_and_wake_together() {
    use rodlab::constraint::BallSocket;
    for sleep in [true, false] {
        let mut world = World::new(Settings {
            sleep,
            ..settings()
        });
        plane(&mut world, Quat::IDENTITY);
        let a = sleepy_box(&mut world, "a", Vec3::new(0.0, 0.1, 0.0));
        let b = sleepy_box(&mut world, "b", Vec3::new(0.45, 0.1, 0.0));
        let anchor = Vec3::new(0.225, 0.1, 0.0);
        let joint =
            BallSocket::at_world_anchor("hinge", &world.bodies, a, b, anchor, Quat::IDENTITY);
        world.add_constraint(joint);
        for _ in 0..60 {
            world.step().unwrap();
        }
        let asleep = |w: &World| (w.body(a).is_asleep(), w.body(b).is_asleep());
        if !sleep {
            assert_eq!(asleep(&world), (false, false), "asleep with sleeping off");
            continue;
        }
        assert_eq!(asleep(&world), (true, true));
        world.body_mut(a).external_force = Vec3::new(200.0, 0.0, 0.0);
        world.step().unwrap();
        // a wakes at once (its force); b wakes a frame later, through the joint
        world.step().unwrap();
        assert_eq!(asleep(&world), (false, false), "the pair did not wake");
        for _ in 0..30 {
            world.step().unwrap();
        }
        assert!(
            world.body(b).position.x > 0.5,
            "b did not follow: {}",
            world.body(b).position
        );
    }
}

/// The run summary names what keeps an island awake: the bodies whose fastest surface point is
/// over the sleep threshold, fastest first, with the spin about a capsule's own axis apart from
/// the spin across it (a limb spinning about its axis at 10 rad/s moves its surface at 10 r,
/// one tumbling end over end at 1 rad/s moves its ends at 1 (half height + r)).
#[test]
fn the_bodies_that_keep_an_island_awake_are_named_with_their_spin_split() {
    let mut world = World::new(Settings {
        gravity: Vec3::ZERO,
        ..settings()
    });
    let capsule = |name: &str, x: f32| {
        let shape = Shape::Capsule {
            half_height: 0.2,
            radius: 0.05,
            axis: Axis::Y,
        };
        Body::new(name, BodyKind::Dynamic, shape, 2.0)
            .with_pose(Vec3::new(x, 1.0, 0.0), Quat::IDENTITY)
    };
    let mut spinner = capsule("spinner", 0.0);
    spinner.angular_velocity = Vec3::new(0.0, 10.0, 0.0);
    let mut tumbler = capsule("tumbler", 2.0);
    tumbler.angular_velocity = Vec3::new(1.0, 0.0, 0.0);
    let still = capsule("still", 4.0);
    for body in [spinner, tumbler, still] {
        world.add_body(body);
    }
    world.step().unwrap();
    let restless = rodlab::sleep::restless_bodies(&world.bodies);
    let names: Vec<&str> = restless
        .iter()
        .map(|r| world.body(r.body).name.as_str())
        .collect();
    assert_eq!(names, ["spinner", "tumbler"], "{restless:?}");
    let (spin, tumble) = (&restless[0], &restless[1]);
    assert!(
        (spin.axial_spin - 10.0).abs() < 1e-3 && spin.cross_spin < 1e-3,
        "{spin:?}"
    );
    assert!((spin.point_speed - 10.0 * 0.05).abs() < 1e-4, "{spin:?}");
    assert!(
        tumble.axial_spin < 1e-3 && (tumble.cross_spin - 1.0).abs() < 1e-3,
        "{tumble:?}"
    );
    assert!((tumble.point_speed - 1.0 * 0.25).abs() < 1e-3, "{tumble:?}");
}

/// The sleep test reads where a body goes, not how fast (Jolt's test): a box jittering on the
/// spot (1 cm either side at 5 Hz, 0.31 m/s at its fastest) falls asleep, where a test of the
/// instantaneous speed would keep it awake for ever, while boxes drifting steadily slower and
/// faster than twice the sleep speed (the test's sphere spans a steady path's whole length)
/// do and do not sleep.
#[test]
fn a_body_jittering_on_the_spot_sleeps_and_a_drifting_one_does_not() {
    use rodlab::sleep::{SLEEP_SPEED, TIME_TO_SLEEP};
    let mut world = World::new(Settings {
        sleep: true,
        gravity: Vec3::ZERO,
        ..Settings::default()
    });
    let jitter = sleepy_box(&mut world, "jitter", Vec3::new(0.0, 1.0, 0.0));
    let slow = sleepy_box(&mut world, "slow", Vec3::new(2.0, 1.0, 0.0));
    let fast = sleepy_box(&mut world, "fast", Vec3::new(4.0, 1.0, 0.0));
    world.body_mut(slow).linear_velocity = Vec3::new(1.6 * SLEEP_SPEED, 0.0, 0.0);
    world.body_mut(fast).linear_velocity = Vec3::new(2.4 * SLEEP_SPEED, 0.0, 0.0);
    let omega = 2.0 * std::f32::consts::PI * 5.0;
    let mut asleep_at = [None; 3];
    for frame in 1..=120 {
        let t = world.time as f32;
        if !world.body(jitter).is_asleep() {
            // velocity of x = 1 cm sin(omega t), over the coming frame
            world.body_mut(jitter).linear_velocity =
                Vec3::new(0.01 * omega * (omega * t).cos(), 0.0, 0.0);
        }
        world.step().unwrap();
        for (slot, id) in asleep_at.iter_mut().zip([jitter, slow, fast]) {
            if slot.is_none() && world.body(id).is_asleep() {
                *slot = Some(frame);
            }
        }
    }
    let limit = (TIME_TO_SLEEP * 60.0) as i32 + 2;
    let [jitter_at, slow_at, fast_at] = asleep_at;
    assert!(
        jitter_at.is_some_and(|f| f <= limit),
        "jittering box asleep at {jitter_at:?}"
    );
    assert!(
        slow_at.is_some_and(|f| f <= limit),
        "slow box asleep at {slow_at:?}"
    );
    assert_eq!(
        fast_at,
        None,
        "a box drifting at {} m/s fell asleep",
        2.4 * SLEEP_SPEED
    );
}
