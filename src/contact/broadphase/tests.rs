//! The broad phase against brute force: exactly the overlapping pairs, none culled that has
//! a contact, kept pairs equal to a fresh grid, and the same pairs on any thread count.

use super::moved::gallop;
use super::*;
use crate::body::Body;
use crate::math::{Quat, Vec3};

fn colliders(bodies: &[Body]) -> Vec<Collider> {
    bodies.iter().map(Collider::new).collect()
}

/// A reproducible uniform sequence in [0, 1) (a linear congruential generator).
fn uniform(mut seed: u32) -> impl FnMut() -> f32 {
    move || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1 << 24) as f32
    }
}

fn ball(x: f32, y: f32, z: f32, radius: f32, kind: BodyKind) -> Body {
    Body::new("b", kind, Shape::Sphere { radius }, 1.0)
        .with_pose(Vec3::new(x, y, z), Quat::IDENTITY)
}

/// Every pair the grid reports is an overlapping pair of boxes, reported once, and no
/// overlapping pair with a dynamic body is missed (against the all-pairs answer), for
/// spheres, and for capsules and boxes at random orientations.
#[test]
fn grid_finds_exactly_the_overlapping_pairs() {
    let mut bodies = Vec::new();
    let mut random = uniform(12345);
    for i in 0..300 {
        let kind = if i % 7 == 0 {
            BodyKind::Fixed
        } else {
            BodyKind::Dynamic
        };
        let size = if i % 50 == 0 {
            3.0
        } else {
            0.05 + 0.3 * random()
        };
        let shape = match i % 3 {
            0 => Shape::Sphere { radius: size },
            1 => Shape::Capsule {
                half_height: size,
                radius: 0.3 * size,
                axis: crate::shape::Axis::Y,
            },
            _ => Shape::Cuboid {
                half_extents: Vec3::new(size, 0.5 * size, 0.2 * size),
            },
        };
        let position = Vec3::new(8.0 * random() - 4.0, 4.0 * random(), 8.0 * random() - 4.0);
        let axis = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
        let orientation = Quat::from_axis_angle(axis, 6.0 * random());
        bodies.push(Body::new("b", kind, shape, 1.0).with_pose(position, orientation));
    }
    assert_pairs_are_the_overlapping_ones(&bodies, 100);
}

/// The same in a crowd: 600 small balls in a 60 cm cube put about a hundred boxes in a cell,
/// so a box's sweep runs over several lane widths of candidates.
#[test]
fn a_crowded_grid_finds_exactly_the_overlapping_pairs() {
    let mut random = uniform(777);
    let bodies: Vec<Body> = (0..600)
        .map(|i| {
            let kind = [BodyKind::Dynamic, BodyKind::Fixed][(i % 9 == 0) as usize];
            let (x, y, z) = (0.6 * random(), 0.6 * random(), 0.6 * random());
            ball(x, y, z, 0.02 + 0.03 * random(), kind)
        })
        .collect();
    assert_pairs_are_the_overlapping_ones(&bodies, 3500);
}

/// Finds the pairs of `bodies` at rest and checks them against all pairs whose boxes (each grown
/// by half the 2 cm margin, so a pair's boxes overlap within the margin) overlap, with a
/// dynamic body; `at_least` of them, so the test means something.
fn assert_pairs_are_the_overlapping_ones(bodies: &[Body], at_least: usize) {
    let mut found = Vec::new();
    BroadPhase::default().find_pairs(&colliders(bodies), 1.0 / 60.0, 0.02, |a, b| {
        found.push((a, b))
    });
    let count = found.len();
    found.sort_unstable();
    found.dedup();
    assert_eq!(found.len(), count, "a pair was reported twice");
    let mut expected = Vec::new();
    for a in 0..bodies.len() {
        for b in a + 1..bodies.len() {
            let (p, q) = (&bodies[a], &bodies[b]);
            let reach = |body: &Body| body.shape.world_half_extents(body.orientation) + 0.01;
            let apart = ((p.position - q.position).abs() - reach(p) - reach(q)).max_element();
            let dynamic = p.kind == BodyKind::Dynamic || q.kind == BodyKind::Dynamic;
            if apart <= 0.0 && dynamic {
                expected.push((a as u32, b as u32));
            }
        }
    }
    assert!(expected.len() > at_least, "{} pairs", expected.len());
    assert_eq!(found, expected);
}

