//! Scene files: what users write (TOML, read with serde, unknown fields refused), checked,
//! then built into a [`Lab`] (a [`World`] and its ragdolls). The definitions here are separate from solver state.
//!
//! Every error reads `FILE:LINE: FIELD: message`, for syntax, type and semantic mistakes alike.

pub mod bounds;
mod locate;
mod overrides;
mod variant;

pub use overrides::Overrides;
pub use variant::VariantDef;

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::body::{Body, BodyKind};
use crate::constraint::{
    AngularLimit, BallSocket, Constraint, JointFlavour, LengthCorrection, Rod, Stiffness, TwistMode,
};
use crate::lab::Lab;
use crate::math::{quat_from_degrees, Iso, Quat, Vec3};
use crate::ragdoll::{joint_names, HumanoidSpec, RodParams, SpineKind};
use crate::shape::{Axis, Shape};
use crate::world::{
    Settings, SolverKind, World, DEFAULT_MAX_ANGULAR_SPEED, DEFAULT_MAX_LINEAR_SPEED,
};
use locate::Seg;

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
    #[serde(default = "default_frames")]
    pub frames: u32,
    /// Frames the main job (`rodlab`, `rodlab all`) runs instead of `frames`, for scenes too
    /// heavy to run in full there; `--frames` overrides both.
    pub ci_frames: Option<u32>,
    #[serde(default = "default_gravity")]
    pub gravity: [f32; 3],
    /// Default solver flavour of every ball-and-socket joint.
    #[serde(default)]
    pub joint_flavour: JointFlavour,
    /// Explosion bounds (m/s, rad/s).
    #[serde(default = "default_max_speed")]
    pub max_speed: f32,
    #[serde(default = "default_max_angular_speed")]
    pub max_angular_speed: f32,
    /// A joint or rod apart by more than this (m) after a frame stops the run.
    #[serde(default = "default_max_separation")]
    pub max_separation: f32,
    /// A contact deeper than this (m) after a frame stops the run.
    #[serde(default = "default_max_penetration")]
    pub max_penetration: f32,
    #[serde(default)]
    pub record: RecordDef,
    #[serde(default)]
    pub ragdoll: Vec<RagdollDef>,
    #[serde(default)]
    pub body: Vec<BodyDef>,
    /// Groups of fixed bodies copied over a grid (expanded into `body` entries when loaded).
    #[serde(default)]
    pub tile: Vec<TileDef>,
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
    pub count: usize,
    #[serde(default)]
    pub spine: SpineKind,
    /// Root position of the first ragdoll (m).
    pub first: [f32; 3],
    /// Distance between neighbours along x, between layers along y, along z (m).
    pub spacing: [f32; 3],
    pub columns: usize,
    pub rows: usize,
    #[serde(default)]
    pub seed: u64,
    /// Largest tip away from upright (deg).
    #[serde(default = "default_tip")]
    pub max_tip: f32,
}

fn default_tip() -> f32 {
    90.0
}

impl DropDef {
    /// The ragdolls this block stands for.
    fn expand(&self) -> Vec<RagdollDef> {
        let mut state = self
            .seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut random = move || {
            // 64-bit LCG (Knuth's MMIX constants), top 24 bits as a float in [0, 1)
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let per_layer = (self.columns * self.rows).max(1);
        (0..self.count)
            .map(|i| {
                let (layer, cell) = (i / per_layer, i % per_layer);
                let (column, row) = (cell % self.columns.max(1), cell / self.columns.max(1));
                let position = [
                    self.first[0] + column as f32 * self.spacing[0],
                    self.first[1] + layer as f32 * self.spacing[1],
                    self.first[2] + row as f32 * self.spacing[2],
                ];
                let yaw = 360.0 * random();
                let tip = self.max_tip * random();
                let rotation = crate::math::rotation_vector(
                    quat_from_degrees([0.0, yaw, 0.0]) * quat_from_degrees([tip, 0.0, 0.0]),
                );
                RagdollDef {
                    name: format!("drop{i:02}"),
                    spine: self.spine,
                    joint_flavour: None,
                    position,
                    rotation: (rotation * 180.0 / std::f32::consts::PI).to_array(),
                    pose: Default::default(),
                    fixed: Vec::new(),
                    spine_spring: Some(0.05),
                    limb_spring: None,
                    alpha_b: None,
                    alpha_t: None,
                    bend_stiffness: None,
                    bend_damping: None,
                    twist_stiffness: None,
                    twist_damping: None,
                    twist: None,
                    rod_length: None,
                    forces: Default::default(),
                }
            })
            .collect()
    }
}

/// A group of fixed bodies copied over a grid in x and z: copy `(i, k)`, for `i` in
/// `0..repeat[0]` and `k` in `0..repeat[1]`, moves every body of the group by
/// `[i * spacing[0], 0, k * spacing[1]]` and names it `<tile>_<i>_<k>_<body>`. Expanded into
/// `[[body]]` entries when the scene is loaded, after the group itself was checked.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TileDef {
    pub name: String,
    /// Copies along x and along z (each >= 1).
    pub repeat: [u32; 2],
    /// Distance between copies along x and along z (m, > 0).
    pub spacing: [f32; 2],
    /// The group: fixed boxes, spheres or capsules, positioned as for copy (0, 0).
    pub body: Vec<BodyDef>,
}

