//! A checked scene built into a [`Lab`]: the world's settings, bodies, joints, rods and
//! ragdolls.

use super::locate::Seg;
use super::{BodyDef, JointDef, KindDef, RagdollDef, Scene, SceneDef, SceneError, ShapeKind};
use crate::body::{Body, BodyId, BodyKind};
use crate::constraint::{AngularLimit, BallSocket, Constraint, JointFlavour, Rod};
use crate::lab::Lab;
use crate::math::{quat_from_degrees, Iso, Vec3};
use crate::playback::Playback;
use crate::ragdoll::character::build_character;
use crate::ragdoll::{HumanoidSpec, Ragdoll, RodParams};
use crate::shape::Axis;
use crate::shape::Shape;
use crate::world::{Settings, World};

/// The name of the group that holds a scene's `[[body]]`s with its `[[joint]]`s and `[[rod]]`s
/// (bodies outside a ragdoll), so those constraints are measured, printed and recorded.
pub const LOOSE_GROUP: &str = "loose";

impl Scene {
    /// Builds the lab (world and ragdolls) this scene describes.
    pub fn build(&self) -> Result<Lab, SceneError> {
        let d = &self.def;
        let mut lab = Lab::new(World::new(settings(d)));
        for (i, r) in d.ragdoll.iter().enumerate() {
            let spec = humanoid_spec(d, r);
            let path = [
                Seg::Key("ragdoll".into()),
                Seg::Index(i),
                Seg::Key("spine".into()),
            ];
            lab.add_humanoid(&spec)
                .map_err(|m| self.error_at(&path, m))?;
        }
        for (i, c) in d.character.iter().enumerate() {
            let (rig, spec, played) = self.character_spec(i, c)?;
            let built = build_character(&mut lab.world, &rig, &spec);
            let path = [
                Seg::Key("character".into()),
                Seg::Index(i),
                Seg::Key("spine".into()),
            ];
            let ragdoll = built.map_err(|m| self.error_at(&path, m))?;
            if let Some(part_poses) = played {
                let playback = playback_of(&mut lab.world, &rig, &spec, &ragdoll, part_poses);
                lab.playbacks.push(playback);
            }
            lab.ragdolls.push(ragdoll);
        }
        let first_body = lab.world.bodies.len();
        let first_constraint = lab.world.constraints.len();
        let world = &mut lab.world;
        for b in &d.body {
            world.add_body(build_body(b));
        }
        for j in &d.joint {
            let joint = build_joint(
                j,
                &world.bodies,
                world.find_body(&j.a).expect("checked"),
                world.find_body(&j.b).expect("checked"),
                d.joint_flavour,
            );
            world.constraints.push(Constraint::BallSocket(joint));
        }
        for (i, r) in d.rod.iter().enumerate() {
            let (a, b) = (
                world.find_body(&r.a).expect("checked"),
                world.find_body(&r.b).expect("checked"),
            );
            let path = [Seg::Key("rod".into()), Seg::Index(i), Seg::Key("b".into())];
            let mut rod = Rod::instantiate(&r.name, &world.bodies, a, b, Vec3::from(r.normal))
                .map_err(|m| self.error_at(&path, m))?;
            rod.rest_length = r.rest_length.unwrap_or(rod.rest_length);
            rod.params = RodParams {
                alpha_bend: r.alpha_b,
                alpha_twist: r.alpha_t,
                bend_stiffness: r.stiffness().bend(),
                twist_stiffness: r.stiffness().twist(),
                twist_mode: r.twist,
                length_correction: r.length_correction,
                bend_twist: r.bend_twist,
            };
            world.constraints.push(Constraint::Rod(rod));
        }
        // the scene's own joints and rods form one group, measured like a ragdoll
        if !d.joint.is_empty() || !d.rod.is_empty() {
            let group = Ragdoll::group(
                LOOSE_GROUP,
                first_body..lab.world.bodies.len(),
                first_constraint..lab.world.constraints.len(),
                &lab.world,
            );
            lab.ragdolls.push(group);
        }
        Ok(lab)
    }
}

/// The world's settings this scene asks for.
fn settings(d: &SceneDef) -> Settings {
    let mut settings = Settings {
        gravity: Vec3::from(d.gravity),
        max_linear_speed: d.max_speed,
        max_angular_speed: d.max_angular_speed,
        max_separation: d.max_separation,
        max_penetration: d.max_penetration,
        contacts: d.contacts,
        contact_margin: d.contact_margin,
        linear_damping: d.damping[0],
        angular_damping: d.damping[1],
        ..Settings::default()
    };
    d.write_method_settings(&mut settings);
    settings
}

