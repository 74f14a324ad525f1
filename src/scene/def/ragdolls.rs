//! The `[[ragdoll]]` and `[drop]` definitions: one reference humanoid, posed and placed, and
//! many ragdolls dropped from a grid.

use serde::Deserialize;

use crate::constraint::{BendTwist, JointFlavour, LengthCorrection, TwistMode};
use crate::ragdoll::{SelfContacts, SpineKind};

/// `count` ragdolls on a grid of `columns` x `rows` per layer, layers stacked up by
/// `spacing[1]`, each turned by a random yaw and tipped by a random angle (fixed `seed`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DropDef {
    /// Number of ragdolls.
    pub count: usize,
    /// Their spine (default chain3).
    #[serde(default)]
    pub spine: SpineKind,
    /// Root position of the first ragdoll (m).
    pub first: [f32; 3],
    /// Distance between neighbours along x, between layers along y, along z (m).
    pub spacing: [f32; 3],
    /// Ragdolls along x per layer.
    pub columns: usize,
    /// Ragdolls along z per layer.
    pub rows: usize,
    /// Seed of the random yaws and tips (default 0).
    #[serde(default)]
    pub seed: u64,
    /// Largest tip away from upright (deg).
    #[serde(default = "default_tip")]
    pub max_tip: f32,
    /// Which pairs of one ragdoll's bodies may collide: `all` (the default), `apart_at_rest`
    /// or `none` ([`SelfContacts`]).
    #[serde(default)]
    pub self_contacts: SelfContacts,
    /// Game characters instead of humanoids: what each `[[character]]` the block makes is
    /// built from (`spine` then takes `rig`, `rod` or `single`).
    pub character: Option<DropCharacterDef>,
}

/// What a `[drop]` of game characters builds each one from: the rig, the clips (the `i`-th
/// character takes clip `i` mod their count), the time and the spine region.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DropCharacterDef {
    /// The rig file, relative to the scene file.
    pub rig: String,
    /// Clips or poses, relative to the scene file; taken in turn.
    pub clips: Vec<String>,
    /// The clips' time (s) the poses are taken at.
    #[serde(default)]
    pub time: f32,
    /// The spine region's end parts, as `[[character]]` names them.
    pub region: super::RegionDef,
    /// The rod's bending relaxation (eq. 11), with the rod spine; none: `[[character]]`'s
    /// default.
    pub alpha_b: Option<f32>,
    /// The rod's twisting relaxation (eq. 13), with the rod spine.
    pub alpha_t: Option<f32>,
}

fn default_tip() -> f32 {
    90.0
}

/// A `[[ragdoll]]`: one reference humanoid ([`crate::ragdoll`]), posed and placed.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RagdollDef {
    /// Ragdoll name, the prefix of its parts' names (`<name>/chest`).
    pub name: String,
    /// Spine kind: `chain3` (the default), `single` or `rod`.
    #[serde(default)]
    pub spine: SpineKind,
    /// Overrides the scene's joint flavour.
    pub joint_flavour: Option<JointFlavour>,
    /// Root translation applied to the standing reference pose (m).
    #[serde(default)]
    pub position: [f32; 3],
    /// Root rotation as a rotation vector (deg).
    #[serde(default)]
    pub rotation: [f32; 3],
    /// Joint name -> rotation vector (deg) of the child about the joint centre.
    #[serde(default)]
    pub pose: std::collections::BTreeMap<String, [f32; 3]>,
    /// Parts held fixed, e.g. ["pelvis"].
    #[serde(default)]
    pub fixed: Vec<String>,
    /// Relaxation in [0, 1] of the spine joints' springs toward the starting pose.
    pub spine_spring: Option<f32>,
    /// Relaxation in [0, 1] of the other joints' springs toward the starting pose.
    pub limb_spring: Option<f32>,
    /// Rod spine: bending relaxation alpha_b in [0, 1] (eq. 11).
    pub alpha_b: Option<f32>,
    /// Rod spine: twisting relaxation alpha_t in [0, 1] (eq. 13).
    pub alpha_t: Option<f32>,
    /// Rod spine: bending stiffness (N m/rad), > 0, solved in compliance form; replaces `alpha_b`.
    pub bend_stiffness: Option<f32>,
    /// Damping of the bend rate (N m s/rad), >= 0; only with `bend_stiffness`.
    pub bend_damping: Option<f32>,
    /// Rod spine: twisting stiffness (N m/rad), > 0; replaces `alpha_t`.
    pub twist_stiffness: Option<f32>,
    /// Damping of the twist rate (N m s/rad), >= 0; only with `twist_stiffness`.
    pub twist_damping: Option<f32>,
    /// Rod spine: twist measure, exact (parallel transport) or paper (eq. 12).
    pub twist: Option<TwistMode>,
    /// Rod spine: length correction, offset (the paper's) or gradient (workless).
    pub rod_length: Option<LengthCorrection>,
    /// Rod spine: bend and twist projected one after the other (sequential) or as one block.
    pub bend_twist: Option<BendTwist>,
    /// Constant external forces (N) on parts, e.g. `{ chest = [0.0, 0.0, 150.0] }`.
    #[serde(default)]
    pub forces: std::collections::BTreeMap<String, [f32; 3]>,
    /// Which pairs of its bodies may collide: `all` (the default), `apart_at_rest` or `none`
    /// ([`SelfContacts`]).
    #[serde(default)]
    pub self_contacts: SelfContacts,
}
