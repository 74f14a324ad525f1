//! The humanoid builder: the spec checked, the parts posed by forward kinematics, then the
//! bodies, the rod spine if any and the joints added to the world, in that order, then the
//! pairs its `self_contacts` keeps from colliding.

use super::table::{has_part, joint_defs, joint_names, LimitDef, Part, PARTS, TOTAL_MASS};
use super::{HumanoidSpec, Ragdoll, SelfContacts, SpineKind};
use crate::body::{Body, BodyId, BodyKind};
use crate::constraint::{AngularLimit, BallSocket, Constraint, Rod};
use crate::contact::collider::Collider;
use crate::contact::narrowphase;
use crate::math::{Iso, Quat, Vec3};
use crate::shape::Shape;
use crate::skeleton::Skeleton;
use crate::world::World;

fn v2(c: [f32; 2]) -> Vec3 {
    Vec3::new(c[0], c[1], 0.0)
}

/// Builds the humanoid's bodies and constraints into `world` and returns the ragdoll that groups
/// them (the caller keeps it, usually in a [`crate::lab::Lab`]). Errors name the unknown joint
/// or part.
pub fn build_humanoid(world: &mut World, spec: &HumanoidSpec) -> Result<Ragdoll, String> {
    let spine = spec.spine;
    check_joints(spec)?;
    let parts: Vec<&Part> = PARTS.iter().filter(|p| has_part(spine, p.name)).collect();
    check_parts(spec, &parts)?;
    let index_of = |name: &str| {
        parts
            .iter()
            .position(|p| p.name == name)
            .expect("joint tables name known parts")
    };
    let posed = pose_parts(spec, &parts, index_of);

    let first_body = world.bodies.len();
    add_bodies(world, spec, &parts, &posed);

    let first_constraint = world.constraints.len();
    if spine == SpineKind::Rod {
        add_spine_rod(world, spec, first_body, index_of)?;
    }
    add_joints(world, spec, &parts, first_body, index_of);
    filter_self_contacts(
        world,
        spec.self_contacts,
        &parts,
        first_body,
        first_constraint,
    );

    let spine_bodies: Vec<(BodyId, f32)> = ["pelvis", "lower_spine", "upper_spine", "chest"]
        .iter()
        .filter(|n| has_part(spine, n))
        .map(|n| {
            (
                BodyId((first_body + index_of(n)) as u32),
                parts[index_of(n)].centre[1],
            )
        })
        .collect();
    let rod = (spine == SpineKind::Rod).then_some(first_constraint);
    Ok(Ragdoll {
        name: spec.name.clone(),
        spine: Some(spine),
        bodies: first_body..world.bodies.len(),
        constraints: first_constraint..world.constraints.len(),
        skeleton: Some(Skeleton::attach(world, &spine_bodies, rod)),
        hd_skeleton: None,
        target_positions: world.bodies[first_body..]
            .iter()
            .map(|b| b.position)
            .collect(),
    })
}

/// Keeps the pairs of the ragdoll's bodies that `self_contacts` excludes from colliding
/// ([`crate::constraint::Constraints::filter_contacts`]), but for those its joints and rod (from
/// `first_constraint` on) already keep apart.
fn filter_self_contacts(
    world: &mut World,
    self_contacts: SelfContacts,
    parts: &[&Part],
    first_body: usize,
    first_constraint: usize,
) {
    if self_contacts == SelfContacts::All {
        return;
    }
    let body = |k: usize| BodyId((first_body + k) as u32);
    let joined: Vec<(BodyId, BodyId)> = (world.constraints[first_constraint..].iter())
        .filter(|c| c.keeps_bodies_apart())
        .map(Constraint::bodies)
        .collect();
    let is_joined = |a: BodyId, b: BodyId| joined.contains(&(a, b)) || joined.contains(&(b, a));
    // the standing reference pose: each part at its centre, unrotated
    let margin = world.settings.contact_margin;
    let at_rest: Vec<Collider> = (parts.iter())
        .map(|p| {
            let body = Body::new(p.name, BodyKind::Dynamic, part_shape(p), 1.0);
            Collider::new(&body.with_pose(v2(p.centre), Quat::IDENTITY))
        })
        .collect();
    let mut features = Vec::new();
    for i in 0..parts.len() {
        for j in i + 1..parts.len() {
            if is_joined(body(i), body(j)) {
                continue;
            }
            let filtered = match self_contacts {
                SelfContacts::All => false,
                SelfContacts::None => true,
                SelfContacts::ApartAtRest => {
                    features.clear();
                    narrowphase::collide(&at_rest[i], &at_rest[j], margin, &mut features)
                }
            };
            if filtered {
                world.constraints.filter_contacts(body(i), body(j));
            }
        }
    }
}

/// The pose's joint names must be the spine's.
fn check_joints(spec: &HumanoidSpec) -> Result<(), String> {
    let spine = spec.spine;
    let known_joints = joint_names(spine);
    for (joint, _) in &spec.joint_rotations {
        if !known_joints.contains(&joint.as_str()) {
            return Err(format!(
                "unknown joint \"{joint}\" for spine {spine}, expected one of {}",
                known_joints.join(", ")
            ));
        }
    }
    Ok(())
}

