//! The cases of the stability suite and the scenes they build, one per [`Method`]. See the
//! module docs of [`crate::stress`] for what each case stresses and how methods map onto it.

use std::f32::consts::PI;

use super::Method;
use crate::body::{Body, BodyId, BodyKind};
use crate::constraint::rod::arc_point;
use crate::constraint::{BallSocket, Constraint, JointFlavour, Rod};
use crate::lab::Lab;
use crate::math::{Iso, Quat, Vec3};
use crate::ragdoll::{HumanoidSpec, Ragdoll, RodParams, SpineKind, TOTAL_MASS};
use crate::shape::{Axis, Shape};
use crate::world::{Settings, World};

/// One scene of the suite with its time step, iterations and length.
#[derive(Clone, Debug)]
pub struct Case {
    /// Case name, in the suite's table and its recordings' names.
    pub name: &'static str,
    /// One line on what the case does.
    pub description: &'static str,
    /// What the case builds.
    pub scenario: Scenario,
    /// Frame time step (s).
    pub dt: f32,
    /// Solver iterations per substep.
    pub iterations: u32,
    /// Simulated time (s).
    pub seconds: f32,
}

impl Case {
    /// Frames to run: `seconds / dt`, rounded, at least 1.
    pub fn frames(&self) -> u32 {
        (self.seconds / self.dt).round().max(1.0) as u32
    }

    /// Builds the lab for this method and the number of frames to run, or None when the
    /// case does not apply to the method (a chain has no spine, so `single` skips it).
    pub fn build(&self, method: Method) -> Option<(Lab, u32)> {
        self.build_full(method).map(|b| (b.lab, b.frames))
    }

    /// [`Case::build`] with what the verdict needs to know about the scene.
    pub fn build_full(&self, method: Method) -> Option<Built> {
        let settings = Settings {
            dt: self.dt,
            iterations: self.iterations,
            ..Settings::default()
        };
        build(self.scenario, settings, self.frames(), method)
    }
}

const HZ60: f32 = 1.0 / 60.0;

const fn slump(tilt_deg: f32, stiff_spine: bool, forearm_mass_divisor: f32) -> Scenario {
    Scenario::Slump {
        tilt_deg,
        stiff_spine,
        forearm_mass_divisor,
    }
}

/// The paper's passive bending pose.
const SLUMP: Scenario = slump(8.0, false, 1.0);

/// The fixed suite, in table order.
pub fn suite() -> Vec<Case> {
    #[rustfmt::skip]
    let cases = [
        ("baseline", "passive bending at 60 Hz, 20 iterations: the reference",
            SLUMP, HZ60, 20, 4.0),
        ("dt_1_30", "passive bending at dt = 1/30 s",
            SLUMP, 1.0 / 30.0, 20, 4.0),
        ("dt_1_15", "passive bending at dt = 1/15 s",
            SLUMP, 1.0 / 15.0, 20, 4.0),
        ("iterations_2", "passive bending with 2 iterations",
            SLUMP, HZ60, 2, 4.0),
        ("iterations_1", "passive bending with 1 iteration",
            SLUMP, HZ60, 1, 4.0),
        ("heavy_hand_100", "pelvis fixed, 100 forearm masses (167 kg) held in the left hand",
            Scenario::HeavyHand { mass_ratio: 100.0 }, HZ60, 20, 4.0),
        ("heavy_hand_1000", "pelvis fixed, 1000 forearm masses (1.67 t) held in the left hand",
            Scenario::HeavyHand { mass_ratio: 1000.0 }, HZ60, 20, 4.0),
        ("light_forearms_100", "passive bending, both forearms 100 times lighter (17 g)",
            slump(8.0, false, 100.0), HZ60, 20, 4.0),
        ("light_forearms_1000", "passive bending, both forearms 1000 times lighter (1.7 g)",
            slump(8.0, false, 1000.0), HZ60, 20, 4.0),
        ("chain_40", "40 links (4 m) released from horizontal; rod: 40 rods, same length",
            Scenario::Chain { links: 40, horizontal: true, stretch_m: 0.0 }, HZ60, 20, 4.0),
        ("chain_40_stretched", "40 links hanging, each 5 cm from its joint at the start",
            Scenario::Chain { links: 40, horizontal: false, stretch_m: 0.05 }, HZ60, 20, 4.0),
        ("stiff_spine_dt_1_30", "stiff spine (rod alpha_b = alpha_t = 1) tilted 30 deg, dt = 1/30 s",
            slump(30.0, true, 1.0), 1.0 / 30.0, 20, 4.0),
        ("stiff_spine_dt_1_15", "stiff spine (rod alpha_b = alpha_t = 1) tilted 30 deg, dt = 1/15 s",
            slump(30.0, true, 1.0), 1.0 / 15.0, 20, 4.0),
        ("projectile_50", "contacts: a 20 kg sphere at 50 m/s hits a standing ragdoll's chest",
            Scenario::Projectile { mass: 20.0, speed: 50.0 }, HZ60, 20, 3.0),
        ("bent_near_pi", "pelvis fixed, spine bent 175 deg (joint spines: 74, their limit)",
            Scenario::BentSpine { psi_deg: 175.0 }, HZ60, 20, 3.0),
        ("hanging_near_zero", "hung by the head, spine bent 0.057 deg (rod psi = 1e-3 rad)",
            Scenario::Hanging { psi_deg: 0.057 }, HZ60, 20, 3.0),
    ];
    cases
        .into_iter()
        .map(
            |(name, description, scenario, dt, iterations, seconds)| Case {
                name,
                description,
                scenario,
                dt,
                iterations,
                seconds,
            },
        )
        .collect()
}