/// The humanoid a `[[ragdoll]]` describes (its alphas or stiffness, pose, forces, springs).
fn humanoid_spec(d: &SceneDef, r: &RagdollDef) -> HumanoidSpec {
    HumanoidSpec {
        name: r.name.clone(),
        spine: r.spine,
        joint_flavour: r.joint_flavour.unwrap_or(d.joint_flavour),
        root: Iso::new(Vec3::from(r.position), quat_from_degrees(r.rotation)),
        joint_rotations: r
            .pose
            .iter()
            .map(|(k, v)| (k.clone(), quat_from_degrees(*v)))
            .collect(),
        spine_spring: r.spine_spring,
        limb_spring: r.limb_spring,
        fixed: r.fixed.clone(),
        self_contacts: r.self_contacts,
        forces: r
            .forces
            .iter()
            .map(|(k, v)| (k.clone(), Vec3::from(*v)))
            .collect(),
        rod: {
            let default = RodParams::default();
            RodParams {
                alpha_bend: r.alpha_b.unwrap_or(default.alpha_bend),
                alpha_twist: r.alpha_t.unwrap_or(default.alpha_twist),
                bend_stiffness: r.stiffness().bend(),
                twist_stiffness: r.stiffness().twist(),
                twist_mode: r.twist.unwrap_or(default.twist_mode),
                length_correction: r.rod_length.unwrap_or(default.length_correction),
                bend_twist: r.bend_twist.unwrap_or(default.bend_twist),
            }
        },
    }
}

/// The ball-and-socket joint a `[[joint]]` describes between bodies `a` and `b`, with its
/// limits and spring.
fn build_joint(
    j: &JointDef,
    bodies: &[Body],
    a: BodyId,
    b: BodyId,
    default_flavour: JointFlavour,
) -> BallSocket {
    let frame = crate::math::quat_from_rotation_arc(Vec3::X, Vec3::from(j.axis).normalize());
    let mut joint = BallSocket::at_world_anchor(&j.name, bodies, a, b, Vec3::from(j.anchor), frame)
        .with_flavour(j.flavour.unwrap_or(default_flavour));
    if let Some([lo, hi]) = j.hinge {
        joint = joint.with_limit(AngularLimit::hinge(lo.to_radians(), hi.to_radians()));
    } else if j.swing.is_some() || j.twist.is_some() {
        let swing = j.swing.unwrap_or(180.0).to_radians();
        let [lo, hi] = j.twist.unwrap_or([-180.0, 180.0]);
        joint = joint.with_limit(AngularLimit::cone(swing, lo.to_radians(), hi.to_radians()));
    }
    if let Some(relaxation) = j.spring {
        joint = joint.with_spring(bodies, relaxation);
    }
    joint
}

fn build_body(b: &BodyDef) -> Body {
    let shape = match b.shape {
        ShapeKind::Sphere => Shape::Sphere {
            radius: b.radius.unwrap(),
        },
        ShapeKind::Capsule => Shape::Capsule {
            half_height: b.half_height.unwrap(),
            radius: b.radius.unwrap(),
            axis: b.axis.unwrap_or(Axis::Y),
        },
        ShapeKind::Box => Shape::Cuboid {
            half_extents: Vec3::from(b.half_extents.unwrap()),
        },
        ShapeKind::Plane => Shape::HalfSpace,
    };
    let kind = match b.kind {
        KindDef::Dynamic => BodyKind::Dynamic,
        KindDef::Fixed => BodyKind::Fixed,
        KindDef::Kinematic => BodyKind::Kinematic,
    };
    let mass = b
        .mass
        .unwrap_or_else(|| b.density.unwrap_or(1000.0) * shape.volume());
    let mut body = Body::new(&b.name, kind, shape, mass)
        .with_pose(Vec3::from(b.position), quat_from_degrees(b.rotation));
    if kind != BodyKind::Fixed {
        body.linear_velocity = Vec3::from(b.velocity);
        body.angular_velocity = Vec3::from(b.angular_velocity);
    }
    body.static_friction = b.static_friction.unwrap_or(body.static_friction);
    body.dynamic_friction = b.dynamic_friction.unwrap_or(body.dynamic_friction);
    body.restitution = b.restitution.unwrap_or(body.restitution);
    body.collision_group = b.collision_group.unwrap_or(body.collision_group);
    body.collision_mask = b.collision_mask.unwrap_or(body.collision_mask);
    body
}

/// A character's clip played on its bodies: each body keeps the offset from its part it was
/// built with at the handover pose, and follows the part's pose frame by frame.
fn playback_of(
    world: &mut World,
    rig: &crate::rig::Rig,
    spec: &crate::ragdoll::character::CharacterSpec,
    ragdoll: &Ragdoll,
    part_poses: Vec<Vec<Iso>>,
) -> Playback {
    let prefix = format!("{}/", spec.name);
    let mut bodies = Vec::new();
    let mut offsets = Vec::new();
    for index in ragdoll.bodies.clone() {
        let body = &world.bodies[index];
        let joint = body.name.strip_prefix(&prefix).unwrap_or(&body.name);
        let Some(part) = rig.part_index(joint) else {
            continue;
        };
        let at = Iso::new(body.position, body.orientation);
        bodies.push((BodyId(index as u32), part));
        offsets.push(spec.pose[part].inverse() * at);
    }
    let poses = (part_poses.iter())
        .map(|parts| {
            (bodies.iter().zip(&offsets))
                .map(|(&(_, p), &o)| parts[p] * o)
                .collect()
        })
        .collect();
    Playback::start(world, bodies.iter().map(|&(id, _)| id).collect(), poses)
}
