//! The chain scene: links joined by ball-and-sockets or by rods, hung from a fixed support,
//! grouped as one ragdoll so the residual measures cover them.

use super::ROD_ALPHA_TWIST;
use crate::body::{Body, BodyKind};
use crate::constraint::{BallSocket, Constraint, Rod};
use crate::lab::Lab;
use crate::math::{Quat, Vec3};
use crate::ragdoll::Ragdoll;
use crate::shape::{Axis, Shape};
use crate::stress::Method;

/// Builds the chain scene; returns the potential energy its stretch hides (J).
pub(super) fn chain(
    lab: &mut Lab,
    method: Method,
    links: u32,
    horizontal: bool,
    stretch_m: f32,
) -> f32 {
    const HALF: f32 = 0.05;
    const RADIUS: f32 = 0.02;
    const MASS: f32 = 1.0;
    let world = &mut lab.world;
    let top = Vec3::new(0.0, 5.0, 0.0);
    let (along, axis, normal) = if horizontal {
        (Vec3::X, Axis::X, Vec3::Y)
    } else {
        (-Vec3::Y, Axis::Y, Vec3::Z)
    };
    let capsule = |name: String, kind, centre: Vec3| {
        Body::new(
            name,
            kind,
            Shape::Capsule {
                half_height: HALF,
                radius: RADIUS,
                axis,
            },
            MASS,
        )
        .with_pose(centre, Quat::IDENTITY)
    };
    // The support sits where a link before the first would, so the rods (centre to centre) and
    // the joints (end to end) make chains of the same length, 2 HALF per link.
    let mut previous = world.add_body(capsule(
        "support".into(),
        BodyKind::Fixed,
        top - HALF * along,
    ));
    for i in 0..links {
        let centre = top + HALF * (2 * i + 1) as f32 * along;
        let link = world.add_body(capsule(format!("link{i}"), BodyKind::Dynamic, centre));
        let name = format!("joint{i}");
        let constraint = if method == Method::Rod {
            let mut rod = Rod::instantiate(name, &world.bodies, previous, link, normal)
                .expect("link centres are 2 HALF apart");
            rod.params.alpha_bend = 0.0;
            rod.params.alpha_twist = ROD_ALPHA_TWIST;
            Constraint::Rod(rod)
        } else {
            let anchor = centre - HALF * along;
            let frame = crate::math::quat_from_rotation_arc(Vec3::X, along);
            Constraint::BallSocket(
                BallSocket::at_world_anchor(name, &world.bodies, previous, link, anchor, frame)
                    .with_flavour(method.joint_flavour()),
            )
        };
        world.add_constraint(constraint);
        previous = link;
    }
    // Pull each link stretch_m away from its joint, half along the chain and half sideways,
    // the side alternating, so the error is not along one line (where the cheap row, the exact
    // block and the rod's length correction all do the same thing).
    let mut hidden_energy = 0.0;
    let gravity = world.settings.gravity;
    let side = along.cross(normal);
    let mut shift = Vec3::ZERO;
    for (i, body) in world.bodies.iter_mut().skip(1).enumerate() {
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        shift += stretch_m * (along + sign * side).normalize();
        hidden_energy += body.mass * gravity.dot(shift);
        body.set_pose(body.position + shift, body.orientation);
    }
    let group = Ragdoll::group(
        "chain",
        0..world.bodies.len(),
        0..world.constraints.len(),
        world,
    );
    lab.ragdolls.push(group);
    hidden_energy.max(0.0)
}