/// The tight boxes and the half-space cut lose no contact: every pair the narrow phase
/// finds a contact for (all pairs tried) was reported, for tumbling capsules and boxes
/// over a tilted half-space, at rest and moving.
#[test]
fn no_pair_with_a_contact_is_culled() {
    let mut random = uniform(4242);
    let plane = Body::new("plane", BodyKind::Fixed, Shape::HalfSpace, 0.0)
        .with_pose(Vec3::new(0.0, 0.3, 0.0), Quat::from_rotation_z(0.2));
    let mut bodies = vec![plane];
    for i in 0..200 {
        let shape = if i % 2 == 0 {
            Shape::Capsule {
                half_height: 0.1 + 0.2 * random(),
                radius: 0.05,
                axis: crate::shape::Axis::X,
            }
        } else {
            Shape::Cuboid {
                half_extents: Vec3::new(0.2, 0.05, 0.1),
            }
        };
        let position = Vec3::new(3.0 * random(), 1.0 * random(), 3.0 * random());
        let axis = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
        let mut body = Body::new("b", BodyKind::Dynamic, shape, 1.0)
            .with_pose(position, Quat::from_axis_angle(axis, 6.0 * random()));
        body.linear_velocity = Vec3::new(random() - 0.5, random() - 0.5, 0.0) * 10.0;
        bodies.push(body);
    }
    let (dt, margin) = (1.0 / 60.0, 0.02);
    let mut found = Vec::new();
    BroadPhase::default().find_pairs(&colliders(&bodies), dt, margin, |a, b| found.push((a, b)));
    let mut contacts = 0;
    let mut features = Vec::new();
    for a in 0..bodies.len() {
        for b in a + 1..bodies.len() {
            let (p, q) = (&bodies[a], &bodies[b]);
            // the narrow phase's reach (contact::PairContext::collide_all)
            let reach = margin + dt * (p.linear_velocity - q.linear_velocity).length();
            features.clear();
            let (p, q) = (Collider::new(p), Collider::new(q));
            if super::super::narrowphase::collide(&p, &q, reach, &mut features) {
                contacts += 1;
                let pair = (a as u32, b as u32);
                assert!(
                    found.contains(&pair),
                    "pair {pair:?} has a contact but was culled"
                );
            }
        }
    }
    assert!(contacts > 50, "{contacts} pairs in contact");
    // and it does cull: 1633 candidates of the 20 100 pairs
    let all = bodies.len() * (bodies.len() - 1) / 2;
    assert!(
        found.len() < all / 10,
        "{} candidates of {all} pairs",
        found.len()
    );
}

/// Step after step of bodies drifting (most by a millimetre, every 100th by 6 cm, one
/// teleported, some falling asleep): the kept fat pairs report exactly the pairs a fresh grid
/// finds, in the same order, and most steps update the moved bodies instead of rebuilding.
#[test]
fn kept_pairs_match_a_fresh_grid_as_bodies_move() {
    let mut random = uniform(99);
    let mut bodies = vec![Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 0.0)];
    bodies.push(
        Body::new(
            "wall",
            BodyKind::Fixed,
            Shape::Cuboid {
                half_extents: Vec3::new(40.0, 1.0, 0.2),
            },
            0.0,
        )
        .with_pose(Vec3::new(5.0, 0.5, 5.0), Quat::IDENTITY),
    );
    for i in 0..1500 {
        let shape = match i % 3 {
            0 => Shape::Sphere { radius: 0.08 },
            _ => Shape::Capsule {
                half_height: 0.1 + 0.1 * random(),
                radius: 0.05,
                axis: crate::shape::Axis::Y,
            },
        };
        let position = Vec3::new(10.0 * random(), 0.6 * random(), 10.0 * random());
        let axis = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
        let orientation = Quat::from_axis_angle(axis, 6.0 * random());
        bodies.push(Body::new("b", BodyKind::Dynamic, shape, 1.0).with_pose(position, orientation));
    }
    let (dt, margin) = (1.0 / 60.0, 0.02);
    let mut kept = BroadPhase::default();
    let mut updates = 0;
    for step in 0..60 {
        for (i, body) in bodies.iter_mut().enumerate().skip(2) {
            let far = i % 100 == step % 100;
            let reach = if far { 0.06 } else { 0.001 };
            let drift = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5) * reach;
            let turn = Quat::from_rotation_y(if far { 0.3 } else { 0.002 });
            body.linear_velocity = drift / dt;
            let pose = (body.position + drift, turn * body.orientation);
            body.set_pose(pose.0, pose.1);
        }
        if step == 30 {
            let far_corner = Vec3::new(9.9, 0.1, 9.9);
            let orientation = bodies[7].orientation;
            bodies[7].set_pose(far_corner, orientation);
        }
        if step == 45 {
            for body in bodies.iter_mut().skip(2).step_by(5) {
                body.asleep = true;
            }
        }
        let rebuilds = kept.rebuilds;
        let mut incremental = Vec::new();
        kept.find_pairs(&colliders(&bodies), dt, margin, |a, b| {
            incremental.push((a, b))
        });
        updates += (kept.rebuilds == rebuilds) as u32;
        let mut fresh = Vec::new();
        BroadPhase::default()
            .find_pairs(&colliders(&bodies), dt, margin, |a, b| fresh.push((a, b)));
        assert!(fresh.len() > 1000, "step {step}: {} pairs", fresh.len());
        assert_eq!(incremental, fresh, "step {step}");
    }
    // only the first step, the sleepers' step and the next (set_pose wakes them) rebuild: a few
    // dozen bodies move each step (before, moved bodies stayed stale in the grid, and once a
    // sixteenth had moved since the last rebuild the grid was rebuilt: 40-odd updates)
    assert!(
        updates >= 57,
        "{updates} of 60 steps updated without a rebuild"
    );
}