/// Mass of the reference humanoid's forearm and hand (kg), humanoid.md.
pub const FOREARM_MASS: f32 = 0.0223 * TOTAL_MASS;

/// What a case builds. Every ragdoll scene uses the same spine stiffness, the pair that makes
/// both spines slump about equally in the passive bending scene: spine springs of relaxation
/// 0.1 for `chain3` and `single`, alpha_b = 0.005 and alpha_t = 0.5 for `rod`; "stiff" means
/// springs of relaxation 1 (hard angular targets) and alpha_b = alpha_t = 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scenario {
    /// Passive bending (paper Fig. 2): pelvis fixed, upper body tilted forward by `tilt_deg`
    /// (spread equally over chain3's three joints), slumping under gravity. The forearms' mass
    /// is divided by `forearm_mass_divisor` (1: the reference humanoid).
    Slump {
        /// Forward tilt of the upper body at the start (deg).
        tilt_deg: f32,
        /// Springs of relaxation 1 and alpha_b = alpha_t = 1 instead of the suite's spine
        /// stiffness.
        stiff_spine: bool,
        /// Divisor of both forearms' mass (1: the reference humanoid).
        forearm_mass_divisor: f32,
    },
    /// Pelvis fixed, standing; a sphere of `mass_ratio` times the forearm's mass hangs from the
    /// left hand by a ball-and-socket (the method's joint flavour).
    HeavyHand {
        /// The sphere's mass over the forearm's.
        mass_ratio: f32,
    },
    /// `links` capsules of 10 cm and 1 kg hung from a fixed support, 4 m for 40 links: joined by
    /// ball-and-sockets (chain3 methods, their flavour) or by rods between the link centres
    /// (rod: alpha_b = 0, free bending like the joints; alpha_t = 0.5; the paper's length
    /// correction). `horizontal`: released from horizontal; otherwise hanging straight down,
    /// every link pulled `stretch_m` away from its joint (at 45 degrees to the chain, sideways
    /// alternately), so the errors add up along the chain.
    Chain {
        /// Number of links.
        links: u32,
        /// Released from horizontal; otherwise hanging straight down.
        horizontal: bool,
        /// Each link's pull away from its joint at the start (m).
        stretch_m: f32,
    },
    /// Contacts on, a floor, a free standing ragdoll hit in the chest by a sphere of `mass` kg
    /// flying at `speed` m/s from 1.5 m away.
    Projectile {
        /// Sphere mass (kg).
        mass: f32,
        /// Sphere speed toward the chest (m/s).
        speed: f32,
    },
    /// Pelvis fixed, the spine bent forward by `psi_deg` at the start, its springs (rod:
    /// alpha_b, alpha_t) resting straight: the rod onto its arc, so its hard constraints hold;
    /// the joint spines as far as their swing limits allow (74 of 75 degrees), by equal
    /// rotations of their spine joints. The springs may give back the potential energy the
    /// bend took (the energy allowance).
    BentSpine {
        /// Forward bend of the spine at the start (deg); joint spines stop at their swing limits.
        psi_deg: f32,
    },
    /// Hung by the head (fixed), the rest of the body hanging below it at rest, the spine bent
    /// by `psi_deg` (the pelvis side moved onto the rod's arc, or the spine joints rotated).
    Hanging {
        /// Bend of the spine at the start (deg).
        psi_deg: f32,
    },
}