impl TileDef {
    /// Name of copy `(i, k)` of the group's body `body`.
    fn copy_name(&self, i: u32, k: u32, body: &str) -> String {
        format!("{}_{i}_{k}_{body}", self.name)
    }

    /// The bodies this tile stands for.
    fn expand(&self) -> Vec<BodyDef> {
        let mut out =
            Vec::with_capacity(self.body.len() * (self.repeat[0] * self.repeat[1]) as usize);
        for i in 0..self.repeat[0] {
            for k in 0..self.repeat[1] {
                for b in &self.body {
                    let mut copy = b.clone();
                    copy.name = self.copy_name(i, k, &b.name);
                    copy.position[0] += i as f32 * self.spacing[0];
                    copy.position[2] += k as f32 * self.spacing[1];
                    out.push(copy);
                }
            }
        }
        out
    }
}

/// A rod constraint (paper §5) between two named bodies, instantiated at their starting poses
/// (§6): tangents along the offset between the centres.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodDef {
    pub name: String,
    pub a: String,
    pub b: String,
    /// Rest length l_0 (m); defaults to the distance between the centres.
    pub rest_length: Option<f32>,
    #[serde(default)]
    pub alpha_b: f32,
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
    #[serde(default)]
    pub twist: TwistMode,
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
    pub bend_stiffness: Option<f32>,
    pub bend_damping: Option<f32>,
    pub twist_stiffness: Option<f32>,
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
    pub fn stiffness(&self) -> StiffnessDef {
        stiffness_of!(self)
    }
}

impl RagdollDef {
    pub fn stiffness(&self) -> StiffnessDef {
        stiffness_of!(self)
    }
}

impl StiffnessDef {
    pub fn bend(&self) -> Option<Stiffness> {
        Some(Stiffness {
            stiffness: self.bend_stiffness?,
            damping: self.bend_damping.unwrap_or(0.0),
        })
    }

    pub fn twist(&self) -> Option<Stiffness> {
        Some(Stiffness {
            stiffness: self.twist_stiffness?,
            damping: self.twist_damping.unwrap_or(0.0),
        })
    }

