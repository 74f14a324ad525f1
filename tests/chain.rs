//! Convergence: a hanging chain at rest keeps its joints together with the exact joint, and the
//! residual falls as iterations rise.

use rodlab::body::{Body, BodyKind};
use rodlab::constraint::{BallSocket, JointFlavour};
use rodlab::math::{Quat, Vec3};
use rodlab::metrics::ragdoll_residual;
use rodlab::ragdoll::{Ragdoll, SpineKind};
use rodlab::shape::{Axis, Shape};
use rodlab::world::{Settings, World};

const LINKS: usize = 8;
const HALF: f32 = 0.1;

/// A chain of `LINKS` capsules hanging straight down from a fixed support, at rest.
fn hanging_chain(flavour: JointFlavour, iterations: u32) -> (World, Ragdoll) {
    let mut world = World::new(Settings {
        iterations,
        ..Settings::default()
    });
    let top = Vec3::new(0.0, 3.0, 0.0);
    let support = world.add_body(
        Body::new(
            "support",
            BodyKind::Fixed,
            Shape::Sphere { radius: 0.03 },
            1.0,
        )
        .with_pose(top, Quat::IDENTITY),
    );
    let mut previous = support;
    for i in 0..LINKS {
        let centre = top - Vec3::Y * (HALF * (2 * i + 1) as f32);
        let link = world.add_body(
            Body::new(
                format!("link{i}"),
                BodyKind::Dynamic,
                Shape::Capsule {
                    half_height: HALF,
                    radius: 0.03,
                    axis: Axis::Y,
                },
                1.0,
            )
            .with_pose(centre, Quat::IDENTITY),
        );
        let anchor = centre + Vec3::Y * HALF;
        world.add_constraint(
            BallSocket::at_world_anchor(
                format!("j{i}"),
                &world.bodies,
                previous,
                link,
                anchor,
                Quat::IDENTITY,
            )
            .with_flavour(flavour),
        );
        previous = link;
    }
    // Group everything as one "ragdoll" to reuse the residual measure.
    let group = Ragdoll {
        name: "chain".into(),
        spine: SpineKind::Chain3,
        bodies: 0..world.bodies.len(),
        constraints: 0..world.constraints.len(),
        skeleton: None,
        target_positions: Vec::new(),
    };
    world.ragdolls.push(group.clone());
    (world, group)
}

fn mean_residual_cm(flavour: JointFlavour, iterations: u32, frames: usize) -> f32 {
    let (mut world, group) = hanging_chain(flavour, iterations);
    let mut total = 0.0;
    for _ in 0..frames {
        world.step().unwrap();
        total += ragdoll_residual(&world, &group).dislocation_cm;
    }
    total / frames as f32
}

/// Every joint's dislocation (distance between its anchors) stays under 0.1 cm for 10 s.
#[test]
fn exact_chain_at_rest_stays_together() {
    let (mut world, _) = hanging_chain(JointFlavour::Exact, 20);
    for frame in 0..600 {
        world.step().unwrap();
        for c in &world.constraints {
            let cm = 100.0 * c.violation(&world.bodies).dislocation;
            assert!(
                cm < 0.1,
                "frame {frame}: joint {} dislocated by {cm} cm",
                c.name()
            );
        }
    }
    // and it stays at rest
    let bottom = world.find_body(&format!("link{}", LINKS - 1)).unwrap();
    assert!(world.body(bottom).linear_velocity.length() < 1e-2);
}

#[test]
fn residual_falls_with_iterations() {
    for flavour in [JointFlavour::Cheap, JointFlavour::Exact] {
        let r: Vec<f32> = [2, 8, 32]
            .iter()
            .map(|&n| mean_residual_cm(flavour, n, 120))
            .collect();
        assert!(
            r[0] > r[1] && r[1] > r[2],
            "{flavour:?}: residuals {r:?} should fall with iterations"
        );
    }
}
