//! Contacts: resting and friction against their analytic solutions, tunnelling and filtering,
//! stacks, sleeping, and overlap recovery, one file each; the helpers they share are here.

use rodlab::body::{Body, BodyKind};
use rodlab::math::{Quat, Vec3};
use rodlab::ragdoll::{build_humanoid, HumanoidSpec, SpineKind};
use rodlab::shape::{Axis, Shape};
use rodlab::world::{Settings, World};

mod overlap;
mod resting;
mod sleeping;
mod stacks;
mod tunnelling;

fn settings() -> Settings {
    Settings {
        contacts: true,
        ..Settings::default()
    }
}

fn plane(world: &mut World, rotation: Quat) {
    world.add_body(
        Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0).with_pose(Vec3::ZERO, rotation),
    );
}

/// A 1 kg ball of 10 cm radius named "ball" at `position`.
fn ball(position: Vec3) -> Body {
    Body::new(
        "ball",
        BodyKind::Dynamic,
        Shape::Sphere { radius: 0.1 },
        1.0,
    )
    .with_pose(position, Quat::IDENTITY)
}

fn sleepy_box(world: &mut World, name: &str, position: Vec3) -> rodlab::body::BodyId {
    world.add_body(
        Body::new(
            name,
            BodyKind::Dynamic,
            Shape::Cuboid {
                half_extents: Vec3::new(0.2, 0.1, 0.15),
            },
            4.0,
        )
        .with_pose(position, Quat::IDENTITY),
    )
}
