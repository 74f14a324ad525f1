//! What users write: the serde definitions of a scene file, with their defaults. Method
//! defaults (time step, iterations, bounds, contact options) are read from
//! [`Settings::default`], so each is written once.

use serde::Deserialize;

use super::VariantDef;
use crate::constraint::{JointFlavour, LengthCorrection, Stiffness, TwistMode};
use crate::ragdoll::SpineKind;
use crate::shape::Axis;
use crate::world::{Settings, SolverKind};

/// The top level of a scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDef {
    /// Recording name; defaults to the file stem.
    pub name: Option<String>,
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
    /// Method variants the main job records beside this one ([`VariantDef`]).
    #[serde(default)]
    pub variant: Vec<VariantDef>,
    /// Whether bodies collide (off: no collision work at all).
    #[serde(default)]
    pub contacts: bool,
    /// Contact points are made this far (m) before the surfaces touch.
    #[serde(default = "default_contact_margin")]
    pub contact_margin: f32,
    /// Deep overlap is pushed out no faster than this (m/s, Box2D's `maxContactPushSpeed`);
    /// `inf` (the default) pushes it out at once, the paper-era projection.
    #[serde(default = "default_contact_push_speed")]
    pub contact_push_speed: f32,
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
}

fn default_tip() -> f32 {
    90.0
}

/// A group of fixed bodies copied over a grid in x and z: copy `(i, k)`, for `i` in
/// `0..repeat[0]` and `k` in `0..repeat[1]`, moves every body of the group by
/// `[i * spacing[0], 0, k * spacing[1]]` and names it `<tile>_<i>_<k>_<body>`. Expanded into
/// `[[body]]` entries when the scene is loaded, after the group itself was checked.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TileDef {
    /// Tile name, the prefix of its copies' names.
    pub name: String,
    /// Copies along x and along z (each >= 1).
    pub repeat: [u32; 2],
    /// Distance between copies along x and along z (m, > 0).
    pub spacing: [f32; 2],
    /// The group: fixed boxes, spheres or capsules, positioned as for copy (0, 0).
    pub body: Vec<BodyDef>,
}

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
fn default_max_separation() -> f32 {
    Settings::default().max_separation
}
fn default_max_penetration() -> f32 {
    Settings::default().max_penetration
}
fn yes() -> bool {
    true
}

/// What the recording holds.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordDef {
    /// Body poses and shapes.
    #[serde(default = "yes")]
    pub bodies: bool,
    /// Joint anchor pairs.
    #[serde(default = "yes")]
    pub joints: bool,
    /// Per-ragdoll residual plots.
    #[serde(default = "yes")]
    pub residuals: bool,
    /// Kinetic, potential and total energy.
    #[serde(default = "yes")]
    pub energy: bool,
    /// Contact points and normals (off by default: many points a frame).
    #[serde(default)]
    pub contacts: bool,
    /// Rod centerlines, material frames and rod scalars.
    #[serde(default = "yes")]
    pub rods: bool,
    /// Animation bones and their errors, per ragdoll and mapping method.
    #[serde(default = "yes")]
    pub bones: bool,
    /// Record every N-th frame (frames 0, N, 2N, ...); 1 records them all.
    #[serde(default = "one")]
    pub every: u32,
    /// End the file with Rerun's footer, a manifest of every chunk (`rerun rrd verify` wants
    /// it; the viewer seeks with it). The writer keeps about 1.4 kB per chunk in memory until
    /// the file closes, one chunk per entity per second: `false` keeps a long run's memory
    /// flat, and `rerun rrd optimize` adds the footer afterwards.
    #[serde(default = "yes")]
    pub footer: bool,
}

fn one() -> u32 {
    1
}