/// The kept pairs reported in parts (as the narrow phase's chunks do), then the others, are
/// the pairs `find_pairs` reports, in its order; with a half-space and a large box.
#[test]
fn kept_pairs_reported_in_parts_are_find_pairs() {
    let mut random = uniform(31);
    let plane = Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 0.0);
    let wall = Body::new(
        "wall",
        BodyKind::Fixed,
        Shape::Cuboid {
            half_extents: Vec3::new(40.0, 1.0, 0.2),
        },
        0.0,
    )
    .with_pose(Vec3::new(5.0, 0.5, 5.0), Quat::IDENTITY);
    let mut bodies = vec![plane, wall];
    for _ in 0..3000 {
        let (x, y, z) = (10.0 * random(), random(), 10.0 * random());
        bodies.push(ball(x, y, z, 0.05 + 0.1 * random(), BodyKind::Dynamic));
    }
    let colliders = colliders(&bodies);
    let mut whole = Vec::new();
    let mut broad = BroadPhase::default();
    broad.find_pairs(&colliders, 1.0 / 60.0, 0.02, |a, b| whole.push((a, b)));
    assert!(broad.update(&colliders, 1.0 / 60.0, 0.02));
    let n = broad.kept_len();
    let mut parts = Vec::new();
    for range in [0..n / 3, n / 3..n / 3, n / 3..n - 1, n - 1..n] {
        broad.report_kept(range, |a, b| parts.push((a, b)));
    }
    broad.report_others(&colliders, |a, b| parts.push((a, b)));
    assert!(whole.len() > 3000 && whole.iter().any(|&(a, _)| a == 0));
    assert_eq!(parts, whole);
}

/// A world large enough for the parallel sort and sweep: the same pairs in the same order on
/// one thread and on two.
#[test]
fn chunked_cells_give_the_same_pairs_on_any_thread_count() {
    let mut random = uniform(777);
    let bodies: Vec<Body> = (0..16000)
        .map(|_| {
            let (x, y, z) = (46.0 * random(), 2.0 * random(), 46.0 * random());
            ball(x, y, z, 0.1 + 0.2 * random(), BodyKind::Dynamic)
        })
        .collect();
    let pairs = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut found = Vec::new();
            let mut broad = BroadPhase::default();
            broad.find_pairs(&colliders(&bodies), 1.0 / 60.0, 0.02, |a, b| {
                found.push((a, b))
            });
            assert!(
                broad.entries.len() >= PARALLEL_SORT,
                "{}",
                broad.entries.len()
            );
            found
        })
    };
    let (one, two) = (pairs(1), pairs(2));
    assert!(one.len() > 1000, "{} pairs", one.len());
    assert_eq!(one, two);
    let mut unique = one.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), one.len(), "a pair was reported twice");
}

/// The doubling search finds what a binary search over the rest finds, from every start.
#[test]
fn gallop_is_a_binary_search_from_its_start() {
    let entries: Vec<(u64, u32)> = (0..300u32).map(|i| ((i / 3 * 2) as u64, i)).collect();
    for from in 0..=entries.len() {
        for cell in 0..205u64 {
            let expected = from + entries[from..].partition_point(|&(k, _)| k < cell);
            assert_eq!(
                gallop(&entries, from, cell),
                expected,
                "from {from}, cell {cell}"
            );
        }
    }
}

