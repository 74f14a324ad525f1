//! A game character built from a rig ([`crate::rig::Rig`]): one body per part at the pose an
//! animation clip gives at a chosen time and moving as the clip does there (the handover of
//! §6), the rig's swing-twist joints, its collision filter, and a spine that is the rig's own,
//! one rod, or one ball-and-socket.
//!
//! The spine region is named by its two end parts (`from`, the lower, and `to`, an
//! ancestor-chain descendant of it: the hips and the chest). With [`SpineKind::Rod`] the
//! parts strictly between them leave, and the two ends are joined by one rod instantiated at
//! the pose (paper §6: rest length and frames from the pose at the transition); with
//! [`SpineKind::Single`] they are joined by one ball-and-socket at the region's first
//! joint, its swing and twist ranges the sum of the region's joints'. Either way the leaving
//! parts' mass is shared equally by the two ends (their inertia scaled with it), so the
//! character weighs what the rig does, as the reference humanoid's spines do.
//!
//! Given the game's animation skeleton, the character carries it posed back from its bodies
//! ([`MappedSkeleton`]): the spine's bones by the §6 methods, measured as the humanoid's are.
//!
//! What the solver's bodies take from a part, and what they approximate:
//! - mass, centre of mass and inertia from the part's true shapes (tapered capsules exact);
//!   the body's frame is the part's first shape's, at the centre of mass, with the inertia
//!   tensor's diagonal in that frame (the shapes are symmetric about it: the off-diagonal terms
//!   are at most a few percent of the largest moment, tested);
//! - collision: one shape centred on the centre of mass: a capsule (a tapered capsule's radius
//!   the mean of its two; a two-capsule neck part one capsule as wide as both) or a box;
//! - a joint's swing cone is circular, its half angle the larger of the rig's two (Jolt's cone
//!   is elliptic); the rig's per-joint friction torques are not read (the method setting
//!   `joint_friction` applies one to every joint).

use crate::body::{Body, BodyId, BodyKind};
use crate::constraint::{AngularLimit, BallSocket, Constraint, JointFlavour, Rod, RodParams};
use crate::math::{Iso, Mat3, Quat, Vec3};
use crate::rig::skeleton::{AnimationSkeleton, Handover, MappedSkeleton};
use crate::rig::{PartShape, Rig, SwingTwist};
use crate::shape::{Axis, Shape};
use crate::world::World;

use super::{Ragdoll, SpineKind};

/// What to build: a rig at a pose, with a spine.
#[derive(Clone, Debug)]
pub struct CharacterSpec {
    /// Name, the prefix of its bodies' and joints' names.
    pub name: String,
    /// The rig's parts' world poses (in the rig's part order), placement included.
    pub pose: Vec<Iso>,
    /// Each part's velocity there, of its origin and its turn (m/s, rad/s, world): what the
    /// animation hands over.
    pub velocities: Vec<(Vec3, Vec3)>,
    /// The spine to simulate.
    pub spine: SpineKind,
    /// The spine region's end parts, lower first (joint names).
    pub region: (String, String),
    /// Parts held fixed (joint names).
    pub fixed: Vec<String>,
    /// Flavour of every ball-and-socket joint.
    pub joint_flavour: JointFlavour,
    /// The rod's settings, with [`SpineKind::Rod`].
    pub rod: RodParams,
    /// The game's animation skeleton and its joints' neutral local transforms, posed back
    /// from the bodies (§6, [`MappedSkeleton`]); none: the character carries no skeleton.
    pub animation_skeleton: Option<(AnimationSkeleton, Vec<Iso>)>,
}

/// The region's end parts and the parts strictly between them, or why the region is not a
/// parent chain.
pub fn region_parts(rig: &Rig, from: &str, to: &str) -> Result<(usize, usize, Vec<usize>), String> {
    let index = |name: &str| {
        rig.part_index(name)
            .ok_or_else(|| format!("the rig {} has no part {name:?}", rig.name))
    };
    let (from, to) = (index(from)?, index(to)?);
    let mut interior = Vec::new();
    let mut at = rig.parts[to].parent;
    while let Some(i) = at {
        if i == from {
            interior.reverse();
            return Ok((from, to, interior));
        }
        interior.push(i);
        at = rig.parts[i].parent;
    }
    Err(format!(
        "{:?} is not an ancestor of {:?} in the rig {}",
        rig.parts[from].joint_name, rig.parts[to].joint_name, rig.name
    ))
}

