//! Speculative contacts against tunnelling (fast and spinning bodies against thin walls), and
//! collision filtering (groups and masks, joined bodies).

use super::*;

#[test]
fn fast_sphere_does_not_tunnel_through_a_thin_capsule() {
    // 10 m/s moves 16.7 cm a frame at 60 Hz, far more than the 5 cm thick bar is wide.
    let mut world = World::new(Settings {
        gravity: Vec3::ZERO,
        ..settings()
    });
    world.add_body(Body::new(
        "bar",
        BodyKind::Fixed,
        Shape::Capsule {
            half_height: 0.5,
            radius: 0.025,
            axis: Axis::Z,
        },
        1.0,
    ));
    let mut ball = Body::new(
        "ball",
        BodyKind::Dynamic,
        Shape::Sphere { radius: 0.05 },
        1.0,
    )
    .with_pose(Vec3::new(-0.5, 0.0, 0.0), Quat::IDENTITY);
    ball.linear_velocity = Vec3::new(10.0, 0.0, 0.0);
    let id = world.add_body(ball);
    for _ in 0..30 {
        world.step().unwrap();
        assert!(
            world.body(id).position.x < -0.07,
            "passed through: {}",
            world.body(id).position
        );
    }
}

#[test]
fn collision_groups_filter_pairs() {
    let mut world = World::new(Settings {
        gravity: Vec3::ZERO,
        ..settings()
    });
    let mut a = Body::new("a", BodyKind::Dynamic, Shape::Sphere { radius: 0.1 }, 1.0)
        .with_pose(Vec3::new(-0.3, 0.0, 0.0), Quat::IDENTITY);
    let mut b = Body::new("b", BodyKind::Dynamic, Shape::Sphere { radius: 0.1 }, 1.0)
        .with_pose(Vec3::new(0.3, 0.0, 0.0), Quat::IDENTITY);
    a.linear_velocity = Vec3::new(1.0, 0.0, 0.0);
    b.linear_velocity = Vec3::new(-1.0, 0.0, 0.0);
    (a.collision_group, a.collision_mask) = (0b01, 0b01);
    (b.collision_group, b.collision_mask) = (0b10, 0b10);
    let (ia, ib) = (world.add_body(a), world.add_body(b));
    for _ in 0..60 {
        world.step().unwrap();
    }
    // they passed through each other
    assert!(world.body(ia).position.x > 0.3 && world.body(ib).position.x < -0.3);
}

/// A 50 cm capsule lying along x at `x`, 2 m up, for the filter tests.
fn lying_capsule(name: &str, x: f32) -> Body {
    let shape = Shape::Capsule {
        half_height: 0.2,
        radius: 0.05,
        axis: Axis::X,
    };
    Body::new(name, BodyKind::Dynamic, shape, 1.0).with_pose(Vec3::new(x, 2.0, 0.0), Quat::IDENTITY)
}

/// Bodies joined by a joint or a rod never make contact points, however they overlap, while the
/// grid is built and while they fall through it (fat boxes left every step); a joint that sets
/// `collide_connected` lets its pair collide.
#[test]
fn joined_bodies_make_no_points_unless_the_joint_asks() {
    use rodlab::body::BodyId;
    use rodlab::constraint::{BallSocket, Constraint, Rod};
    // (joint, collide_connected): a joint, a joint that asks to collide, a rod
    for (kind, connected) in [("joint", false), ("joint", true), ("rod", false)] {
        let mut world = World::new(settings());
        // three capsules in a row, each overlapping the next by 10 cm (joined a-b, free b-c)
        let a = world.add_body(lying_capsule("a", 0.0));
        let b = world.add_body(lying_capsule("b", 0.4));
        let c = world.add_body(lying_capsule("c", 0.8));
        match kind {
            "joint" => {
                let anchor = Vec3::new(0.2, 2.0, 0.0);
                let mut joint =
                    BallSocket::at_world_anchor("ab", &world.bodies, a, b, anchor, Quat::IDENTITY);
                joint.collide_connected = connected;
                world.add_constraint(joint);
            }
            _ => {
                let rod = Rod::instantiate("ab", &world.bodies, a, b, Vec3::Z).unwrap();
                world.add_constraint(Constraint::Rod(rod));
            }
        }
        let touching = |w: &World, x: BodyId, y: BodyId| {
            let pair = (x.min(y), x.max(y));
            (w.contacts.points.iter())
                .any(|p| (p.body_a.min(p.body_b), p.body_a.max(p.body_b)) == pair)
        };
        let (mut ab_frames, mut bc_frames) = (0, 0);
        for _ in 0..30 {
            world.step().unwrap();
            ab_frames += touching(&world, a, b) as u32;
            bc_frames += touching(&world, b, c) as u32;
        }
        // the free pair collides from the first frame on (it is pushed apart, then stays
        // within the margin); the joined one only when its joint asks
        assert!(bc_frames > 0, "{kind}: the free pair never touched");
        match connected {
            true => assert!(ab_frames > 0, "{kind}: collide_connected made no point"),
            false => assert_eq!(ab_frames, 0, "{kind}: the joined pair made points"),
        }
        assert!(
            world.body(a).position.y < 1.0,
            "{kind}: the bodies did not fall"
        );
    }
}

