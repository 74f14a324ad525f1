//! What users write: the serde definitions of a scene file, with their defaults. The method
//! settings are declared once, in `method_settings!` (`solver::settings`), with their defaults.

use serde::Deserialize;

use super::{Method, Overrides};
use crate::constraint::JointFlavour;
use crate::ragdoll::SpineKind;
use crate::world::Settings;

mod bodies;
mod characters;
mod ragdolls;
mod record;
mod rods;

pub use bodies::{BodyDef, JointDef, KindDef, ShapeKind, TileDef};
pub use characters::{CharacterDef, RegionDef};
pub use ragdolls::{DropCharacterDef, DropDef, RagdollDef};
pub use record::RecordDef;
pub use rods::{RodDef, StiffnessDef};

/// Defines [`SceneDef`]: its own fields (given with their defaults) and every method setting
/// (`method_settings!` (`solver::settings`)) as a top-level key.
macro_rules! scene_def {
    ({ $( $(#[doc = $fdoc:literal])* $field:ident : $fty:ty = $fdefault:expr, )* }
     $( $(#[doc = $doc:literal])* $name:ident : $ty:ty = $default:expr,
        unit $unit:literal, bounds $bounds:expr, label $label:literal; )*) => {
        /// The top level of a scene file: the method settings (`rodlab settings` lists them)
        /// and what the scene holds.
        #[derive(Clone, Debug, Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct SceneDef {
            $( $(#[doc = $fdoc])* pub $field: $fty, )*
            $( $(#[doc = $doc])* pub $name: $ty, )*
        }

        impl Default for SceneDef {
            fn default() -> Self {
                SceneDef {
                    $( $field: $fdefault, )*
                    $( $name: $default, )*
                }
            }
        }

        impl SceneDef {
            /// Writes the scene's method settings into `settings`.
            pub fn write_method_settings(&self, settings: &mut Settings) {
                $( settings.$name = self.$name.clone(); )*
            }
        }
    };
}

crate::solver::method_settings!(scene_def! {
    /// Recording name; defaults to the file stem.
    name: Option<String> = None,
    /// A named bundle of method settings ([`Method`]) under the file's own keys; none: each
    /// setting's default, the paper's method.
    method: Option<Method> = None,
    /// Frames to run; `--frames` overrides it.
    frames: u32 = 300,
    /// Frames the main job (`rodlab`, `rodlab all`) runs instead of `frames`, for scenes too
    /// heavy to run in full there; `--frames` overrides both.
    ci_frames: Option<u32> = None,
    /// Gravity acceleration (m/s^2), -9.81 along y.
    gravity: [f32; 3] = Settings::default().gravity.to_array(),
    /// Default solver flavour of every ball-and-socket joint.
    joint_flavour: JointFlavour = JointFlavour::default(),
    /// Explosion bound on linear speed (m/s); past it the run stops.
    max_speed: f32 = Settings::default().max_linear_speed,
    /// Explosion bound on angular speed (rad/s); past it the run stops.
    max_angular_speed: f32 = Settings::default().max_angular_speed,
    /// A joint or rod apart by more than this (m) after a frame stops the run.
    max_separation: f32 = Settings::default().max_separation,
    /// A contact deeper than this (m) after a frame stops the run.
    max_penetration: f32 = Settings::default().max_penetration,
    /// What the recording holds (`[record]`); everything but contacts by default.
    record: RecordDef = RecordDef::default(),
    /// Reference humanoids (`[[ragdoll]]`).
    ragdoll: Vec<RagdollDef> = Vec::new(),
    /// Game characters from rig files (`[[character]]`).
    character: Vec<CharacterDef> = Vec::new(),
    /// Rigid bodies (`[[body]]`).
    body: Vec<BodyDef> = Vec::new(),
    /// Groups of fixed bodies copied over a grid (expanded into `body` entries when loaded).
    tile: Vec<TileDef> = Vec::new(),
    /// Ball-and-socket joints (`[[joint]]`).
    joint: Vec<JointDef> = Vec::new(),
    /// Linear and angular velocity damping rates (1/s); zero by default.
    damping: [f32; 2] = [0.0; 2],
    /// Method variants the main job records beside this one (`[[variant]]`, read as named
    /// [`Overrides`]).
    variant: Vec<Overrides> = Vec::new(),
    /// Whether bodies collide (off: no collision work at all).
    contacts: bool = false,
    /// Contact points are made this far (m) before the surfaces touch.
    contact_margin: f32 = Settings::default().contact_margin,
    /// Print a residual row every this many frames (0: only the summary).
    report_every: u32 = 0,
    /// A purely kinematic comparison of chains and a rod (Fig. 6) instead of a simulation.
    kinematics: Option<KinematicsDef> = None,
    /// Rod constraints (`[[rod]]`).
    rod: Vec<RodDef> = Vec::new(),
    /// Many ragdolls dropped from a grid (expanded into `ragdoll` entries when loaded).
    drop: Option<DropDef> = None,
    /// Spines the main job runs this scene with, one recording each (`<name>_<spine>.rrd`).
    spines: Vec<SpineKind> = Vec::new(),
});

/// Fig. 6: end loci of an equal-angle chain, an unequal-angle chain and a rod of one length,
/// swept over bends in [-max_bend, max_bend] across the scene's frames.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KinematicsDef {
    /// Spine length (m), pelvis centre to chest centre.
    #[serde(default = "default_spine_length")]
    pub length: f32,
    /// Joints in the chains.
    #[serde(default = "default_chain_joints")]
    pub joints: usize,
    /// Shares of the bend taken by each joint of the unequal chain (normalised).
    pub unequal: Vec<f32>,
    /// Largest bend (deg).
    #[serde(default = "default_max_bend")]
    pub max_bend: f32,
}

fn default_spine_length() -> f32 {
    0.385
}
fn default_chain_joints() -> usize {
    3
}
fn default_max_bend() -> f32 {
    150.0
}

impl SceneDef {
    /// The spines a run per spine takes when none are named: `spines`; else the multi-joint
    /// spine and the rod of what the scene holds (a game character's rig, else the humanoid's
    /// chain3).
    pub fn default_spines(&self) -> Vec<SpineKind> {
        if !self.spines.is_empty() {
            return self.spines.clone();
        }
        let own = match self.ragdoll.is_empty() && !self.character.is_empty() {
            true => SpineKind::Rig,
            false => SpineKind::Chain3,
        };
        vec![own, SpineKind::Rod]
    }
}