impl Default for RecordDef {
    fn default() -> Self {
        RecordDef {
            every: 1,
            bodies: true,
            joints: true,
            residuals: true,
            energy: true,
            contacts: false,
            rods: true,
            bones: true,
            footer: true,
        }
    }
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
    /// Constant external forces (N) on parts, e.g. `{ chest = [0.0, 0.0, 150.0] }`.
    #[serde(default)]
    pub forces: std::collections::BTreeMap<String, [f32; 3]>,
}

/// A `[[body]]`'s `kind`: how the solver treats it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum KindDef {
    /// Moved by forces and constraints (the default).
    #[default]
    Dynamic,
    /// Never moves; infinite mass.
    Fixed,
    /// Moves with its given velocity; infinite mass for constraints.
    Kinematic,
}

/// A `[[body]]`'s `shape`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShapeKind {
    /// Needs `radius`.
    Sphere,
    /// Needs `radius` and `half_height`; `axis` defaults to y.
    Capsule,
    /// Needs `half_extents`.
    Box,
    /// A half-space below the plane through `position` with normal `rotation * +Y`; fixed only.
    Plane,
}

/// A `[[body]]`: one rigid body.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDef {
    /// Body name, unique in the scene.
    pub name: String,
    /// How the solver treats it (default dynamic).
    #[serde(default)]
    pub kind: KindDef,
    /// Its shape; each kind needs its own size fields.
    pub shape: ShapeKind,
    /// Sphere and capsule radius (m).
    pub radius: Option<f32>,
    /// Capsule half distance between cap centres (m).
    pub half_height: Option<f32>,
    /// Capsule axis in body space.
    pub axis: Option<Axis>,
    /// Box half extents (m).
    pub half_extents: Option<[f32; 3]>,
    /// Mass (kg); give this or `density`.
    pub mass: Option<f32>,
    /// Density (kg/m^3); give this or `mass`.
    pub density: Option<f32>,
    /// Position of the centre of mass (m); default the origin.
    #[serde(default)]
    pub position: [f32; 3],
    /// Rotation vector (deg).
    #[serde(default)]
    pub rotation: [f32; 3],
    /// Initial linear velocity (m/s); ignored for fixed bodies.
    #[serde(default)]
    pub velocity: [f32; 3],
    /// Initial angular velocity (rad/s); ignored for fixed bodies.
    #[serde(default)]
    pub angular_velocity: [f32; 3],
    /// Coulomb friction coefficients (default 0.6 static, 0.5 dynamic).
    pub static_friction: Option<f32>,
    /// Dynamic Coulomb friction coefficient (default 0.5).
    pub dynamic_friction: Option<f32>,
    /// Coefficient of restitution in [0, 1] (default 0: inelastic).
    pub restitution: Option<f32>,
    /// Collision filter bits (default group 1, mask all).
    pub collision_group: Option<u32>,
    /// Collision mask bits (default all).
    pub collision_mask: Option<u32>,
}

/// A `[[joint]]`: a ball-and-socket joint between two named bodies, taken at their starting poses.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointDef {
    /// Joint name, for reports and recordings.
    pub name: String,
    /// Name of the first body.
    pub a: String,
    /// Name of the second body.
    pub b: String,
    /// World anchor point at the starting pose (m).
    pub anchor: [f32; 3],
    /// Twist or hinge axis in world space at the starting pose.
    #[serde(default = "default_twist_axis")]
    pub axis: [f32; 3],
    /// Solver flavour of the point part; defaults to the scene's `joint_flavour`.
    pub flavour: Option<JointFlavour>,
    /// Swing cone half-angle (deg).
    pub swing: Option<f32>,
    /// Twist range [min, max] (deg).
    pub twist: Option<[f32; 2]>,
    /// Hinge range [min, max] (deg) about `axis`; excludes `swing` and `twist`.
    pub hinge: Option<[f32; 2]>,
    /// Relaxation in [0, 1] of a spring toward the starting relative orientation.
    pub spring: Option<f32>,
}

fn default_twist_axis() -> [f32; 3] {
    [1.0, 0.0, 0.0]
}
