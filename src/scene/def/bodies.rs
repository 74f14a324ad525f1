//! The `[[body]]`, `[[tile]]` and `[[joint]]` definitions: rigid bodies, grids of fixed
//! bodies, and ball-and-socket joints between named bodies.

use serde::Deserialize;

use crate::constraint::JointFlavour;
use crate::shape::Axis;

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