/// A joint moved to other bodies between steps moves the filter with it, though the number of
/// constraints stays the same: detection rebuilds its joined pairs whenever the constraints'
/// stamp changes ([`rodlab::constraint::Constraints`]), where it once compared their count.
#[test]
fn a_joint_moved_to_other_bodies_moves_the_contact_filter() {
    use rodlab::body::BodyId;
    use rodlab::constraint::{BallSocket, Constraint};
    let mut world = World::new(Settings {
        gravity: Vec3::ZERO,
        ..settings()
    });
    // three capsules in a row, each overlapping the next by 10 cm
    let a = world.add_body(lying_capsule("a", 0.0));
    let b = world.add_body(lying_capsule("b", 0.4));
    let c = world.add_body(lying_capsule("c", 0.8));
    let joint = |world: &World, x: BodyId, y: BodyId, at: f32| {
        let anchor = Vec3::new(at, 2.0, 0.0);
        BallSocket::at_world_anchor("joint", &world.bodies, x, y, anchor, Quat::IDENTITY)
    };
    world.add_constraint(joint(&world, a, b, 0.2));
    let pairs = |w: &World| {
        let pair =
            |p: &rodlab::contact::ContactPoint| (p.body_a.min(p.body_b), p.body_a.max(p.body_b));
        let touch = |x: BodyId, y: BodyId| w.contacts.points.iter().any(|p| pair(p) == (x, y));
        (touch(a, b), touch(b, c))
    };
    world.step().unwrap();
    assert_eq!(pairs(&world), (false, true), "joined a-b, free b-c");
    let moved = joint(&world, b, c, world.body(b).position.x + 0.2);
    world.constraints[0] = Constraint::BallSocket(moved);
    world.step().unwrap();
    assert_eq!(pairs(&world), (true, false), "free a-b, joined b-c");
}

/// No gravity, and a fixed wall 5 cm thick whose faces lie at x = -0.025 and +0.025.
fn weightless_world_with_a_thin_wall() -> World {
    let mut world = World::new(Settings {
        gravity: Vec3::ZERO,
        ..settings()
    });
    world.add_body(Body::new(
        "wall",
        BodyKind::Fixed,
        Shape::Cuboid {
            half_extents: Vec3::new(0.025, 1.0, 1.0),
        },
        1.0,
    ));
    world
}

#[test]
fn fast_capsule_does_not_pass_through_a_thin_box() {
    // 10 m/s at 60 Hz: 16.7 cm a frame against a 5 cm thick wall.
    let mut world = weightless_world_with_a_thin_wall();
    let mut capsule = Body::new(
        "dart",
        BodyKind::Dynamic,
        Shape::Capsule {
            half_height: 0.15,
            radius: 0.04,
            axis: Axis::Y,
        },
        1.0,
    )
    .with_pose(Vec3::new(-0.6, 0.0, 0.0), Quat::IDENTITY);
    capsule.linear_velocity = Vec3::new(10.0, 0.0, 0.0);
    let id = world.add_body(capsule);
    for _ in 0..30 {
        world.step().unwrap();
        assert!(
            world.body(id).position.x < -0.06,
            "passed through: {}",
            world.body(id).position
        );
    }
}

/// A spinning stick beside a thin wall: its centre never moves toward the wall, but at
/// 40 rad/s its end sweeps 24 cm a frame and would pass through the 5 cm wall between two
/// frames unless the speculative reach counts what spin adds at the farthest surface point
/// (the broad phase's boxes and the narrow phase's reach both do). The stick must bounce off
/// the wall's face rather than end up with a point beyond it.
#[test]
fn a_spinning_stick_does_not_pass_through_a_thin_wall() {
    let mut world = weightless_world_with_a_thin_wall();
    let (half_height, radius) = (0.35, 0.02);
    let mut stick = Body::new(
        "stick",
        BodyKind::Dynamic,
        Shape::Capsule {
            half_height,
            radius,
            axis: Axis::Y,
        },
        1.0,
    )
    // centre 0.3 m from the wall's face, the stick lying along y, spinning about z: its end
    // swings through the wall's plane within a quarter turn
    .with_pose(Vec3::new(-0.325, 0.0, 0.0), Quat::IDENTITY);
    stick.angular_velocity = Vec3::new(0.0, 0.0, 40.0);
    let id = world.add_body(stick);
    for frame in 0..30 {
        world.step().unwrap();
        let b = world.body(id);
        let tip = b.orientation * Vec3::new(0.0, half_height + radius, 0.0);
        let farthest = b.position.x + tip.x.abs();
        assert!(
            farthest < 0.0,
            "frame {frame}: a point of the stick is at x = {farthest}, beyond the wall's face"
        );
    }
}