/// Builds the character into `world`: its bodies (the parts but the removed ones), joints,
/// spine and collision filter. The returned group measures like a ragdoll.
pub fn build_character(
    world: &mut World,
    rig: &Rig,
    spec: &CharacterSpec,
) -> Result<Ragdoll, String> {
    let (from, to, interior) = region_parts(rig, &spec.region.0, &spec.region.1)?;
    let removed =
        match spec.spine {
            SpineKind::Rig => Vec::new(),
            SpineKind::Chain3 => return Err(
                "chain3 is the reference humanoid's spine; a character takes rig, rod or single"
                    .into(),
            ),
            _ if interior.is_empty() => {
                return Err(format!(
                    "the spine region {:?} to {:?} has no part between its ends to replace",
                    spec.region.0, spec.region.1
                ))
            }
            _ => interior,
        };
    for name in &spec.fixed {
        match rig.part_index(name) {
            Some(i) if !removed.contains(&i) => {}
            Some(_) => {
                return Err(format!(
                    "fixed part {name:?} leaves with the {} spine",
                    spec.spine
                ))
            }
            None => return Err(format!("the rig {} has no part {name:?} to fix", rig.name)),
        }
    }
    let shared: f32 = removed.iter().map(|&i| rig.parts[i].mass.mass).sum::<f32>() / 2.0;
    let first_body = world.bodies.len();
    let mut body_of = vec![None; rig.parts.len()];
    for (i, part) in rig.parts.iter().enumerate() {
        if removed.contains(&i) {
            continue;
        }
        let extra = if i == from || i == to { shared } else { 0.0 };
        let kind = match spec.fixed.contains(&part.joint_name) {
            true => BodyKind::Fixed,
            false => BodyKind::Dynamic,
        };
        let (mut body, frame) = part_body(part, extra, kind);
        let pose = spec.pose[i] * frame;
        body.name = format!("{}/{}", spec.name, part.joint_name);
        if kind == BodyKind::Dynamic {
            // the centre of mass moves with the part's origin and turns about it
            let (linear, angular) = spec.velocities[i];
            let arm = spec.pose[i].rotation * frame.translation;
            body.linear_velocity = linear + angular.cross(arm);
            body.angular_velocity = angular;
        }
        body_of[i] = Some(world.add_body(body.with_pose(pose.translation, pose.rotation)));
    }
    let first_constraint = world.constraints.len();
    let id = |i: usize| body_of[i].expect("a kept part");
    for joint in &rig.constraints {
        if removed.contains(&joint.body1) || removed.contains(&joint.body2) {
            continue;
        }
        let limit = limit_of(joint);
        let name = format!("{}/{}", spec.name, rig.parts[joint.body2].joint_name);
        let ball = ball_socket(
            world,
            joint,
            rig,
            &spec.pose,
            (id(joint.body1), id(joint.body2)),
            name,
            limit,
            spec.joint_flavour,
        );
        world.constraints.push(Constraint::BallSocket(ball));
    }
    let mut rod_index = None;
    match spec.spine {
        SpineKind::Rig | SpineKind::Chain3 => {}
        SpineKind::Rod => {
            let forward = spec.pose[from].rotation * Vec3::Z;
            let mut rod = Rod::instantiate(
                format!("{}/spine_rod", spec.name),
                &world.bodies,
                id(from),
                id(to),
                forward,
            )?;
            rod.params = spec.rod;
            rod_index = Some(world.constraints.len());
            world.constraints.push(Constraint::Rod(rod));
        }
        SpineKind::Single => {
            // the region's joints, from its first (at `from`) to its last (into `to`)
            let chain: Vec<&SwingTwist> = (rig.constraints.iter())
                .filter(|j| {
                    (removed.contains(&j.body2) || j.body2 == to)
                        && (j.body1 == from || removed.contains(&j.body1))
                })
                .collect();
            let first = chain.first().ok_or("the spine region has no joint")?;
            let limit = chain.iter().map(|j| limit_of(j)).fold(
                AngularLimit::cone(0.0, 0.0, 0.0),
                |sum, l| {
                    AngularLimit::cone(
                        sum.swing_max + l.swing_max,
                        sum.twist_min + l.twist_min,
                        sum.twist_max + l.twist_max,
                    )
                },
            );
            let name = format!("{}/spine_joint", spec.name);
            let ball = ball_socket(
                world,
                first,
                rig,
                &spec.pose,
                (id(from), id(to)),
                name,
                limit,
                spec.joint_flavour,
            );
            world.constraints.push(Constraint::BallSocket(ball));
        }
    }
    // the rig's filter, and the spine's ends
    let mut pairs = rig.no_collide.clone();
    pairs.push((from.min(to), from.max(to)));
    for (a, b) in pairs {
        if let (Some(a), Some(b)) = (body_of[a], body_of[b]) {
            world.constraints.filter_contacts(a, b);
        }
    }
    let mut ragdoll = Ragdoll::group(
        &spec.name,
        first_body..world.bodies.len(),
        first_constraint..world.constraints.len(),
        world,
    );
    ragdoll.spine = Some(spec.spine);
    if let Some((skeleton, neutral_locals)) = &spec.animation_skeleton {
        let handover = Handover {
            rig,
            parts: &spec.pose,
            bodies: &body_of,
        };
        let region = (spec.region.0.as_str(), spec.region.1.as_str());
        let mapped = MappedSkeleton::new(
            world,
            skeleton,
            neutral_locals,
            &handover,
            region,
            rod_index,
        )?;
        ragdoll.skeleton = Some(mapped.spine().clone());
        ragdoll.hd_skeleton = Some(mapped);
    }
    Ok(ragdoll)
}