/// Chains of 2 to 40 capsules (each joined link to link, some links also to the link before
/// last, as a ragdoll's limbs), one chain holding a large box, loose balls, a large wall and a
/// half-space, some bodies asleep, drifting step after step: the rebuild by groups finds
/// exactly the grid's pairs in the grid's order, on one thread and two, and the incremental
/// updates after it (which enter the grid first) agree too. A world whose groups are not runs
/// of consecutive bodies, or with a group of 200 bodies, falls back to the grid.
#[test]
fn groups_find_the_grids_pairs() {
    let mut random = uniform(4242);
    let mut bodies = vec![Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 0.0)];
    let mut links = Vec::new();
    while bodies.len() < 6000 {
        let length = 2 + (random() * 39.0) as usize;
        let at = Vec3::new(30.0 * random(), 1.5 * random(), 30.0 * random());
        let with_large = bodies.len() > 3000 && !links.iter().any(|&(a, _)| a > 3000);
        for link in 0..length {
            let this = bodies.len() as u32;
            if link > 0 {
                links.push((this - 1, this));
            }
            if link > 1 && random() < 0.3 {
                links.push((this - 2, this));
            }
            let capsule = Shape::Capsule {
                half_height: 0.1 + 0.1 * random(),
                radius: 0.05,
                axis: crate::shape::Axis::Y,
            };
            let spread = if length > 16 { 1.5 } else { 0.6 };
            let position = at + Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5) * spread;
            let turn = Quat::from_axis_angle(Vec3::X, 6.0 * random());
            let body = match with_large && link == 1 {
                true => Body::new("slab", BodyKind::Fixed, slab(), 0.0)
                    .with_pose(position - Vec3::Y, Quat::IDENTITY),
                false => Body::new("l", BodyKind::Dynamic, capsule, 1.0).with_pose(position, turn),
            };
            bodies.push(body);
        }
        if random() < 0.1 {
            let (x, y, z) = (30.0 * random(), random(), 30.0 * random());
            bodies.push(ball(x, y, z, 0.1, BodyKind::Dynamic));
        }
    }
    bodies.push(
        Body::new("ground", BodyKind::Fixed, slab(), 0.0)
            .with_pose(Vec3::new(15.0, -0.3, 15.0), Quat::IDENTITY),
    );
    let joined = || Joined::new(bodies.len(), links.iter().copied());
    let (dt, margin) = (1.0 / 60.0, 0.02);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut bodies = bodies.clone();
        let mut random = uniform(7);
        let (mut by_groups, mut by_cells) = (BroadPhase::default(), BroadPhase::default());
        by_groups.set_joined(joined());
        by_cells.set_joined(joined());
        by_cells.set_grid_only(true);
        for step in 0..12 {
            // a crowd moving (a rebuild) every third step, else a few bodies (an update)
            let crowd = step % 3 == 0;
            for (i, body) in bodies.iter_mut().enumerate().skip(1) {
                let reach = if crowd || i % 97 == step { 0.08 } else { 0.001 };
                let drift = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5) * reach;
                body.linear_velocity = drift / dt;
                body.set_pose(body.position + drift, body.orientation);
                if step == 7 && i % 50 < 12 {
                    body.asleep = true;
                }
            }
            let colliders = colliders(&bodies);
            let (mut grouped, mut celled) = (Vec::new(), Vec::new());
            pool.install(|| {
                by_groups.find_pairs(&colliders, dt, margin, |a, b| grouped.push((a, b)));
                by_cells.find_pairs(&colliders, dt, margin, |a, b| celled.push((a, b)));
            });
            assert!(celled.len() > 3000, "step {step}: {} pairs", celled.len());
            let first_difference = grouped.iter().zip(&celled).position(|(g, c)| g != c);
            assert_eq!(
                (grouped.len(), first_difference),
                (celled.len(), None),
                "{threads} threads, step {step}: pairs, and the first that differs"
            );
            if step == 0 {
                assert!(by_groups.grid_stale, "the groups rebuilt the pairs");
                assert!(!by_groups.large.is_empty(), "a large box");
            }
        }
    }
    // the grid where a group is too large (the first 200 bodies one rope), or a group is not a
    // run (the last chain's last link joined to the first body)
    let rope: Vec<(u32, u32)> = (1..200).map(|i| (i, i + 1)).collect();
    for extra in [rope, vec![(1, bodies.len() as u32 - 2)]] {
        let links = links.iter().copied().chain(extra);
        let mut broad = BroadPhase::default();
        broad.set_joined(Joined::new(bodies.len(), links));
        broad.find_pairs(&colliders(&bodies), dt, margin, |_, _| {});
        assert!(!broad.grid_stale, "the grid, not groups");
    }
}

/// A box too large for the grid's cells (80 m by 80 m, 10 cm thick).
fn slab() -> Shape {
    Shape::Cuboid {
        half_extents: Vec3::new(40.0, 0.05, 40.0),
    }
}
