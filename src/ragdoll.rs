//! The reference humanoid of `shared/humanoid.md` (1.80 m, 75 kg), built into a [`World`].
//!
//! One builder serves scenes, tests and benchmarks. It starts from any pose: a root transform
//! applied to the standing reference pose, plus per-joint rotations of each child subtree about
//! its joint centre (in the parent's reference frame), applied parent first.
//!
//! Joint limits and anchors are defined on the reference pose (anatomical zero); angular
//! springs, when asked for, rest at the starting pose (instantiated at the transition, §6).
//!
//! Spines:
//! - `chain3`: pelvis - lower spine - upper spine - chest, three ball-and-socket joints;
//! - `single`: pelvis - chest, one ball-and-socket at the lumbosacral joint with the three
//!   spine joints' ranges added up (swing 75 deg, twist +-45 deg);
//! - `rod`: pelvis - chest joined by one rod constraint (paper §5), instantiated at the starting
//!   pose (§6) with the body normals pointing forward.
//!
//! With `single` and `rod` the removed spine bodies' 12.24 kg are shared equally between
//! pelvis and chest, so the total stays 75 kg.

use std::f32::consts::FRAC_PI_2;
use std::ops::Range;

use serde::Deserialize;

use crate::body::{Body, BodyId, BodyKind};
use crate::constraint::{
    AngularLimit, BallSocket, Constraint, JointFlavour, LengthCorrection, Rod, Stiffness, TwistMode,
};
use crate::math::{Iso, Quat, Vec3};
use crate::shape::{Axis, Shape};
use crate::skeleton::Skeleton;
use crate::world::World;

/// How the humanoid's spine between pelvis and chest is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum SpineKind {
    /// Pelvis - lower spine - upper spine - chest, three ball-and-socket joints.
    #[default]
    Chain3,
    /// Pelvis - chest joined by one rod constraint (§5), instantiated at the starting pose (§6).
    Rod,
    /// Pelvis - chest, one ball-and-socket with the three spine joints' ranges added up.
    Single,
}

impl std::fmt::Display for SpineKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SpineKind::Chain3 => "chain3",
            SpineKind::Rod => "rod",
            SpineKind::Single => "single",
        })
    }
}

/// What to build.
#[derive(Clone, Debug)]
pub struct HumanoidSpec {
    /// Ragdoll name; prefixes its bodies' and constraints' names (`name/part`).
    pub name: String,
    /// Which spine to build.
    pub spine: SpineKind,
    /// How the ball-and-socket joints' point part is solved.
    pub joint_flavour: JointFlavour,
    /// Applied to the whole standing reference pose.
    pub root: Iso,
    /// Joint name -> rotation of the child subtree about the joint centre.
    pub joint_rotations: Vec<(String, Quat)>,
    /// Relaxation of the spine joints' angular springs (None: no spring).
    pub spine_spring: Option<f32>,
    /// Relaxation of the other joints' angular springs (None: no spring).
    pub limb_spring: Option<f32>,
    /// Parts made fixed (e.g. "pelvis").
    pub fixed: Vec<String>,
    /// Rod parameters (used by the `rod` spine).
    pub rod: RodParams,
    /// Constant external forces (N) on parts, e.g. a push on the chest.
    pub forces: Vec<(String, Vec3)>,
}

/// The rod spine's soft-constraint relaxations and twist measure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodParams {
    /// Bending relaxation alpha_b in [0, 1] (eq. 11); default 0.1.
    pub alpha_bend: f32,
    /// Twisting relaxation alpha_t in [0, 1] (eq. 12-13); default 0.5.
    pub alpha_twist: f32,
    /// Stiffness in physical units, replacing the alphas where set.
    pub bend_stiffness: Option<Stiffness>,
    /// Twisting stiffness, replacing `alpha_twist` where set.
    pub twist_stiffness: Option<Stiffness>,
    /// How the twist tau is measured; default exact.
    pub twist_mode: TwistMode,
    /// How the length constraint (eq. 9) is corrected; default the paper's offset correction.
    pub length_correction: LengthCorrection,
}

