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

mod build;
pub mod character;
mod table;

pub use build::build_humanoid;
pub use table::{joint_names, part_names, TOTAL_MASS};

use std::ops::Range;

use serde::Deserialize;

use crate::body::BodyId;
use crate::constraint::JointFlavour;
pub use crate::constraint::RodParams;
use crate::math::{Iso, Quat, Vec3};
use crate::rig::skeleton::MappedSkeleton;
use crate::skeleton::Skeleton;
use crate::world::World;

/// How a ragdoll's spine between pelvis and chest is built: the reference humanoid's
/// (`chain3`, `rod`, `single`) or a game character's (`rig`, `rod`, `single`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum SpineKind {
    /// The humanoid's pelvis - lower spine - upper spine - chest, three ball-and-socket joints.
    #[default]
    Chain3,
    /// A game character's own spine joints, as its rig ships them (four on Jolt's human).
    Rig,
    /// Pelvis - chest joined by one rod constraint (§5), instantiated at the starting pose (§6).
    Rod,
    /// Pelvis - chest, one ball-and-socket with the spine joints' ranges added up.
    Single,
}

impl SpineKind {
    /// Whether a `[[ragdoll]]` (the humanoid) is built with it.
    pub fn fits_humanoid(self) -> bool {
        self != SpineKind::Rig
    }

    /// Whether a `[[character]]` (a game rig) is built with it.
    pub fn fits_character(self) -> bool {
        self != SpineKind::Chain3
    }
}

impl std::fmt::Display for SpineKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SpineKind::Chain3 => "chain3",
            SpineKind::Rig => "rig",
            SpineKind::Rod => "rod",
            SpineKind::Single => "single",
        })
    }
}

/// Which pairs of one ragdoll's bodies may collide with each other (bodies joined by a joint
/// or the rod never do). Game ragdolls commonly filter more: Jolt's
/// `Ragdoll::DisableParentChildCollisions` also filters the pairs that overlap in the pose it is
/// given, and many games let no part of a ragdoll touch another.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SelfContacts {
    /// Every pair not joined (the default).
    #[default]
    All,
    /// Not the pairs within the world's contact margin in the standing reference pose: the
    /// humanoid's forearms hang against its pelvis and thighs there, four pairs.
    ApartAtRest,
    /// None: the ragdoll's bodies touch only other bodies.
    None,
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
    /// Which of its own bodies may touch each other.
    pub self_contacts: SelfContacts,
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
            self_contacts: SelfContacts::All,
        }
    }
}

/// A built ragdoll: which bodies and constraints of the world are its own.
#[derive(Clone, Debug)]
pub struct Ragdoll {
    /// Ragdoll name, the prefix of its bodies' and constraints' names.
    pub name: String,
    /// Its spine; `None` for a plain group (the loose joints and rods of a scene, a chain).
    pub spine: Option<SpineKind>,
    /// Indices of its bodies in the world's bodies.
    pub bodies: Range<usize>,
    /// Indices of its constraints in the world's constraints.
    pub constraints: Range<usize>,
    /// The animation skeleton between hips and chest (§6); None for plain groups of bodies.
    pub skeleton: Option<Skeleton>,
    /// A game character's whole animation skeleton posed back from its bodies (§6), its
    /// spine the bones of `skeleton`; None for the humanoid, plain groups and characters
    /// without one.
    pub hd_skeleton: Option<MappedSkeleton>,
    /// Body positions of the starting pose, the target of the controllability measure.
    pub target_positions: Vec<Vec3>,
}

impl Ragdoll {
    /// A plain group of bodies and the constraints between them, with no skeleton: measured,
    /// printed and recorded like a humanoid, its pose deviation taken from where the bodies
    /// stand now.
    pub fn group(
        name: &str,
        bodies: Range<usize>,
        constraints: Range<usize>,
        world: &World,
    ) -> Ragdoll {
        Ragdoll {
            name: name.to_string(),
            spine: None,
            target_positions: world.bodies[bodies.clone()]
                .iter()
                .map(|b| b.position)
                .collect(),
            bodies,
            constraints,
            skeleton: None,
            hd_skeleton: None,
        }
    }

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