/// The pairs of one ragdoll's bodies with points when it stands on the floor, at rest or with
/// its left leg crossed over the right, and how many points its bodies have with the floor.
fn self_contact_pairs(
    self_contacts: rodlab::ragdoll::SelfContacts,
    crossed: bool,
) -> (std::collections::BTreeSet<(String, String)>, usize) {
    let world = crate::common::ragdoll_on_a_floor(self_contacts, crossed);
    let mut contacts = rodlab::contact::Contacts::default();
    let (dt, margin) = (world.settings.dt, world.settings.contact_margin);
    contacts.detect(&world.bodies, &world.constraints, dt, margin);
    let part = |id: rodlab::body::BodyId| {
        let name = &world.body(id).name;
        name.strip_prefix("r/").map(str::to_string)
    };
    let mut pairs = std::collections::BTreeSet::new();
    let mut floor = 0;
    for p in &contacts.points {
        match (part(p.body_a), part(p.body_b)) {
            (Some(a), Some(b)) => {
                pairs.insert((a.clone().min(b.clone()), a.max(b)));
            }
            _ => floor += 1,
        }
    }
    (pairs, floor)
}

/// A ragdoll's `self_contacts`: `all` lets every pair not joined collide (at rest its forearms
/// hang against its pelvis and thighs; a leg crossed over the other touches it), `apart_at_rest`
/// filters the four pairs touching at rest but not the crossed legs, and `none` filters every
/// pair of the ragdoll, while its feet still touch the floor.
#[test]
fn a_ragdolls_self_contacts_filter_its_own_pairs() {
    use rodlab::ragdoll::SelfContacts;
    let pair = |a: &str, b: &str| (a.to_string(), b.to_string());
    let at_rest = [
        pair("forearm_l", "pelvis"),
        pair("forearm_r", "pelvis"),
        pair("forearm_l", "thigh_l"),
        pair("forearm_r", "thigh_r"),
    ];
    let thighs = pair("thigh_l", "thigh_r");
    for crossed in [false, true] {
        let (all, floor) = self_contact_pairs(SelfContacts::All, crossed);
        let (apart, apart_floor) = self_contact_pairs(SelfContacts::ApartAtRest, crossed);
        let (none, none_floor) = self_contact_pairs(SelfContacts::None, crossed);
        assert!(floor >= 1, "a foot stands on the floor: {floor} points");
        assert_eq!((apart_floor, none_floor), (floor, floor));
        assert!(none.is_empty(), "{none:?}");
        assert!(at_rest.iter().all(|p| !apart.contains(p)), "{apart:?}");
        // apart_at_rest filters the pairs touching at rest and no other
        let kept: std::collections::BTreeSet<_> = all.difference(&apart).collect();
        assert!(
            kept.iter().all(|p| at_rest.contains(p)),
            "{all:?} / {apart:?}"
        );
        if crossed {
            assert!(
                all.contains(&thighs) && apart.contains(&thighs),
                "{apart:?}"
            );
        } else {
            assert_eq!(all, at_rest.iter().cloned().collect(), "at rest");
            assert!(apart.is_empty(), "{apart:?}");
        }
    }
}

/// `self_contacts` set by a `[[variant]]` or the command line (`--self-contacts`, the same
/// [`rodlab::scene::Overrides`]) reaches every ragdoll, those of a `[drop]` block included: none
/// filters each chain3 ragdoll's 66 part pairs not joined (13 parts, 12 joints), apart_at_rest
/// its 4, and the file's `all` none.
#[test]
fn self_contacts_reach_every_ragdoll_from_a_variant_or_the_command_line() {
    let text = &crate::common::small_drop_scene(2, 7);
    let scene = rodlab::scene::Scene::parse("scenes/x.toml", text).unwrap();
    let filters = |scene: &rodlab::scene::Scene| {
        let lab = scene.build().unwrap();
        lab.world.constraints.contact_filters().len()
    };
    assert_eq!(filters(&scene), 0, "the file's default: all");
    assert_eq!(filters(&scene.variant("no_self_contacts").unwrap()), 3 * 66);
    let mut at_rest = scene.clone();
    rodlab::scene::Overrides {
        self_contacts: Some(rodlab::ragdoll::SelfContacts::ApartAtRest),
        ..Default::default()
    }
    .apply(&mut at_rest.def);
    assert_eq!(filters(&at_rest), 3 * 4);
}
