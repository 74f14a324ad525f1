//! The `[[character]]` definition: a game rig (`scenes/rigs/...`) at a clip's pose, placed, with
//! the spine to simulate.

use std::collections::BTreeMap;

use serde::Deserialize;

use crate::constraint::{JointFlavour, TwistMode};
use crate::ragdoll::SpineKind;

/// A character built from a rig file and posed by an animation clip.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CharacterDef {
    /// Name, unique among the scene's ragdolls, characters and rods.
    pub name: String,
    /// The rig file (Jolt's `RagdollSettings` text stream), relative to the scene file.
    pub rig: String,
    /// An animation clip (Jolt's `SkeletalAnimation` text stream) that poses the rig, relative
    /// to the scene file; none: the rig file's own pose.
    pub clip: Option<String>,
    /// The clip's time (s) the pose is taken at: the handover to physics.
    #[serde(default)]
    pub time: f32,
    /// The clip's time (s) to play it from, kinematically, until `time` (paper §6: the
    /// ragdoll takes over a character in motion); none: physics from the first frame.
    pub play_from: Option<f32>,
    /// Where the clip's origin is placed (m).
    #[serde(default)]
    pub position: [f32; 3],
    /// How the clip's origin is turned (rotation vector, deg).
    #[serde(default)]
    pub rotation: [f32; 3],
    /// Extra turns of joints on top of the clip, each a rotation vector (deg) about the
    /// world's axes (before `rotation`) at the joint, carrying the part's children with it.
    #[serde(default)]
    pub pose: BTreeMap<String, [f32; 3]>,
    /// The spine: `rig` (the rig's own joints), `rod` (one rod between the region's ends) or
    /// `single` (one ball-and-socket).
    #[serde(default = "rig_spine")]
    pub spine: SpineKind,
    /// The spine region's end parts, the lower first (`{ from = "hipsBone", to = "C_Spine_sjnt_4" }`).
    pub region: RegionDef,
    /// Parts held fixed.
    #[serde(default)]
    pub fixed: Vec<String>,
    /// Flavour of every ball-and-socket joint; none: the scene's.
    pub joint_flavour: Option<JointFlavour>,
    /// The rod's bending relaxation (eq. 11), with the rod spine.
    #[serde(default = "default_alpha_b")]
    pub alpha_b: f32,
    /// The rod's twisting relaxation (eq. 13), with the rod spine.
    #[serde(default = "default_alpha_t")]
    pub alpha_t: f32,
    /// The rod's twist measure (exact, or the paper's eq. 12).
    #[serde(default)]
    pub twist: TwistMode,
    /// The game's animation skeleton (Jolt's `Skeleton` text stream), relative to the scene
    /// file, posed back from the bodies (§6); given with `skeleton_pose`.
    pub skeleton: Option<String>,
    /// The skeleton's neutral pose (Jolt's `SkeletalAnimation` text stream, a key per joint),
    /// relative to the scene file; given with `skeleton`.
    pub skeleton_pose: Option<String>,
}

/// A spine region: the part it starts at and the part it ends at, a descendant of the first.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionDef {
    /// The lower end (the hips).
    pub from: String,
    /// The upper end (the chest).
    pub to: String,
}

impl CharacterDef {
    /// The rod's relaxations when a character names none: (alpha_b, alpha_t).
    pub fn default_alphas() -> (f32, f32) {
        (default_alpha_b(), default_alpha_t())
    }
}

fn rig_spine() -> SpineKind {
    SpineKind::Rig
}

fn default_alpha_b() -> f32 {
    crate::ragdoll::RodParams::default().alpha_bend
}

fn default_alpha_t() -> f32 {
    crate::ragdoll::RodParams::default().alpha_twist
}