impl Default for RodParams {
    fn default() -> Self {
        RodParams {
            alpha_bend: 0.1,
            alpha_twist: 0.5,
            bend_stiffness: None,
            twist_stiffness: None,
            twist_mode: TwistMode::Exact,
            length_correction: LengthCorrection::Offset,
        }
    }
}

impl HumanoidSpec {
    /// The standing reference pose (identity root) with no joint rotations, springs, fixed parts
    /// or forces, exact joints and the default rod parameters.
    pub fn new(name: impl Into<String>, spine: SpineKind) -> Self {
        HumanoidSpec {
            name: name.into(),
            spine,
            joint_flavour: JointFlavour::Exact,
            root: Iso::IDENTITY,
            joint_rotations: Vec::new(),
            spine_spring: None,
            limb_spring: None,
            fixed: Vec::new(),
            rod: RodParams::default(),
            forces: Vec::new(),
        }
    }
}

/// A built ragdoll: which bodies and constraints of the world are its own.
#[derive(Clone, Debug)]
pub struct Ragdoll {
    /// Ragdoll name, the prefix of its bodies' and constraints' names.
    pub name: String,
    /// Its spine.
    pub spine: SpineKind,
    /// Indices of its bodies in the world's bodies.
    pub bodies: Range<usize>,
    /// Indices of its constraints in the world's constraints.
    pub constraints: Range<usize>,
    /// The animation skeleton between hips and chest (§6); None for plain groups of bodies.
    pub skeleton: Option<Skeleton>,
    /// Body positions of the starting pose, the target of the controllability measure.
    pub target_positions: Vec<Vec3>,
}

impl Ragdoll {
    /// Ids of its bodies.
    pub fn body_ids(&self) -> impl Iterator<Item = BodyId> + '_ {
        self.bodies.clone().map(|i| BodyId(i as u32))
    }

    /// The body of part `part` (e.g. "chest"), if this ragdoll has it.
    pub fn part(&self, world: &World, part: &str) -> Option<BodyId> {
        let full = format!("{}/{part}", self.name);
        self.body_ids().find(|&id| world.body(id).name == full)
    }
}

struct Part {
    name: &'static str,
    axis: Axis,
    half_height: f32,
    radius: f32,
    centre: [f32; 2],
    /// Share of the total mass (de Leva 1996).
    mass_fraction: f32,
}

const fn part(
    name: &'static str,
    axis: Axis,
    half_height: f32,
    radius: f32,
    centre: [f32; 2],
    mass_fraction: f32,
) -> Part {
    Part {
        name,
        axis,
        half_height,
        radius,
        centre,
        mass_fraction,
    }
}

/// Total mass of the reference humanoid (kg).
pub const TOTAL_MASS: f32 = 75.0;

/// humanoid.md, bodies with the 3-joint spine. Parent parts come before their children.
const PARTS: [Part; 13] = [
    part("pelvis", Axis::X, 0.070, 0.100, [0.0, 1.000], 0.1117),
    part("lower_spine", Axis::X, 0.090, 0.055, [0.0, 1.1125], 0.08165),
    part("upper_spine", Axis::X, 0.090, 0.055, [0.0, 1.2175], 0.08165),
    part("chest", Axis::X, 0.070, 0.120, [0.0, 1.385], 0.1596),
    part("head", Axis::Y, 0.040, 0.100, [0.0, 1.660], 0.0694),
    part("upper_arm_l", Axis::Y, 0.105, 0.045, [0.22, 1.290], 0.0271),
    part("upper_arm_r", Axis::Y, 0.105, 0.045, [-0.22, 1.290], 0.0271),
    part("forearm_l", Axis::Y, 0.180, 0.040, [0.22, 0.920], 0.0223),
    part("forearm_r", Axis::Y, 0.180, 0.040, [-0.22, 0.920], 0.0223),
    part("thigh_l", Axis::Y, 0.150, 0.070, [0.09, 0.730], 0.1416),
    part("thigh_r", Axis::Y, 0.150, 0.070, [-0.09, 0.730], 0.1416),
    part("shank_l", Axis::Y, 0.205, 0.050, [0.09, 0.255], 0.057),
    part("shank_r", Axis::Y, 0.205, 0.050, [-0.09, 0.255], 0.057),
];