/// A scene ready to run, with what the verdict needs to know about it.
pub struct Built {
    /// The scene's world and ragdolls.
    pub lab: Lab,
    /// Frames to run.
    pub frames: u32,
    /// Whether everything should be nearly at rest by the end of the run.
    pub settles: bool,
    /// Energy (J) the scene may gain legitimately: the potential energy hidden by its initial
    /// joint errors (a pre-stretched chain rises when its joints close) or taken by a bend
    /// its springs will undo.
    pub energy_allowance: f32,
}

const SPINE_SPRING: f32 = 0.1;
const ROD_ALPHA_BEND: f32 = 0.005;
const ROD_ALPHA_TWIST: f32 = 0.5;

impl Method {
    /// The ragdoll spine this method builds.
    pub fn spine(self) -> SpineKind {
        match self {
            Method::Chain3Cheap | Method::Chain3Exact => SpineKind::Chain3,
            Method::Rod => SpineKind::Rod,
            Method::Single => SpineKind::Single,
        }
    }

    /// Ball-and-socket flavour: cheap only for `chain3-cheap`; the rod and single spines use
    /// exact limb joints, so they differ from `chain3-exact` in the spine alone.
    pub fn joint_flavour(self) -> JointFlavour {
        match self {
            Method::Chain3Cheap => JointFlavour::Cheap,
            _ => JointFlavour::Exact,
        }
    }
}

fn build(scenario: Scenario, settings: Settings, frames: u32, method: Method) -> Option<Built> {
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
            let mut spec = humanoid(method, stiff_spine);
            spec.fixed = vec!["pelvis".into()];
            spec.joint_rotations = spine_bend(method.spine(), tilt_deg.to_radians());
            let ragdoll = add_humanoid(&mut lab, &spec);
            for forearm in ["forearm_l", "forearm_r"] {
                let id = ragdoll
                    .part(&lab.world, forearm)
                    .expect("humanoid has forearms");
                lab.world
                    .body_mut(id)
                    .set_mass(FOREARM_MASS / forearm_mass_divisor);
            }
        }
        Scenario::HeavyHand { mass_ratio } => {
            settles = false; // the upper body gives way under the weight and swings
            let mut spec = humanoid(method, false);
            spec.fixed = vec!["pelvis".into()];
            let ragdoll = add_humanoid(&mut lab, &spec);
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
            let grip = BallSocket::at_world_anchor(
                "grip",
                &world.bodies,
                forearm,
                weight,
                hand,
                Quat::IDENTITY,
            )
            .with_flavour(method.joint_flavour());
            world.add_constraint(grip);
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
            lab.world.settings.contacts = true;
            lab.world
                .add_body(Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0));
            let mut spec = humanoid(method, false);
            spec.root = Iso::new(Vec3::new(0.0, 0.005, 0.0), Quat::IDENTITY);
            let ragdoll = add_humanoid(&mut lab, &spec);
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
        SpineKind::Chain3 => &["lumbosacral", "thoracolumbar", "mid_thoracic"],
        SpineKind::Rod | SpineKind::Single => &["lumbosacral"],
    };
    let each = Quat::from_rotation_x(angle / joints.len() as f32);
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
        Quat::from_rotation_x(psi),
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

/// Builds the chain scene; returns the potential energy its stretch hides (J).
fn chain(lab: &mut Lab, method: Method, links: u32, horizontal: bool, stretch_m: f32) -> f32 {
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
            rod.alpha_bend = 0.0;
            rod.alpha_twist = ROD_ALPHA_TWIST;
            Constraint::Rod(rod)
        } else {
            let anchor = centre - HALF * along;
            let frame = Quat::from_rotation_arc(Vec3::X, along);
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
    let group = group_as_ragdoll(world);
    lab.ragdolls.push(group);
    hidden_energy.max(0.0)
}

/// Every body and constraint grouped as one ragdoll, so the residual measures cover them.
fn group_as_ragdoll(world: &World) -> Ragdoll {
    Ragdoll {
        name: "chain".into(),
        spine: SpineKind::Chain3,
        bodies: 0..world.bodies.len(),
        constraints: 0..world.constraints.len(),
        skeleton: None,
        target_positions: world.bodies.iter().map(|b| b.position).collect(),
    }
}
