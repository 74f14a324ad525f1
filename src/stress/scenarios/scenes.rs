//! Building a case's scene: [`build`] dispatches over the scenarios to a builder each; the
//! humanoid's settings for the suite, and bending its spine at the start. The chain scene is in
//! [`super::chain`].

use std::f32::consts::PI;

use super::chain::chain;
use super::{Built, Scenario, FOREARM_MASS, ROD_ALPHA_BEND, ROD_ALPHA_TWIST, SPINE_SPRING};
use crate::body::{Body, BodyId, BodyKind};
use crate::constraint::rod::arc_point;
use crate::constraint::{BallSocket, Constraint};
use crate::lab::Lab;
use crate::math::{Iso, Quat, Vec3};
use crate::ragdoll::{HumanoidSpec, Ragdoll, RodParams, SpineKind};
use crate::shape::Shape;
use crate::stress::Method;
use crate::world::{Settings, World};

pub(super) fn build(
    scenario: Scenario,
    settings: Settings,
    frames: u32,
    method: Method,
) -> Option<Built> {
    let mut lab = Lab::new(World::new(settings));
    let mut settles = true;
    let mut energy_allowance = 0.0;
    match scenario {
        Scenario::Slump {
            tilt_deg,
            stiff_spine,
            forearm_mass_divisor,
        } => {
            settles = false; // the arms swing on: nothing damps them
            build_slump(
                &mut lab,
                method,
                tilt_deg,
                stiff_spine,
                forearm_mass_divisor,
            );
        }
        Scenario::HeavyHand { mass_ratio } => {
            settles = false; // the upper body gives way under the weight and swings
            build_heavy_hand(&mut lab, method, mass_ratio);
        }
        Scenario::Chain {
            links,
            horizontal,
            stretch_m,
        } => {
            if method == Method::Single {
                return None;
            }
            settles = !horizontal;
            energy_allowance = chain(&mut lab, method, links, horizontal, stretch_m);
        }
        Scenario::Projectile { mass, speed } => {
            settles = false; // the sphere rolls on (no rolling resistance)
            build_projectile(&mut lab, method, mass, speed);
        }
        Scenario::BentSpine { psi_deg } => {
            settles = false; // the upper body falls and swings
            let mut spec = humanoid(method, false);
            spec.fixed = vec!["pelvis".into()];
            energy_allowance = bend_spine(&mut lab, spec, psi_deg.to_radians(), false);
        }
        Scenario::Hanging { psi_deg } => {
            let mut spec = humanoid(method, false);
            spec.fixed = vec!["head".into()];
            energy_allowance = bend_spine(&mut lab, spec, psi_deg.to_radians(), true);
        }
    }
    Some(Built {
        lab,
        frames,
        settles,
        energy_allowance,
    })
}

/// [`Scenario::Slump`]: passive bending, pelvis fixed, the upper body tilted by `tilt_deg`, the
/// forearms' mass divided by `forearm_mass_divisor`.
fn build_slump(
    lab: &mut Lab,
    method: Method,
    tilt_deg: f32,
    stiff_spine: bool,
    forearm_mass_divisor: f32,
) {
    let mut spec = humanoid(method, stiff_spine);
    spec.fixed = vec!["pelvis".into()];
    spec.joint_rotations = spine_bend(method.spine(), tilt_deg.to_radians());
    let ragdoll = add_humanoid(lab, &spec);
    for forearm in ["forearm_l", "forearm_r"] {
        let id = ragdoll
            .part(&lab.world, forearm)
            .expect("humanoid has forearms");
        lab.world
            .body_mut(id)
            .set_mass(FOREARM_MASS / forearm_mass_divisor);
    }
}

/// [`Scenario::HeavyHand`]: pelvis fixed, a sphere of `mass_ratio` forearm masses held in the
/// left hand by a ball-and-socket of the method's flavour.
fn build_heavy_hand(lab: &mut Lab, method: Method, mass_ratio: f32) {
    let mut spec = humanoid(method, false);
    spec.fixed = vec!["pelvis".into()];
    let ragdoll = add_humanoid(lab, &spec);
    let world = &mut lab.world;
    let forearm = ragdoll.part(world, "forearm_l").expect("left forearm");
    let radius = 0.1;
    let hand = world.body(forearm).world_point(Vec3::new(0.0, -0.22, 0.0));
    let weight = world.add_body(
        Body::new(
            "weight",
            BodyKind::Dynamic,
            Shape::Sphere { radius },
            mass_ratio * FOREARM_MASS,
        )
        .with_pose(hand - radius * Vec3::Y, Quat::IDENTITY),
    );
    let grip =
        BallSocket::at_world_anchor("grip", &world.bodies, forearm, weight, hand, Quat::IDENTITY)
            .with_flavour(method.joint_flavour());
    world.add_constraint(grip);
}

/// [`Scenario::Projectile`]: contacts on, a floor, a standing ragdoll, and a sphere of `mass`
/// kg flying at its chest at `speed` m/s from 1.5 m away.
fn build_projectile(lab: &mut Lab, method: Method, mass: f32, speed: f32) {
    lab.world.settings.contacts = true;
    lab.world
        .add_body(Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0));
    let mut spec = humanoid(method, false);
    spec.root = Iso::new(Vec3::new(0.0, 0.005, 0.0), Quat::IDENTITY);
    let ragdoll = add_humanoid(lab, &spec);
    let world = &mut lab.world;
    let chest = world
        .body(ragdoll.part(world, "chest").expect("chest"))
        .position;
    let mut ball = Body::new(
        "projectile",
        BodyKind::Dynamic,
        Shape::Sphere { radius: 0.12 },
        mass,
    )
    .with_pose(chest - 1.5 * Vec3::Z, Quat::IDENTITY);
    ball.linear_velocity = speed * Vec3::Z;
    world.add_body(ball);
}

