//! The `[[rod]]` definition (paper §5-6) and the stiffness fields in physical units that a rod
//! and a rod-spine ragdoll share ([`StiffnessDef`]).

use serde::Deserialize;

use super::RagdollDef;
use crate::constraint::{BendTwist, LengthCorrection, Stiffness, TwistMode};

/// A rod constraint (paper §5) between two named bodies, instantiated at their starting poses
/// (§6): tangents along the offset between the centres.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodDef {
    /// Rod name, for reports and recordings.
    pub name: String,
    /// Name of the body at the rod's start (s = 0).
    pub a: String,
    /// Name of the body at the rod's end (s = 1).
    pub b: String,
    /// Rest length l_0 (m); defaults to the distance between the centres.
    pub rest_length: Option<f32>,
    /// Bending relaxation alpha_b in [0, 1] (eq. 11); default 0, free bending.
    #[serde(default)]
    pub alpha_b: f32,
    /// Twisting relaxation alpha_t in [0, 1] (eq. 12-13); default 0, free twisting.
    #[serde(default)]
    pub alpha_t: f32,
    /// Bending stiffness (N m/rad), > 0, solved in compliance form; replaces `alpha_b`.
    pub bend_stiffness: Option<f32>,
    /// Damping of the bend rate (N m s/rad), >= 0; only with `bend_stiffness`.
    pub bend_damping: Option<f32>,
    /// Twisting stiffness (N m/rad), > 0; replaces `alpha_t`.
    pub twist_stiffness: Option<f32>,
    /// Damping of the twist rate (N m s/rad), >= 0; only with `twist_stiffness`.
    pub twist_damping: Option<f32>,
    /// Twist measure: `exact` (parallel transport, the default) or `paper` (eq. 12).
    #[serde(default)]
    pub twist: TwistMode,
    /// Length correction (eq. 9): `offset` (the paper's, the default) or `gradient`.
    #[serde(default)]
    pub length_correction: LengthCorrection,
    /// Bend and twist projected one after the other (`sequential`, the default) or as one
    /// 2x2 block (`block`).
    #[serde(default)]
    pub bend_twist: BendTwist,
    /// Direction the body normals point to (projected off the tangent).
    #[serde(default = "default_rod_normal")]
    pub normal: [f32; 3],
}

/// A rod's bend and twist stiffness in physical units, solved in compliance form (XPBD), as an
/// alternative to the paper's `alpha_b` and `alpha_t`: the same stiffness at any iteration
/// count, time step or substep count ([`crate::constraint::rod`]). The fields of a `[[rod]]`
/// or a rod-spine `[[ragdoll]]`, gathered.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StiffnessDef {
    /// Bending stiffness (N m/rad), > 0; replaces `alpha_b`.
    pub bend_stiffness: Option<f32>,
    /// Damping of the bend rate (N m s/rad), >= 0; 0 when unset.
    pub bend_damping: Option<f32>,
    /// Twisting stiffness (N m/rad), > 0; replaces `alpha_t`.
    pub twist_stiffness: Option<f32>,
    /// Damping of the twist rate (N m s/rad), >= 0; 0 when unset.
    pub twist_damping: Option<f32>,
}

macro_rules! stiffness_of {
    ($def:expr) => {
        StiffnessDef {
            bend_stiffness: $def.bend_stiffness,
            bend_damping: $def.bend_damping,
            twist_stiffness: $def.twist_stiffness,
            twist_damping: $def.twist_damping,
        }
    };
}

impl RodDef {
    /// This rod's stiffness fields, gathered.
    pub fn stiffness(&self) -> StiffnessDef {
        stiffness_of!(self)
    }
}

impl RagdollDef {
    /// This ragdoll's rod-spine stiffness fields, gathered.
    pub fn stiffness(&self) -> StiffnessDef {
        stiffness_of!(self)
    }
}

impl StiffnessDef {
    /// The bend stiffness, or None when `bend_stiffness` is unset (damping 0 when unset).
    pub fn bend(&self) -> Option<Stiffness> {
        Some(Stiffness {
            stiffness: self.bend_stiffness?,
            damping: self.bend_damping.unwrap_or(0.0),
        })
    }

    /// The twist stiffness, or None when `twist_stiffness` is unset (damping 0 when unset).
    pub fn twist(&self) -> Option<Stiffness> {
        Some(Stiffness {
            stiffness: self.twist_stiffness?,
            damping: self.twist_damping.unwrap_or(0.0),
        })
    }
}

fn default_rod_normal() -> [f32; 3] {
    [0.0, 0.0, 1.0]
}