/// Twist or hinge axis of a joint frame in the reference pose.
#[derive(Clone, Copy)]
enum FrameAxis {
    Up,
    Down,
    /// +x (left): positive hinge angle swings the child backward (knee flexion).
    Left,
    /// -x: positive hinge angle swings the child forward (elbow flexion).
    Right,
}

impl FrameAxis {
    fn rotation(self) -> Quat {
        match self {
            FrameAxis::Up => Quat::from_rotation_z(FRAC_PI_2),
            FrameAxis::Down => Quat::from_rotation_z(-FRAC_PI_2),
            FrameAxis::Left => Quat::IDENTITY,
            FrameAxis::Right => Quat::from_rotation_y(std::f32::consts::PI),
        }
    }
}

struct JointDef {
    name: &'static str,
    parent: &'static str,
    child: &'static str,
    centre: [f32; 2],
    axis: FrameAxis,
    /// Swing cone half-angle and symmetric twist range (deg), or hinge range (deg).
    limit: LimitDef,
    spine: bool,
}

#[derive(Clone, Copy)]
enum LimitDef {
    Cone { swing: f32, twist: f32 },
    Hinge { min: f32, max: f32 },
}

const fn joint(
    name: &'static str,
    parent: &'static str,
    child: &'static str,
    centre: [f32; 2],
    axis: FrameAxis,
    limit: LimitDef,
    spine: bool,
) -> JointDef {
    JointDef {
        name,
        parent,
        child,
        centre,
        axis,
        limit,
        spine,
    }
}

const SPINE_CONE: LimitDef = LimitDef::Cone {
    swing: 25.0,
    twist: 15.0,
};

/// humanoid.md joints (chain3 spine first; `single`/`rod` replace the first three).
const CHAIN3_SPINE: [JointDef; 3] = [
    joint(
        "lumbosacral",
        "pelvis",
        "lower_spine",
        [0.0, 1.060],
        FrameAxis::Up,
        SPINE_CONE,
        true,
    ),
    joint(
        "thoracolumbar",
        "lower_spine",
        "upper_spine",
        [0.0, 1.165],
        FrameAxis::Up,
        SPINE_CONE,
        true,
    ),
    joint(
        "mid_thoracic",
        "upper_spine",
        "chest",
        [0.0, 1.270],
        FrameAxis::Up,
        SPINE_CONE,
        true,
    ),
];
const SINGLE_SPINE: JointDef = joint(
    "lumbosacral",
    "pelvis",
    "chest",
    [0.0, 1.060],
    FrameAxis::Up,
    LimitDef::Cone {
        swing: 75.0,
        twist: 45.0,
    },
    true,
);
const LIMBS: [JointDef; 9] = [
    joint(
        "neck",
        "chest",
        "head",
        [0.0, 1.520],
        FrameAxis::Up,
        LimitDef::Cone {
            swing: 45.0,
            twist: 45.0,
        },
        false,
    ),
    joint(
        "shoulder_l",
        "chest",
        "upper_arm_l",
        [0.22, 1.440],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 90.0,
            twist: 60.0,
        },
        false,
    ),
    joint(
        "shoulder_r",
        "chest",
        "upper_arm_r",
        [-0.22, 1.440],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 90.0,
            twist: 60.0,
        },
        false,
    ),
    joint(
        "elbow_l",
        "upper_arm_l",
        "forearm_l",
        [0.22, 1.140],
        FrameAxis::Right,
        LimitDef::Hinge {
            min: 0.0,
            max: 145.0,
        },
        false,
    ),
    joint(
        "elbow_r",
        "upper_arm_r",
        "forearm_r",
        [-0.22, 1.140],
        FrameAxis::Right,
        LimitDef::Hinge {
            min: 0.0,
            max: 145.0,
        },
        false,
    ),
    joint(
        "hip_l",
        "pelvis",
        "thigh_l",
        [0.09, 0.950],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 70.0,
            twist: 30.0,
        },
        false,
    ),
    joint(
        "hip_r",
        "pelvis",
        "thigh_r",
        [-0.09, 0.950],
        FrameAxis::Down,
        LimitDef::Cone {
            swing: 70.0,
            twist: 30.0,
        },
        false,
    ),
    joint(
        "knee_l",
        "thigh_l",
        "shank_l",
        [0.09, 0.510],
        FrameAxis::Left,
        LimitDef::Hinge {
            min: 0.0,
            max: 140.0,
        },
        false,
    ),
    joint(
        "knee_r",
        "thigh_r",
        "shank_r",
        [-0.09, 0.510],
        FrameAxis::Left,
        LimitDef::Hinge {
            min: 0.0,
            max: 140.0,
        },
        false,
    ),
];