/// Builds the humanoid into `lab` and returns a copy of its ragdoll.
fn add_humanoid(lab: &mut Lab, spec: &HumanoidSpec) -> Ragdoll {
    lab.add_humanoid(spec)
        .expect("the suite names only known joints and parts")
        .clone()
}

fn humanoid(method: Method, stiff_spine: bool) -> HumanoidSpec {
    let mut spec = HumanoidSpec::new("ragdoll", method.spine());
    spec.joint_flavour = method.joint_flavour();
    let (spring, alpha_bend, alpha_twist) = if stiff_spine {
        (1.0, 1.0, 1.0)
    } else {
        (SPINE_SPRING, ROD_ALPHA_BEND, ROD_ALPHA_TWIST)
    };
    spec.spine_spring = Some(spring);
    spec.rod = RodParams {
        alpha_bend,
        alpha_twist,
        ..RodParams::default()
    };
    spec
}

/// Joint rotations bending the spine forward (about +x, toward +z) by `angle` in total.
fn spine_bend(spine: SpineKind, angle: f32) -> Vec<(String, Quat)> {
    let joints: &[&str] = match spine {
        SpineKind::Chain3 | SpineKind::Rig => &["lumbosacral", "thoracolumbar", "mid_thoracic"],
        SpineKind::Rod | SpineKind::Single => &["lumbosacral"],
    };
    let each = crate::math::quat_from_rotation_x(angle / joints.len() as f32);
    joints.iter().map(|j| (j.to_string(), each)).collect()
}

/// Just inside the joint spines' swing limits (3 x 25 = 75 degrees, and 75 for `single`).
const JOINT_SPINE_MAX_BEND: f32 = 74.0 * PI / 180.0;

const CHEST_SIDE: [&str; 6] = [
    "chest",
    "head",
    "upper_arm_l",
    "upper_arm_r",
    "forearm_l",
    "forearm_r",
];
const PELVIS_SIDE: [&str; 5] = ["pelvis", "thigh_l", "thigh_r", "shank_l", "shank_r"];

/// Builds the humanoid straight (so spine springs and the rod rest straight), then bends its
/// spine forward by `psi`. Joint spines: the poses of a second build whose spine joints are
/// rotated, as far as their limits allow. Rod: one side moved rigidly onto the rod's arc,
/// `move_pelvis` choosing the side (the other one is the fixed one), so the rod starts bent
/// with its hard constraints holding. Returns the potential energy the bend took away, which
/// the spine's springs may give back.
fn bend_spine(lab: &mut Lab, spec: HumanoidSpec, psi: f32, move_pelvis: bool) -> f32 {
    let ragdoll = add_humanoid(lab, &spec);
    let world = &mut lab.world;
    let straight_energy = world.potential_energy();
    if spec.spine == SpineKind::Rod {
        bend_rod(world, &ragdoll, psi, move_pelvis);
    } else {
        let mut bent = Lab::new(World::new(world.settings.clone()));
        let bent_spec = HumanoidSpec {
            joint_rotations: spine_bend(spec.spine, psi.min(JOINT_SPINE_MAX_BEND)),
            ..spec
        };
        add_humanoid(&mut bent, &bent_spec);
        for (body, pose) in world.bodies[ragdoll.bodies.clone()]
            .iter_mut()
            .zip(&bent.world.bodies)
        {
            body.set_pose(pose.position, pose.orientation);
        }
    }
    (straight_energy - world.potential_energy()).max(0.0)
}

fn bend_rod(world: &mut World, ragdoll: &Ragdoll, psi: f32, move_pelvis: bool) {
    let rod = match &world.constraints[ragdoll.constraints.start] {
        Constraint::Rod(rod) => rod.clone(),
        Constraint::BallSocket(_) => unreachable!("the rod spine's first constraint is its rod"),
    };
    let (pelvis, chest) = (world.body(rod.body_a), world.body(rod.body_b));
    let (tangent, bend) = (
        pelvis.orientation * rod.local_frame_a * Vec3::X,
        crate::math::quat_from_rotation_x(psi),
    );
    let (moved, parts, new_pose): (BodyId, &[&str], Iso) = if move_pelvis {
        // t_b stays; t_a = bend^-1 t_b, and p_a is where the arc from it ends at p_b.
        let ta = bend.inverse() * tangent;
        let reach = arc_point(Vec3::ZERO, ta, tangent, rod.rest_length, 1.0);
        let pose = Iso::new(chest.position - reach, bend.inverse() * pelvis.orientation);
        (rod.body_a, &PELVIS_SIDE, pose)
    } else {
        let tb = bend * tangent;
        let end = arc_point(pelvis.position, tangent, tb, rod.rest_length, 1.0);
        (
            rod.body_b,
            &CHEST_SIDE,
            Iso::new(end, bend * chest.orientation),
        )
    };
    let old = world.body(moved);
    let motion = new_pose * Iso::new(old.position, old.orientation).inverse();
    for part in parts {
        let id = ragdoll.part(world, part).expect("humanoid part");
        let body = world.body_mut(id);
        let pose = motion * Iso::new(body.position, body.orientation);
        body.set_pose(pose.translation, pose.rotation);
    }
}