    /// Positive stiffness, damping only beside one, and neither beside the alpha it replaces
    /// (`alpha_b`, `alpha_t`: whether the file sets them).
    fn check(&self, alpha_b: bool, alpha_t: bool) -> Result<(), (&'static str, String)> {
        let parts = [
            (
                "bend_stiffness",
                "bend_damping",
                "alpha_b",
                alpha_b,
                self.bend_stiffness,
                self.bend_damping,
            ),
            (
                "twist_stiffness",
                "twist_damping",
                "alpha_t",
                alpha_t,
                self.twist_stiffness,
                self.twist_damping,
            ),
        ];
        for (stiffness_field, damping_field, alpha_field, alpha, stiffness, damping) in parts {
            match stiffness {
                Some(k) if !(k > 0.0 && k.is_finite()) => {
                    return Err((
                        stiffness_field,
                        format!("must be a positive stiffness in N m/rad, got {k}"),
                    ))
                }
                Some(_) if alpha => {
                    return Err((
                        stiffness_field,
                        format!("replaces {alpha_field}: set one of them, not both"),
                    ))
                }
                None if damping.is_some() => {
                    return Err((
                        damping_field,
                        format!("damps the {stiffness_field}, which is not set"),
                    ))
                }
                _ => {}
            }
            if let Some(c) = damping.filter(|c| !(*c >= 0.0 && c.is_finite())) {
                return Err((
                    damping_field,
                    format!("must be 0 or more N m s/rad, got {c}"),
                ));
            }
        }
        Ok(())
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
    0.02
}
fn default_contact_damping_ratio() -> f32 {
    1.0
}

fn default_contact_push_speed() -> f32 {
    crate::solver::DEFAULT_CONTACT_PUSH_SPEED
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
    1.0 / 60.0
}
fn default_iterations() -> u32 {
    20
}
fn default_substeps() -> u32 {
    1
}
fn default_frames() -> u32 {
    300
}
fn default_gravity() -> [f32; 3] {
    [0.0, -9.81, 0.0]
}
fn default_max_speed() -> f32 {
    DEFAULT_MAX_LINEAR_SPEED
}
fn default_max_angular_speed() -> f32 {
    DEFAULT_MAX_ANGULAR_SPEED
}
fn default_max_separation() -> f32 {
    crate::solver::DEFAULT_MAX_SEPARATION
}
fn default_max_penetration() -> f32 {
    crate::solver::DEFAULT_MAX_PENETRATION
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

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RagdollDef {
    pub name: String,
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

#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum KindDef {
    #[default]
    Dynamic,
    Fixed,
    Kinematic,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShapeKind {
    Sphere,
    Capsule,
    Box,
    /// A half-space below the plane through `position` with normal `rotation * +Y`; fixed only.
    Plane,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDef {
    pub name: String,
    #[serde(default)]
    pub kind: KindDef,
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
    #[serde(default)]
    pub position: [f32; 3],
    /// Rotation vector (deg).
    #[serde(default)]
    pub rotation: [f32; 3],
    #[serde(default)]
    pub velocity: [f32; 3],
    #[serde(default)]
    pub angular_velocity: [f32; 3],
    /// Coulomb friction coefficients (default 0.6 static, 0.5 dynamic).
    pub static_friction: Option<f32>,
    pub dynamic_friction: Option<f32>,
    /// Coefficient of restitution in [0, 1] (default 0: inelastic).
    pub restitution: Option<f32>,
    /// Collision filter bits (default group 1, mask all).
    pub collision_group: Option<u32>,
    pub collision_mask: Option<u32>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointDef {
    pub name: String,
    pub a: String,
    pub b: String,
    /// World anchor point at the starting pose (m).
    pub anchor: [f32; 3],
    /// Twist or hinge axis in world space at the starting pose.
    #[serde(default = "default_twist_axis")]
    pub axis: [f32; 3],
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

/// A scene error located in its file.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    pub file: PathBuf,
    pub line: usize,
    pub field: String,
    pub message: String,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: ", self.file.display(), self.line)?;
        if !self.field.is_empty() {
            write!(f, "{}: ", self.field)?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for SceneError {}

/// A parsed and checked scene, with its source text (logged into recordings).
#[derive(Clone, Debug)]
pub struct Scene {
    pub path: PathBuf,
    pub text: String,
    pub def: SceneDef,
}

impl Scene {
    /// Reads and checks a scene file.
    pub fn load(path: impl AsRef<Path>) -> anyhow::Result<Scene> {
        let path = path.as_ref();
        let bytes = std::fs::read(path)
            .map_err(|e| anyhow::anyhow!("{}: cannot read scene file: {e}", path.display()))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
            let column = valid.iter().rev().take_while(|&&b| b != b'\n').count() + 1;
            anyhow::anyhow!(
                "{}:{line}: not UTF-8 text (a bad byte at column {column}); scene files are UTF-8 TOML",
                path.display()
            )
        })?;
        Ok(Scene::parse(path, &text)?)
    }

    /// Parses and checks scene text; `path` is used in messages only.
    pub fn parse(path: impl AsRef<Path>, text: &str) -> Result<Scene, SceneError> {
        let path = path.as_ref().to_path_buf();
        let def: SceneDef = toml::from_str(text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            let field = locate::parse(text)
                .map(|doc| locate::render(&locate::path_at(doc.get_ref(), &span)));
            SceneError {
                file: path.clone(),
                line: locate::line_of(text, span.start),
                field: field.unwrap_or_default(),
                message: tidy_serde_message(e.message()),
            }
        })?;
        let mut scene = Scene {
            path,
            text: text.to_string(),
            def,
        };
        // the drop block is checked before it makes its ragdolls
        if let Some(drop) = &scene.def.drop {
            bounds::check_drop(drop).map_err(|(p, message)| scene.error_at(&p, message))?;
            let generated = drop.expand();
            scene.def.ragdoll.extend(generated);
        }
        // tiles are checked where they are written, then copied into `body`
        scene
            .check_tiles()
            .map_err(|(p, message)| scene.error_at(&p, message))?;
        let copies: Vec<BodyDef> = scene.def.tile.iter().flat_map(TileDef::expand).collect();
        scene.def.body.extend(copies);
        scene
            .check()
            .map_err(|(p, message)| scene.error_at(&p, message))?;
        Ok(scene)
    }

    /// Name used for the recording: `name`, or the file stem.
    pub fn name(&self) -> String {
        self.def.name.clone().unwrap_or_else(|| {
            self.path
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        })
    }

    fn error_at(&self, path: &[Seg], message: String) -> SceneError {
        let doc = locate::parse(&self.text).expect("text parsed before");
        let span = locate::span_of(&doc, path);
        SceneError {
            file: self.path.clone(),
            line: locate::line_of(&self.text, span.start),
            field: locate::render(path),
            message,
        }
    }

    /// The `[[tile]]` groups, before they are expanded: sizes, names, and fixed bodies only.
    fn check_tiles(&self) -> Result<(), (Vec<Seg>, String)> {
        let d = &self.def;
        let at = |i: usize, field: &str| {
            vec![
                Seg::Key("tile".into()),
                Seg::Index(i),
                Seg::Key(field.into()),
            ]
        };
        let mut tile_names: Vec<&str> = Vec::new();
        for (i, t) in d.tile.iter().enumerate() {
            check_name(&t.name, &tile_names).map_err(|m| (at(i, "name"), m))?;
            tile_names.push(&t.name);
            if t.repeat.contains(&0) {
                return Err((
                    at(i, "repeat"),
                    format!(
                        "copies along x and z must be at least 1, got {:?}",
                        t.repeat
                    ),
                ));
            }
            if t.spacing.iter().any(|s| !(*s > 0.0 && s.is_finite())) {
                return Err((
                    at(i, "spacing"),
                    format!("must be positive distances (m), got {:?}", t.spacing),
                ));
            }
            if t.body.is_empty() {
                return Err((at(i, "body"), "needs at least one [[tile.body]]".into()));
            }
            let made = bounds::tile_bodies(t.repeat, t.body.len());
            if made > bounds::MAX_TILE_BODIES {
                return Err((
                    at(i, "repeat"),
                    format!("makes {made} bodies, more than {}", bounds::MAX_TILE_BODIES),
                ));
            }
            let mut names: Vec<&str> = Vec::new();
            for (j, b) in t.body.iter().enumerate() {
                let field = |f: &str| {
                    vec![
                        Seg::Key("tile".into()),
                        Seg::Index(i),
                        Seg::Key("body".into()),
                        Seg::Index(j),
                        Seg::Key(f.into()),
                    ]
                };
                check_name(&b.name, &names).map_err(|m| (field("name"), m))?;
                names.push(&b.name);
                if b.kind != KindDef::Fixed {
                    return Err((
                        field("kind"),
                        "a tile copies static geometry: kind must be \"fixed\"".into(),
                    ));
                }
                if b.shape == ShapeKind::Plane {
                    return Err((
                        field("shape"),
                        "a plane is unbounded: give it as one [[body]], not in a tile".into(),
                    ));
                }
                check_body(b).map_err(|(f, m)| (field(f), m))?;
                bounds::check_body(b, d.max_speed, d.max_angular_speed)
                    .map_err(|(f, m)| (field(f), m))?;
                for other in &d.body {
                    if other.name == t.copy_name(0, 0, &b.name) {
                        return Err((
                            field("name"),
                            format!(
                                "its copies are named {}_<i>_<k>_{}, and body \"{}\" already exists",
                                t.name, b.name, other.name
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// Semantic checks serde cannot express.
    fn check(&self) -> Result<(), (Vec<Seg>, String)> {
        let d = &self.def;
        let at = |list: &str, i: usize, field: &str| {
            vec![Seg::Key(list.into()), Seg::Index(i), Seg::Key(field.into())]
        };
        check_settings(d, &[])?;
        if !(1..=bounds::MAX_FRAMES).contains(&d.record.every) {
            return Err((
                vec![Seg::Key("record".into()), Seg::Key("every".into())],
                format!("must be at least 1 (every frame), got {}", d.record.every),
            ));
        }
        if let Some(name) = &d.name {
            bounds::check_scene_name(name).map_err(|m| (vec![Seg::Key("name".into())], m))?;
        }
        let mut variants: Vec<&str> = Vec::new();
        for (i, v) in d.variant.iter().enumerate() {
            variant::check_variant_name(&v.name, &variants)
                .map_err(|m| (at("variant", i, "name"), m))?;
            variants.push(&v.name);
            let prefix = [Seg::Key("variant".into()), Seg::Index(i)];
            check_settings(&v.applied_to(d), &prefix)?;
        }
        if let Some(k) = &d.kinematics {
            let field = |f: &str| vec![Seg::Key("kinematics".into()), Seg::Key(f.into())];
            if !(k.length > 0.0 && k.length <= bounds::MAX_SIZE) {
                return Err((
                    field("length"),
                    format!(
                        "must be positive, at most {} m, got {}",
                        bounds::MAX_SIZE,
                        k.length
                    ),
                ));
            }
            if !(1..=1000).contains(&k.joints) {
                return Err((
                    field("joints"),
                    format!("must lie in [1, 1000], got {}", k.joints),
                ));
            }
            if !(k.max_bend.abs() <= bounds::MAX_DEGREES) {
                return Err((
                    field("max_bend"),
                    format!("must be a finite angle (deg), got {}", k.max_bend),
                ));
            }
            if k.unequal.len() != k.joints
                || k.unequal.iter().any(|w| !(*w >= 0.0 && w.is_finite()))
                || k.unequal.iter().sum::<f32>() <= 0.0
            {
                return Err((
                    field("unequal"),
                    format!("needs {} non-negative shares with a positive sum", k.joints),
                ));
            }
            if !d.ragdoll.is_empty() || !d.body.is_empty() {
                return Err((
                    field("joints"),
                    "a kinematics scene simulates nothing: remove its ragdolls and bodies".into(),
                ));
            }
        }
        let mut names: Vec<&str> = Vec::new();
        for (i, r) in d.ragdoll.iter().enumerate() {
            check_name(&r.name, &names).map_err(|m| (at("ragdoll", i, "name"), m))?;
            names.push(&r.name);
            for (field, value) in [
                ("spine_spring", r.spine_spring),
                ("limb_spring", r.limb_spring),
            ] {
                check_relaxation(value).map_err(|m| (at("ragdoll", i, field), m))?;
            }
            for (field, value) in [("alpha_b", r.alpha_b), ("alpha_t", r.alpha_t)] {
                check_relaxation(value).map_err(|m| (at("ragdoll", i, field), m))?;
            }
            r.stiffness()
                .check(r.alpha_b.is_some(), r.alpha_t.is_some())
                .map_err(|(f, m)| (at("ragdoll", i, f), m))?;
            bounds::check_ragdoll(r, |f| at("ragdoll", i, f))?;
            let joints = joint_names(r.spine);
            for joint in r.pose.keys() {
                if !joints.contains(&joint.as_str()) {
                    let mut p = at("ragdoll", i, "pose");
                    p.push(Seg::Key(joint.clone()));
                    return Err((
                        p,
                        format!(
                            "unknown joint \"{joint}\" for spine {}, expected one of {}",
                            r.spine,
                            joints.join(", ")
                        ),
                    ));
                }
            }
            let parts = crate::ragdoll::part_names(r.spine);
            for part in r.forces.keys() {
                if !parts.contains(&part.as_str()) {
                    let mut p = at("ragdoll", i, "forces");
                    p.push(Seg::Key(part.clone()));
                    return Err((
                        p,
                        format!(
                            "unknown part \"{part}\", expected one of {}",
                            parts.join(", ")
                        ),
                    ));
                }
            }
            for part in &r.fixed {
                if !parts.contains(&part.as_str()) {
                    return Err((
                        at("ragdoll", i, "fixed"),
                        format!(
                            "unknown part \"{part}\", expected one of {}",
                            parts.join(", ")
                        ),
                    ));
                }
            }
        }
        let mut body_names: Vec<&str> = Vec::new();
        for (i, b) in d.body.iter().enumerate() {
            check_name(&b.name, &body_names).map_err(|m| (at("body", i, "name"), m))?;
            body_names.push(&b.name);
            check_body(b).map_err(|(field, m)| (at("body", i, field), m))?;
            bounds::check_body(b, d.max_speed, d.max_angular_speed)
                .map_err(|(field, m)| (at("body", i, field), m))?;
        }
        for (i, r) in d.rod.iter().enumerate() {
            check_name(&r.name, &names).map_err(|m| (at("rod", i, "name"), m))?;
            names.push(&r.name);
            check_pair(&r.a, &r.b, &body_names).map_err(|(f, m)| (at("rod", i, f), m))?;
            if let Some(l) = r
                .rest_length
                .filter(|l| !(*l > 0.0 && *l <= bounds::MAX_SIZE))
            {
                return Err((
                    at("rod", i, "rest_length"),
                    format!("must be a positive length, got {l}"),
                ));
            }
            check_relaxation(Some(r.alpha_b)).map_err(|m| (at("rod", i, "alpha_b"), m))?;
            check_relaxation(Some(r.alpha_t)).map_err(|m| (at("rod", i, "alpha_t"), m))?;
            r.stiffness()
                .check(r.alpha_b != 0.0, r.alpha_t != 0.0)
                .map_err(|(f, m)| (at("rod", i, f), m))?;
        }
        let mut joint_names_seen: Vec<&str> = Vec::new();
        for (i, j) in d.joint.iter().enumerate() {
            check_name(&j.name, &joint_names_seen).map_err(|m| (at("joint", i, "name"), m))?;
            joint_names_seen.push(&j.name);
            check_pair(&j.a, &j.b, &body_names).map_err(|(f, m)| (at("joint", i, f), m))?;
            bounds::check_joint(j).map_err(|(f, m)| (at("joint", i, f), m))?;
            check_relaxation(j.spring).map_err(|m| (at("joint", i, "spring"), m))?;
            if Vec3::from(j.axis).length() < 1e-6 {
                return Err((at("joint", i, "axis"), "must be a non-zero vector".into()));
            }
            if j.hinge.is_some() && (j.swing.is_some() || j.twist.is_some()) {
                return Err((
                    at("joint", i, "hinge"),
                    "a hinge excludes swing and twist".into(),
                ));
            }
            if let Some([lo, hi]) = j.twist.or(j.hinge) {
                if lo > hi {
                    let f = if j.hinge.is_some() { "hinge" } else { "twist" };
                    return Err((
                        at("joint", i, f),
                        format!("range [{lo}, {hi}] has min above max"),
                    ));
                }
            }
            if matches!(j.swing, Some(s) if s < 0.0) {
                return Err((at("joint", i, "swing"), "must not be negative".into()));
            }
        }
        Ok(())
    }

    /// Builds the lab (world and ragdolls) this scene describes.
    pub fn build(&self) -> Result<Lab, SceneError> {
        let d = &self.def;
        let mut lab = Lab::new(World::new(Settings {
            gravity: Vec3::from(d.gravity),
            dt: d.dt,
            iterations: d.iterations,
            substeps: d.substeps,
            solver: d.solver,
            max_linear_speed: d.max_speed,
            max_angular_speed: d.max_angular_speed,
            max_separation: d.max_separation,
            max_penetration: d.max_penetration,
            contacts: d.contacts,
            contact_margin: d.contact_margin,
            contact_push_speed: d.contact_push_speed,
            contact_warm_start: d.contact_warm_start,
            contact_hertz: d.contact_hertz,
            contact_damping_ratio: d.contact_damping_ratio,
            contact_stacking: d.contact_stacking,
            sleep: d.sleep,
            linear_damping: d.damping[0],
            angular_damping: d.damping[1],
            joint_damping: d.joint_damping,
        }));
        for (i, r) in d.ragdoll.iter().enumerate() {
            let spec = HumanoidSpec {
                name: r.name.clone(),
                spine: r.spine,
                joint_flavour: r.joint_flavour.unwrap_or(d.joint_flavour),
                root: Iso::new(Vec3::from(r.position), quat_from_degrees(r.rotation)),
                joint_rotations: r
                    .pose
                    .iter()
                    .map(|(k, v)| (k.clone(), quat_from_degrees(*v)))
                    .collect(),
                spine_spring: r.spine_spring,
                limb_spring: r.limb_spring,
                fixed: r.fixed.clone(),
                forces: r
                    .forces
                    .iter()
                    .map(|(k, v)| (k.clone(), Vec3::from(*v)))
                    .collect(),
                rod: {
                    let default = RodParams::default();
                    RodParams {
                        alpha_bend: r.alpha_b.unwrap_or(default.alpha_bend),
                        alpha_twist: r.alpha_t.unwrap_or(default.alpha_twist),
                        bend_stiffness: r.stiffness().bend(),
                        twist_stiffness: r.stiffness().twist(),
                        twist_mode: r.twist.unwrap_or(default.twist_mode),
                        length_correction: r.rod_length.unwrap_or(default.length_correction),
                    }
                },
            };
            let path = [
                Seg::Key("ragdoll".into()),
                Seg::Index(i),
                Seg::Key("spine".into()),
            ];
            lab.add_humanoid(&spec)
                .map_err(|m| self.error_at(&path, m))?;
        }
        let world = &mut lab.world;
        for b in &d.body {
            world.add_body(build_body(b));
        }
        for j in &d.joint {
            let a = world.find_body(&j.a).expect("checked");
            let b = world.find_body(&j.b).expect("checked");
            let frame = Quat::from_rotation_arc(Vec3::X, Vec3::from(j.axis).normalize());
            let mut joint = BallSocket::at_world_anchor(
                &j.name,
                &world.bodies,
                a,
                b,
                Vec3::from(j.anchor),
                frame,
            )
            .with_flavour(j.flavour.unwrap_or(d.joint_flavour));
            if let Some([lo, hi]) = j.hinge {
                joint = joint.with_limit(AngularLimit::hinge(lo.to_radians(), hi.to_radians()));
            } else if j.swing.is_some() || j.twist.is_some() {
                let swing = j.swing.unwrap_or(180.0).to_radians();
                let [lo, hi] = j.twist.unwrap_or([-180.0, 180.0]);
                joint =
                    joint.with_limit(AngularLimit::cone(swing, lo.to_radians(), hi.to_radians()));
            }
            if let Some(relaxation) = j.spring {
                joint = joint.with_spring(&world.bodies, relaxation);
            }
            world.constraints.push(Constraint::BallSocket(joint));
        }
        for (i, r) in d.rod.iter().enumerate() {
            let (a, b) = (
                world.find_body(&r.a).expect("checked"),
                world.find_body(&r.b).expect("checked"),
            );
            let path = [Seg::Key("rod".into()), Seg::Index(i), Seg::Key("b".into())];
            let mut rod = Rod::instantiate(&r.name, &world.bodies, a, b, Vec3::from(r.normal))
                .map_err(|m| self.error_at(&path, m))?;
            rod.rest_length = r.rest_length.unwrap_or(rod.rest_length);
            rod.alpha_bend = r.alpha_b;
            rod.alpha_twist = r.alpha_t;
            rod.bend_stiffness = r.stiffness().bend();
            rod.twist_stiffness = r.stiffness().twist();
            rod.twist_mode = r.twist;
            rod.length_correction = r.length_correction;
            world.constraints.push(Constraint::Rod(rod));
        }
        Ok(lab)
    }
}

/// The scene's method settings (a variant's too, with `prefix` its path): time step, counts,
/// damping, contact options.
fn check_settings(d: &SceneDef, prefix: &[Seg]) -> Result<(), (Vec<Seg>, String)> {
    let key = |k: &str| {
        let mut path = prefix.to_vec();
        path.push(Seg::Key(k.into()));
        path
    };
    if !(d.dt > 0.0 && d.dt.is_finite()) {
        return Err((
            key("dt"),
            format!("must be a positive number of seconds, got {}", d.dt),
        ));
    }
    if d.iterations == 0 {
        return Err((key("iterations"), "must be at least 1".into()));
    }
    if d.substeps == 0 {
        return Err((key("substeps"), "must be at least 1".into()));
    }
    if d.frames == 0 {
        return Err((key("frames"), "must be at least 1".into()));
    }
    if let Some(n) = d.ci_frames.filter(|&n| n == 0 || n > d.frames) {
        return Err((
            key("ci_frames"),
            format!("must lie in [1, frames = {}], got {n}", d.frames),
        ));
    }
    if !(d.max_speed > 0.0) {
        return Err((key("max_speed"), "must be positive".into()));
    }
    if d.damping.iter().any(|c| !(*c >= 0.0 && c.is_finite())) {
        return Err((
            key("damping"),
            format!("rates must be non-negative, got {:?}", d.damping),
        ));
    }
    if !(d.joint_damping >= 0.0 && d.joint_damping.is_finite()) {
        return Err((
            key("joint_damping"),
            format!("must be 0 or more (N m s/rad), got {}", d.joint_damping),
        ));
    }
    for (name, value) in [
        ("max_separation", d.max_separation),
        ("max_penetration", d.max_penetration),
    ] {
        if !(value > 0.0) {
            return Err((
                key(name),
                format!("must be a positive distance in m (or inf), got {value}"),
            ));
        }
    }
    if !(d.max_angular_speed > 0.0) {
        return Err((key("max_angular_speed"), "must be positive".into()));
    }
    if !(d.contact_push_speed > 0.0) {
        return Err((
            key("contact_push_speed"),
            format!(
                "must be a positive speed in m/s (or inf), got {}",
                d.contact_push_speed
            ),
        ));
    }
    if !(0.0..=1.0).contains(&d.contact_warm_start) {
        return Err((
            key("contact_warm_start"),
            format!(
                "must be a fraction from 0 to 1, got {}",
                d.contact_warm_start
            ),
        ));
    }
    if !(d.contact_hertz >= 0.0 && d.contact_hertz.is_finite()) {
        return Err((
            key("contact_hertz"),
            format!(
                "must be a frequency of 0 Hz or more, got {}",
                d.contact_hertz
            ),
        ));
    }
    if !(d.contact_damping_ratio >= 0.0 && d.contact_damping_ratio.is_finite()) {
        return Err((
            key("contact_damping_ratio"),
            format!("must be 0 or more, got {}", d.contact_damping_ratio),
        ));
    }
    if !(d.contact_stacking >= 0.0 && d.contact_stacking <= MAX_CONTACT_STACKING) {
        return Err((
            key("contact_stacking"),
            format!(
                "must be a rate from 0 to {MAX_CONTACT_STACKING} per metre, got {}",
                d.contact_stacking
            ),
        ));
    }
    bounds::check_settings(d, prefix)
}

/// The largest stacking rate a scene may ask for (1/m): at 1000 a body 1 cm lower already
/// counts 22 000 times heavier.
pub const MAX_CONTACT_STACKING: f32 = 1000.0;

fn check_name(name: &str, seen: &[&str]) -> Result<(), String> {
    if name.is_empty() || name.contains('/') {
        return Err(format!(
            "\"{name}\" is not a valid name (non-empty, no '/')"
        ));
    }
    if seen.contains(&name) {
        return Err(format!("duplicate name \"{name}\""));
    }
    Ok(())
}

/// The two ends of a joint or rod: known bodies, and not the same one.
fn check_pair(a: &str, b: &str, body_names: &[&str]) -> Result<(), (&'static str, String)> {
    for (field, name) in [("a", a), ("b", b)] {
        if !body_names.contains(&name) {
            let known = body_names.join(", ");
            return Err((
                field,
                format!("unknown body \"{name}\", expected one of: {known}"),
            ));
        }
    }
    if a == b {
        return Err(("b", "needs two different bodies".into()));
    }
    Ok(())
}

fn check_relaxation(value: Option<f32>) -> Result<(), String> {
    match value {
        Some(v) if !(0.0..=1.0).contains(&v) => {
            Err(format!("relaxation must lie in [0, 1], got {v}"))
        }
        _ => Ok(()),
    }
}

fn check_body(b: &BodyDef) -> Result<(), (&'static str, String)> {
    let positive = |field: &'static str, v: Option<f32>| match v {
        None => Err((
            field,
            format!("required for a {:?} shape", b.shape).to_lowercase(),
        )),
        Some(x) if !(x > 0.0) => Err((field, format!("must be positive, got {x}"))),
        Some(_) => Ok(()),
    };
    match b.shape {
        ShapeKind::Sphere => positive("radius", b.radius)?,
        ShapeKind::Capsule => {
            positive("radius", b.radius)?;
            positive("half_height", b.half_height)?;
        }
        ShapeKind::Box => match b.half_extents {
            None => return Err(("half_extents", "required for a box shape".into())),
            Some(h) if h.iter().any(|&x| !(x > 0.0)) => {
                return Err(("half_extents", format!("must be positive, got {h:?}")))
            }
            Some(_) => {}
        },
        ShapeKind::Plane if b.kind != KindDef::Fixed => {
            return Err(("kind", "a plane (half-space) must be fixed".into()))
        }
        ShapeKind::Plane => {}
    }
    if matches!(b.restitution, Some(e) if !(0.0..=1.0).contains(&e)) {
        return Err(("restitution", "must lie in [0, 1]".into()));
    }
    for (field, value) in [
        ("static_friction", b.static_friction),
        ("dynamic_friction", b.dynamic_friction),
    ] {
        if matches!(value, Some(mu) if !(mu >= 0.0 && mu.is_finite())) {
            return Err((field, "must be a non-negative number".into()));
        }
    }
    if b.kind == KindDef::Dynamic {
        match (b.mass, b.density) {
            (Some(_), Some(_)) => return Err(("density", "give mass or density, not both".into())),
            (None, None) => {
                return Err(("mass", "a dynamic body needs a mass or a density".into()))
            }
            (Some(m), None) if !(m > 0.0 && m.is_finite()) => {
                return Err((
                    "mass",
                    format!("a dynamic body needs a positive mass, got {m}"),
                ))
            }
            (None, Some(rho)) if !(rho > 0.0 && rho.is_finite()) => {
                return Err((
                    "density",
                    format!("a dynamic body needs a positive density, got {rho}"),
                ))
            }
            _ => {}
        }
    }
    Ok(())
}

fn build_body(b: &BodyDef) -> Body {
    let shape = match b.shape {
        ShapeKind::Sphere => Shape::Sphere {
            radius: b.radius.unwrap(),
        },
        ShapeKind::Capsule => Shape::Capsule {
            half_height: b.half_height.unwrap(),
            radius: b.radius.unwrap(),
            axis: b.axis.unwrap_or(Axis::Y),
        },
        ShapeKind::Box => Shape::Cuboid {
            half_extents: Vec3::from(b.half_extents.unwrap()),
        },
        ShapeKind::Plane => Shape::HalfSpace,
    };
    let kind = match b.kind {
        KindDef::Dynamic => BodyKind::Dynamic,
        KindDef::Fixed => BodyKind::Fixed,
        KindDef::Kinematic => BodyKind::Kinematic,
    };
    let mass = b
        .mass
        .unwrap_or_else(|| b.density.unwrap_or(1000.0) * shape.volume());
    let mut body = Body::new(&b.name, kind, shape, mass)
        .with_pose(Vec3::from(b.position), quat_from_degrees(b.rotation));
    if kind != BodyKind::Fixed {
        body.linear_velocity = Vec3::from(b.velocity);
        body.angular_velocity = Vec3::from(b.angular_velocity);
    }
    body.static_friction = b.static_friction.unwrap_or(body.static_friction);
    body.dynamic_friction = b.dynamic_friction.unwrap_or(body.dynamic_friction);
    body.restitution = b.restitution.unwrap_or(body.restitution);
    body.collision_group = b.collision_group.unwrap_or(body.collision_group);
    body.collision_mask = b.collision_mask.unwrap_or(body.collision_mask);
    body
}

/// serde's "unknown variant `x`, expected one of `a`, `b`" reads better as
/// `unknown value "x", expected one of a, b`.
fn tidy_serde_message(message: &str) -> String {
    let message = message.trim().replace("unknown variant", "unknown value");
    let mut out = String::with_capacity(message.len());
    for (i, part) in message.split('`').enumerate() {
        if i == 1 || i == 2 {
            out.push('"'); // quotes around the user's value; the choices stay bare
        }
        out.push_str(part);
    }
    out
}