/// Names of the joints a pose may rotate for this spine.
pub fn joint_names(spine: SpineKind) -> Vec<&'static str> {
    joint_defs(spine).map(|j| j.name).collect()
}

fn joint_defs(spine: SpineKind) -> impl Iterator<Item = &'static JointDef> {
    let spine_joints: &'static [JointDef] = match spine {
        SpineKind::Chain3 => &CHAIN3_SPINE,
        SpineKind::Single | SpineKind::Rod => std::slice::from_ref(&SINGLE_SPINE),
    };
    spine_joints.iter().chain(LIMBS.iter())
}

fn has_part(spine: SpineKind, name: &str) -> bool {
    spine == SpineKind::Chain3 || !matches!(name, "lower_spine" | "upper_spine")
}

/// Part names for this spine.
pub fn part_names(spine: SpineKind) -> Vec<&'static str> {
    PARTS
        .iter()
        .map(|p| p.name)
        .filter(|n| has_part(spine, n))
        .collect()
}

fn v2(c: [f32; 2]) -> Vec3 {
    Vec3::new(c[0], c[1], 0.0)
}

/// Builds the humanoid's bodies and constraints into `world` and returns the ragdoll that groups
/// them (the caller keeps it, usually in a [`crate::lab::Lab`]). Errors name the unknown joint
/// or part.
pub fn build_humanoid(world: &mut World, spec: &HumanoidSpec) -> Result<Ragdoll, String> {
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
    let parts: Vec<&Part> = PARTS.iter().filter(|p| has_part(spine, p.name)).collect();
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
    let index_of = |name: &str| {
        parts
            .iter()
            .position(|p| p.name == name)
            .expect("joint tables name known parts")
    };

    // Forward kinematics from the reference pose (all parts axis-aligned).
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

    let first_body = world.bodies.len();
    // single and rod: the two removed spine bodies' mass is shared by pelvis and chest
    let extra_mass = if spine == SpineKind::Chain3 {
        0.0
    } else {
        0.5 * 2.0 * 0.08165 * TOTAL_MASS
    };
    for (p, pose) in parts.iter().zip(&posed) {
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
        let shape = Shape::Capsule {
            half_height: p.half_height,
            radius: p.radius,
            axis: p.axis,
        };
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

    let first_constraint = world.constraints.len();
    if spine == SpineKind::Rod {
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
        rod.alpha_bend = spec.rod.alpha_bend;
        rod.alpha_twist = spec.rod.alpha_twist;
        rod.bend_stiffness = spec.rod.bend_stiffness;
        rod.twist_stiffness = spec.rod.twist_stiffness;
        rod.twist_mode = spec.rod.twist_mode;
        rod.length_correction = spec.rod.length_correction;
        world.constraints.push(Constraint::Rod(rod));
    }
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
        spine,
        bodies: first_body..world.bodies.len(),
        constraints: first_constraint..world.constraints.len(),
        skeleton: Some(Skeleton::attach(world, &spine_bodies, rod)),
        target_positions: world.bodies[first_body..]
            .iter()
            .map(|b| b.position)
            .collect(),
    })
}