/// Forces and fixed parts must name parts of the spine.
fn check_parts(spec: &HumanoidSpec, parts: &[&Part]) -> Result<(), String> {
    for (name, _) in &spec.forces {
        if !parts.iter().any(|p| p.name == name) {
            let names: Vec<_> = parts.iter().map(|p| p.name).collect();
            return Err(format!(
                "unknown part \"{name}\", expected one of {}",
                names.join(", ")
            ));
        }
    }
    for fixed in &spec.fixed {
        if !parts.iter().any(|p| p.name == fixed) {
            let names: Vec<_> = parts.iter().map(|p| p.name).collect();
            return Err(format!(
                "unknown part \"{fixed}\", expected one of {}",
                names.join(", ")
            ));
        }
    }
    Ok(())
}

/// Forward kinematics from the reference pose (all parts axis-aligned): the parts' starting poses.
fn pose_parts(spec: &HumanoidSpec, parts: &[&Part], index_of: impl Fn(&str) -> usize) -> Vec<Iso> {
    let spine = spec.spine;
    let reference: Vec<Iso> = parts
        .iter()
        .map(|p| Iso::new(v2(p.centre), Quat::IDENTITY))
        .collect();
    let mut posed = reference.clone();
    posed[0] = spec.root * reference[0];
    for def in joint_defs(spine) {
        let (parent, child) = (index_of(def.parent), index_of(def.child));
        let rotation = spec
            .joint_rotations
            .iter()
            .find(|(n, _)| n == def.name)
            .map_or(Quat::IDENTITY, |(_, q)| *q);
        let centre = v2(def.centre);
        let about_joint = Iso::new(centre, rotation) * Iso::new(-centre, Quat::IDENTITY);
        posed[child] = posed[parent] * reference[parent].inverse() * about_joint * reference[child];
    }
    posed
}

/// A part's capsule.
fn part_shape(p: &Part) -> Shape {
    Shape::Capsule {
        half_height: p.half_height,
        radius: p.radius,
        axis: p.axis,
    }
}

/// One body per part at its starting pose; with `single` and `rod`, pelvis and chest also take
/// the removed spine bodies' mass.
fn add_bodies(world: &mut World, spec: &HumanoidSpec, parts: &[&Part], posed: &[Iso]) {
    let spine = spec.spine;
    // single and rod: the two removed spine bodies' mass is shared by pelvis and chest
    let extra_mass = if spine == SpineKind::Chain3 {
        0.0
    } else {
        0.5 * 2.0 * 0.08165 * TOTAL_MASS
    };
    for (p, pose) in parts.iter().zip(posed) {
        let kind = if spec.fixed.iter().any(|f| f == p.name) {
            BodyKind::Fixed
        } else {
            BodyKind::Dynamic
        };
        let mass = p.mass_fraction * TOTAL_MASS
            + if matches!(p.name, "pelvis" | "chest") {
                extra_mass
            } else {
                0.0
            };
        let shape = part_shape(p);
        let mut body = Body::new(format!("{}/{}", spec.name, p.name), kind, shape, mass)
            .with_pose(pose.translation, pose.rotation);
        body.external_force = spec
            .forces
            .iter()
            .filter(|(n, _)| n == p.name)
            .map(|(_, f)| *f)
            .sum();
        world.add_body(body);
    }
}

/// The rod spine (paper §5) between pelvis and chest, instantiated at the starting pose (§6).
fn add_spine_rod(
    world: &mut World,
    spec: &HumanoidSpec,
    first_body: usize,
    index_of: impl Fn(&str) -> usize,
) -> Result<(), String> {
    let (pelvis, chest) = (index_of("pelvis"), index_of("chest"));
    let forward = spec.root.rotation * Vec3::Z;
    let id = |i: usize| BodyId((first_body + i) as u32);
    let mut rod = Rod::instantiate(
        format!("{}/spine_rod", spec.name),
        &world.bodies,
        id(pelvis),
        id(chest),
        forward,
    )?;
    rod.params = spec.rod;
    world.constraints.push(Constraint::Rod(rod));
    Ok(())
}

/// The ball-and-socket joints, each with its limit (and spring, where the spec asks for one).
fn add_joints(
    world: &mut World,
    spec: &HumanoidSpec,
    parts: &[&Part],
    first_body: usize,
    index_of: impl Fn(&str) -> usize,
) {
    let spine = spec.spine;
    // The rod spine replaces the lumbosacral joint, which only served the pose above.
    for def in joint_defs(spine).filter(|d| !(spine == SpineKind::Rod && d.spine)) {
        let (parent, child) = (index_of(def.parent), index_of(def.child));
        let centre = v2(def.centre);
        let frame = def.axis.rotation();
        let limit = match def.limit {
            LimitDef::Cone { swing, twist } => {
                AngularLimit::cone(swing.to_radians(), -twist.to_radians(), twist.to_radians())
            }
            LimitDef::Hinge { min, max } => AngularLimit::hinge(min.to_radians(), max.to_radians()),
        };
        let mut joint = BallSocket {
            name: format!("{}/{}", spec.name, def.name),
            body_a: BodyId((first_body + parent) as u32),
            body_b: BodyId((first_body + child) as u32),
            local_anchor_a: centre - v2(parts[parent].centre),
            local_anchor_b: centre - v2(parts[child].centre),
            local_frame_a: frame,
            local_frame_b: frame,
            flavour: spec.joint_flavour,
            limit: Some(limit),
            spring: None,
            collide_connected: false,
        };
        let spring = if def.spine {
            spec.spine_spring
        } else {
            spec.limb_spring
        };
        if let Some(relaxation) = spring {
            joint = joint.with_spring(&world.bodies, relaxation);
        }
        world.constraints.push(Constraint::BallSocket(joint));
    }
}
