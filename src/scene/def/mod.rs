//! What users write: the serde definitions of a scene file, with their defaults. Method
//! defaults (time step, iterations, bounds, contact options) are read from
//! [`Settings::default`], so each is written once.

use serde::Deserialize;

use super::{Method, Overrides};
use crate::constraint::JointFlavour;
use crate::ragdoll::SpineKind;
use crate::world::{ContactDetection, Settings, SolverKind};

mod bodies;
mod ragdolls;
mod record;
mod rods;

pub use bodies::{BodyDef, JointDef, KindDef, ShapeKind, TileDef};
pub use ragdolls::{DropDef, RagdollDef};
pub use record::RecordDef;
pub use rods::{RodDef, StiffnessDef};

/// The top level of a scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDef {
    /// Recording name; defaults to the file stem.
    pub name: Option<String>,
    /// A named bundle of method settings ([`Method`]) under the file's own keys; none: each
    /// field's default, the paper's method.
    pub method: Option<Method>,
    /// Frame time step (s).
    #[serde(default = "default_dt")]
    pub dt: f32,
    /// Solver iterations per substep.
    #[serde(default = "default_iterations")]
    pub iterations: u32,
    /// Substeps per frame, each of `dt / substeps` with `iterations` sweeps (1: the paper's method).
    #[serde(default = "default_substeps")]
    pub substeps: u32,
    /// How the rows of a colour are solved: scalar (the reference) or simd.
    #[serde(default)]
    pub solver: SolverKind,
    /// Islands of still bodies fall asleep and leave the step (off: the paper's scenes).
    #[serde(default)]
    pub sleep: bool,
    /// Frames to run (default 300); `--frames` overrides it.
    #[serde(default = "default_frames")]
    pub frames: u32,
    /// Frames the main job (`rodlab`, `rodlab all`) runs instead of `frames`, for scenes too
    /// heavy to run in full there; `--frames` overrides both.
    pub ci_frames: Option<u32>,
    /// Gravity acceleration (m/s^2); defaults to [`Settings::default`]'s, -9.81 along y.
    #[serde(default = "default_gravity")]
    pub gravity: [f32; 3],
    /// Default solver flavour of every ball-and-socket joint.
    #[serde(default)]
    pub joint_flavour: JointFlavour,
    /// Explosion bounds (m/s, rad/s).
    #[serde(default = "default_max_speed")]
    pub max_speed: f32,
    /// Explosion bound on angular speed (rad/s); past it the run stops.
    #[serde(default = "default_max_angular_speed")]
    pub max_angular_speed: f32,
    /// Each substep a faster body's spin is scaled down to this angular speed (rad/s), as
    /// game engines do; `inf` (the default) is the paper's method, no limit.
    #[serde(default = "default_angular_speed_limit")]
    pub angular_speed_limit: f32,
    /// A joint or rod apart by more than this (m) after a frame stops the run.
    #[serde(default = "default_max_separation")]
    pub max_separation: f32,
    /// A contact deeper than this (m) after a frame stops the run.
    #[serde(default = "default_max_penetration")]
    pub max_penetration: f32,
    /// What the recording holds (`[record]`); everything but contacts by default.
    #[serde(default)]
    pub record: RecordDef,
    /// Reference humanoids (`[[ragdoll]]`).
    #[serde(default)]
    pub ragdoll: Vec<RagdollDef>,
    /// Rigid bodies (`[[body]]`).
    #[serde(default)]
    pub body: Vec<BodyDef>,
    /// Groups of fixed bodies copied over a grid (expanded into `body` entries when loaded).
    #[serde(default)]
    pub tile: Vec<TileDef>,
    /// Ball-and-socket joints (`[[joint]]`).
    #[serde(default)]
    pub joint: Vec<JointDef>,
    /// Linear and angular velocity damping rates (1/s); zero by default.
    #[serde(default)]
    pub damping: [f32; 2],
    /// Joint damping (N m s/rad): a rotational dashpot across every joint and rod, the torque
    /// `-k w_rel`; zero by default, the paper's method.
    #[serde(default)]
    pub joint_damping: f32,
    /// Joint friction (N m): the most torque every joint and rod resists a turn with; zero by
    /// default, the paper's method.
    #[serde(default)]
    pub joint_friction: f32,
    /// Method variants the main job records beside this one (`[[variant]]`, read as named
    /// [`Overrides`]).
    #[serde(default)]
    pub variant: Vec<Overrides>,
    /// Whether bodies collide (off: no collision work at all).
    #[serde(default)]
    pub contacts: bool,
    /// Contact points are made this far (m) before the surfaces touch.
    #[serde(default = "default_contact_margin")]
    pub contact_margin: f32,
    /// When contact points are found: `frame` (the default, the paper's method) or afresh at
    /// every `substep`.
    #[serde(default)]
    pub contact_detection: ContactDetection,
    /// Deep overlap is pushed out no faster than this (m/s, Box2D's `maxContactPushSpeed`);
    /// `inf` (the default) pushes it out at once, the paper-era projection.
    #[serde(default = "default_contact_push_speed")]
    pub contact_push_speed: f32,
    /// Contact-only sweeps after each substep's iterations; 0 (the default) is the paper's
    /// method.
    #[serde(default)]
    pub contact_extra_sweeps: u32,
    /// Each substep starts its contacts with this fraction of their last impulses (warm
    /// starting, 0 to 1); 0 (the default) is the paper's method.
    #[serde(default)]
    pub contact_warm_start: f32,
    /// Soft contacts: each point a damped spring of this natural frequency (Hz); 0 (the
    /// default) is the paper's hard projection.
    #[serde(default)]
    pub contact_hertz: f32,
    /// The soft contacts' damping ratio (1: critical, the default).
    #[serde(default = "default_contact_damping_ratio")]
    pub contact_damping_ratio: f32,
    /// Stacking (1/m): PBD's mass scaling by height in the contact solve; 0 (the default) is
    /// the paper's contact (see `contact::Stacking`).
    #[serde(default)]
    pub contact_stacking: f32,
    /// The most times heavier stacking makes the lower body (1 or more); `inf` (the default)
    /// is no cap.
    #[serde(default = "default_contact_stacking_max_ratio")]
    pub contact_stacking_max_ratio: f32,
    /// Print a residual row every this many frames (0: only the summary).
    #[serde(default)]
    pub report_every: u32,
    /// A purely kinematic comparison of chains and a rod (Fig. 6) instead of a simulation.
    pub kinematics: Option<KinematicsDef>,
    /// Rod constraints (`[[rod]]`).
    #[serde(default)]
    pub rod: Vec<RodDef>,
    /// Many ragdolls dropped from a grid (expanded into `ragdoll` entries when loaded).
    pub drop: Option<DropDef>,
    /// Spines the main job runs this scene with, one recording each (`<name>_<spine>.rrd`).
    #[serde(default)]
    pub spines: Vec<SpineKind>,
}

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

fn default_contact_margin() -> f32 {
    Settings::default().contact_margin
}
fn default_contact_damping_ratio() -> f32 {
    Settings::default().contact_damping_ratio
}

fn default_contact_push_speed() -> f32 {
    Settings::default().contact_push_speed
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

fn default_dt() -> f32 {
    Settings::default().dt
}
fn default_iterations() -> u32 {
    Settings::default().iterations
}
fn default_substeps() -> u32 {
    Settings::default().substeps
}
fn default_frames() -> u32 {
    300
}
fn default_gravity() -> [f32; 3] {
    Settings::default().gravity.to_array()
}
fn default_max_speed() -> f32 {
    Settings::default().max_linear_speed
}
fn default_max_angular_speed() -> f32 {
    Settings::default().max_angular_speed
}

fn default_contact_stacking_max_ratio() -> f32 {
    Settings::default().contact_stacking_max_ratio
}

fn default_angular_speed_limit() -> f32 {
    Settings::default().angular_speed_limit
}
fn default_max_separation() -> f32 {
    Settings::default().max_separation
}
fn default_max_penetration() -> f32 {
    Settings::default().max_penetration
}