/// A part's body at the origin (its mass `extra` heavier, inertia scaled with it), and where
/// the body sits in the part's frame: at its centre of mass, turned as its first shape.
fn part_body(part: &crate::rig::Part, extra: f32, kind: BodyKind) -> (Body, Iso) {
    let first = &part.shapes[0];
    let mass = part.mass.scaled_to_mass(part.mass.mass + extra);
    let turn = Mat3::from_quat(first.rotation);
    let inertia = turn.transpose() * mass.inertia * turn;
    let shape = match first.shape {
        PartShape::Capsule {
            half_height,
            radius,
        } => {
            // a second, parallel capsule (a neck part) widens the one capsule to cover both
            let spread = (part.shapes.iter())
                .map(|s| (s.position - first.position).length() / 2.0)
                .fold(0.0f32, f32::max);
            Shape::Capsule {
                half_height,
                radius: radius + spread,
                axis: Axis::Y,
            }
        }
        PartShape::TaperedCapsule {
            half_height,
            top_radius,
            bottom_radius,
        } => Shape::Capsule {
            half_height,
            radius: 0.5 * (top_radius + bottom_radius),
            axis: Axis::Y,
        },
        PartShape::Box { half_extent, .. } => Shape::Cuboid {
            half_extents: half_extent,
        },
    };
    let mut body = Body::new(&part.joint_name, kind, shape, mass.mass);
    body.set_inertia(Vec3::new(
        inertia.x_axis.x,
        inertia.y_axis.y,
        inertia.z_axis.z,
    ));
    body.static_friction = part.friction;
    body.dynamic_friction = part.friction;
    body.restitution = part.restitution;
    (body, Iso::new(mass.com, first.rotation))
}

/// The joint's limit: a circular cone as wide as the rig's wider half angle, its twist range.
fn limit_of(joint: &SwingTwist) -> AngularLimit {
    let swing = joint
        .normal_half_cone_angle
        .max(joint.plane_half_cone_angle);
    AngularLimit::cone(swing, joint.twist_min_angle, joint.twist_max_angle)
}

/// The rig's joint `joint` between `bodies`, its frames (x the twist axis, z the plane axis)
/// taken from the rig's pose of each part and carried to `pose`.
#[allow(clippy::too_many_arguments)]
fn ball_socket(
    world: &World,
    joint: &SwingTwist,
    rig: &Rig,
    pose: &[Iso],
    bodies: (BodyId, BodyId),
    name: String,
    limit: AngularLimit,
    flavour: JointFlavour,
) -> BallSocket {
    let [frame1, frame2] = joint.body_frames(rig);
    let (a, b) = (
        &world.bodies[bodies.0.index()],
        &world.bodies[bodies.1.index()],
    );
    let in_body = |body: &Body, part: usize, (anchor, twist, plane): (Vec3, Vec3, Vec3)| {
        let frame = Quat::from_mat3(&Mat3::from_cols(twist, plane.cross(twist), plane));
        let world_anchor = pose[part].transform_point(anchor);
        let world_frame = pose[part].rotation * frame;
        let inverse = body.orientation.inverse();
        (
            inverse * (world_anchor - body.position),
            (inverse * world_frame).normalize(),
        )
    };
    let (anchor_a, frame_a) = in_body(a, joint.body1, frame1);
    let (anchor_b, frame_b) = in_body(b, joint.body2, frame2);
    BallSocket {
        name,
        body_a: bodies.0,
        body_b: bodies.1,
        local_anchor_a: anchor_a,
        local_anchor_b: anchor_b,
        local_frame_a: frame_a,
        local_frame_b: frame_b,
        flavour,
        limit: Some(limit),
        spring: None,
        collide_connected: false,
    }
}
