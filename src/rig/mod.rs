//! Ragdoll rigs, clips and skeletons from Jolt Physics' text object streams (`.tof`, read by
//! [`tof`]): [`Rig`] holds the parts, their shapes and mass properties ([`mass`]), the joints
//! and the pairs that never collide; [`Animation`] the clips; [`skeleton`] the animation skeleton.
//!
//! What the files mean, from Jolt's sources (`Ragdoll.cpp`, `BodyCreationSettings`,
//! `SwingTwistConstraint.cpp`, `SkeletonPose.cpp`):
//! - A part is a `BodyCreationSettings`: its position and rotation place the origin and axes
//!   of its shape (not its centre of mass), and they are its skeleton joint's world matrix in
//!   the pose the rig was authored in. `Ragdoll::SetPose` puts every body at its joint's world
//!   matrix, and `SkeletonPose::CalculateJointMatrices` makes a joint's world matrix its
//!   parent's times its local transform (the root's local transform is its world one).
//! - A part's shape is a compound of sub-shapes, each placed in the part's frame.
//! - Part `i`'s `mToParent` joins its parent (body 1) to it (body 2), its frames in world
//!   space (Jolt's default; the Human rig's file has no `mSpace`), where in the rig's pose the
//!   two anchors coincide; Jolt's other space is each body's frame at its centre of mass.

pub mod animation;
pub mod mass;
pub mod skeleton;
#[cfg(test)]
mod tests;
pub mod tof;

pub use animation::{AnimatedJoint, Animation, Keyframe};
pub use mass::MassProperties;

use crate::math::{Iso, Quat, Vec3};
use std::path::Path;
use tof::{Document, View};

/// A ragdoll: parts in skeleton order (parents first), joints and collision filter.
#[derive(Clone, Debug, PartialEq)]
pub struct Rig {
    /// The file's stem, e.g. `Human`.
    pub name: String,
    /// One body per skeleton joint, parents before children.
    pub parts: Vec<Part>,
    /// The joints, in part order; each joins a part's parent (body 1) to the part (body 2).
    pub constraints: Vec<SwingTwist>,
    /// Pairs `(a, b)`, `a < b`, of parts that never collide with each other (Jolt's
    /// `GroupFilterTable`, with all parts in one collision group as `CreateRagdoll` puts them).
    pub no_collide: Vec<(usize, usize)>,
}

/// Jolt's `EMotionType`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionType {
    /// Does not move.
    Static,
    /// Moved by velocities only, not by forces.
    Kinematic,
    /// Moved by forces.
    Dynamic,
}

/// One body of the rig.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// The skeleton joint the part follows.
    pub joint_name: String,
    /// The parent part's index.
    pub parent: Option<usize>,
    /// World position of the body's (shape's) origin in the rig's pose (m).
    pub position: Vec3,
    /// World rotation of the body in the rig's pose.
    pub rotation: Quat,
    /// The shapes making up the body, placed in its frame.
    pub shapes: Vec<SubShape>,
    /// Mass, centre of mass and inertia about it in the body frame, from the true shapes.
    pub mass: MassProperties,
    /// How the body moves.
    pub motion_type: MotionType,
    /// Friction coefficient.
    pub friction: f32,
    /// Restitution coefficient.
    pub restitution: f32,
    /// Linear damping (1/s): `dv/dt = -c v`.
    pub linear_damping: f32,
    /// Angular damping (1/s).
    pub angular_damping: f32,
    /// Largest linear speed (m/s).
    pub max_linear_velocity: f32,
    /// Largest angular speed (rad/s).
    pub max_angular_velocity: f32,
    /// Factor on gravity.
    pub gravity_factor: f32,
    /// Sub-group in the collision filter table.
    pub collision_sub_group: u32,
}

/// A shape placed in a part's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubShape {
    /// The shape, in its own frame.
    pub shape: PartShape,
    /// Position of the shape's origin in the body frame (m).
    pub position: Vec3,
    /// Rotation of the shape in the body frame.
    pub rotation: Quat,
    /// Density (kg/m^3).
    pub density: f32,
}

/// A convex shape, in its own frame, axis along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PartShape {
    /// Two hemispheres of radius `radius` centred at `y = ±half_height` and the cylinder
    /// between; the radius is also Jolt's convex radius.
    Capsule {
        /// Half the distance between the sphere centres (m).
        half_height: f32,
        /// Radius (m).
        radius: f32,
    },
    /// The convex hull of a sphere of `top_radius` at `y = +half_height` and one of
    /// `bottom_radius` at `y = -half_height`; Jolt's convex radius is the smaller radius.
    TaperedCapsule {
        /// Half the distance between the sphere centres (m).
        half_height: f32,
        /// Radius of the sphere at `+half_height` (m).
        top_radius: f32,
        /// Radius of the sphere at `-half_height` (m).
        bottom_radius: f32,
    },
    /// A box; Jolt rounds its edges by `convex_radius` for collision only, its mass is the
    /// full box's.
    Box {
        /// Half the size along each axis (m).
        half_extent: Vec3,
        /// Radius by which Jolt rounds the edges (m).
        convex_radius: f32,
    },
}

/// Jolt's `EConstraintSpace`: the space a constraint's frames are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConstraintSpace {
    /// Each body's frame with its origin at the body's centre of mass.
    LocalToBodyCom,
    /// World space, with the bodies at the rig's pose.
    World,
}

/// A swing-twist joint (Jolt's `SwingTwistConstraintSettings`). Each body's constraint frame
/// has x along the twist axis, z along the plane axis and y = z × x (the normal axis). Swing
/// about y (in the plane of the twist and plane axes) is limited to `±plane_half_cone_angle`,
/// swing about z to `±normal_half_cone_angle`, twist about x to
/// `[twist_min_angle, twist_max_angle]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingTwist {
    /// The parent part's index.
    pub body1: usize,
    /// The child part's index.
    pub body2: usize,
    /// The space the positions and axes are in.
    pub space: ConstraintSpace,
    /// Anchor on body 1 (m).
    pub position1: Vec3,
    /// Anchor on body 2 (m).
    pub position2: Vec3,
    /// Twist axis of body 1's frame (unit).
    pub twist_axis1: Vec3,
    /// Twist axis of body 2's frame (unit).
    pub twist_axis2: Vec3,
    /// Plane axis of body 1's frame (unit, normal to the twist axis).
    pub plane_axis1: Vec3,
    /// Plane axis of body 2's frame (unit, normal to the twist axis).
    pub plane_axis2: Vec3,
    /// Swing limit about the plane axis (rad).
    pub normal_half_cone_angle: f32,
    /// Swing limit about the normal axis (rad).
    pub plane_half_cone_angle: f32,
    /// Lower twist limit (rad).
    pub twist_min_angle: f32,
    /// Upper twist limit (rad).
    pub twist_max_angle: f32,
    /// Friction torque when no motor drives the joint (N m).
    pub max_friction_torque: f32,
    /// Motor on the swing.
    pub swing_motor: Motor,
    /// Motor on the twist.
    pub twist_motor: Motor,
}

/// Jolt's `MotorSettings` (spring in frequency-and-damping form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motor {
    /// Oscillation frequency of the position drive (Hz).
    pub frequency: f32,
    /// Damping ratio (1 = critical).
    pub damping: f32,
    /// Smallest force a linear motor applies (N).
    pub min_force_limit: f32,
    /// Largest force a linear motor applies (N).
    pub max_force_limit: f32,
    /// Smallest torque an angular motor applies (N m).
    pub min_torque_limit: f32,
    /// Largest torque an angular motor applies (N m).
    pub max_torque_limit: f32,
}

/// A file's text and name (for error messages).
fn read(path: &Path) -> Result<(String, String), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let name = path.file_name().map(|f| f.to_string_lossy().into_owned());
    Ok((text, name.unwrap_or_else(|| path.display().to_string())))
}

/// A file name without its extension.
fn stem(file: &str) -> String {
    file.rsplit_once('.').map_or(file, |(s, _)| s).to_string()
}

/// Field `name` read by `get`, or `default` when the type does not declare it: older files
/// lack the fields newer Jolt versions added, and Jolt keeps its defaults for them.
fn optional<'a, T>(v: &View<'a>, name: &str, default: T, get: Getter<'a, T>) -> Result<T, String> {
    match v.has(name) {
        true => get(v, name),
        false => Ok(default),
    }
}

/// A typed field getter of [`View`].
type Getter<'a, T> = fn(&View<'a>, &str) -> Result<T, String>;

/// A finite float field in `range`.
fn float_in(v: &View, name: &str, range: std::ops::RangeInclusive<f32>) -> Result<f32, String> {
    let x = v.float(name)?;
    if !range.contains(&x) {
        return Err(v.error(name, &format!("{x} is outside {range:?}")));
    }
    Ok(x)
}

/// A float field that must be positive.
fn positive(v: &View, name: &str) -> Result<f32, String> {
    float_in(v, name, f32::MIN_POSITIVE..=f32::MAX)
}

/// A unit `vec3` field (normalized; within 1% of unit length).
fn unit(v: &View, name: &str) -> Result<Vec3, String> {
    let x = v.vec3(name)?;
    if !((x.length() - 1.0).abs() < 0.01) {
        return Err(v.error(name, "expected a unit vector"));
    }
    Ok(x.normalize())
}

/// A reference field that must not be null.
fn required<'a>(v: &View<'a>, name: &str) -> Result<View<'a>, String> {
    v.reference(name)?.ok_or_else(|| v.error(name, "is null"))
}

/// An error about the object `v` as a whole.
fn object_error(v: &View, msg: &str) -> String {
    format!("{}:{}: {}: {msg}", v.doc.file, v.obj.line, v.obj.label)
}

impl Rig {
    /// Reads a rig from a `.tof` file.
    pub fn load(path: impl AsRef<Path>) -> Result<Rig, String> {
        let (text, file) = read(path.as_ref())?;
        Rig::from_str(&text, &file)
    }

    /// Reads a rig from the text of a `.tof` file called `file` (for error messages; its stem
    /// names the rig).
    pub fn from_str(text: &str, file: &str) -> Result<Rig, String> {
        let doc = Document::parse(text, file)?;
        let root = doc.root()?;
        if root.obj.type_name != "RagdollSettings" {
            return Err(object_error(&root, "expected RagdollSettings"));
        }
        let joints = required(&root, "mSkeleton")?.inlines("mJoints")?;
        let part_views = root.inlines("mParts")?;
        if joints.len() != part_views.len() {
            let msg = format!("{} parts, {} joints", part_views.len(), joints.len());
            return Err(root.error("mParts", &msg));
        }
        let mut parts: Vec<Part> = Vec::with_capacity(joints.len());
        let (mut constraints, mut groups) = (Vec::new(), Vec::new());
        for (i, (joint, v)) in joints.iter().zip(&part_views).enumerate() {
            let (name, parent_name) = (joint.string("mName")?, joint.string("mParentName")?);
            let parent = parts.iter().position(|p| p.joint_name == parent_name);
            if parent.is_none() != parent_name.is_empty() {
                return Err(joint.error("mParentName", "names no earlier joint"));
            }
            let (part, filter) = read_part(v, name, parent)?;
            groups.push((filter, part.collision_sub_group));
            parts.push(part);
            if let Some(c) = v.reference("mToParent")? {
                let parent =
                    parent.ok_or_else(|| v.error("mToParent", "the root has no parent"))?;
                constraints.push(read_swing_twist(&c, parent, i)?);
            }
        }
        Ok(Rig {
            name: stem(file),
            parts,
            constraints,
            no_collide: no_collide(&groups)?,
        })
    }

    /// The index of the part following joint `name`.
    pub fn part_index(&self, name: &str) -> Option<usize> {
        self.parts.iter().position(|p| p.joint_name == name)
    }

    /// The total mass (kg).
    pub fn total_mass(&self) -> f32 {
        self.parts.iter().map(|p| p.mass.mass).sum()
    }
}

/// A part and its group filter (the `GroupFilterTable` view, if any).
fn read_part<'a>(
    v: &View<'a>,
    name: &str,
    parent: Option<usize>,
) -> Result<(Part, Option<View<'a>>), String> {
    let mut shapes = Vec::new();
    collect_shapes(&required(v, "mShape")?, Iso::IDENTITY, 0, &mut shapes)?;
    let mut mass = mass::of_shapes(&shapes);
    let given = v.inline("mMassPropertiesOverride")?;
    let multiplier = optional(v, "mInertiaMultiplier", 1.0, positive)?;
    match v.uint("mOverrideMassProperties")? {
        0 => mass.inertia *= multiplier,
        1 => {
            mass = mass.scaled_to_mass(positive(&given, "mMass")?);
            mass.inertia *= multiplier;
        }
        2 => {
            let m = given.mat44("mInertia")?;
            let column = |i: usize| Vec3::new(m[4 * i], m[4 * i + 1], m[4 * i + 2]);
            mass.inertia = crate::math::Mat3::from_cols(column(0), column(1), column(2));
            mass.mass = positive(&given, "mMass")?;
        }
        x => return Err(v.error("mOverrideMassProperties", &format!("unknown mode {x}"))),
    }
    let motion_type = match v.uint("mMotionType")? {
        0 => MotionType::Static,
        1 => MotionType::Kinematic,
        2 => MotionType::Dynamic,
        x => return Err(v.error("mMotionType", &format!("unknown motion type {x}"))),
    };
    let group = v.inline("mCollisionGroup")?;
    let f = |name: &str| float_in(v, name, 0.0..=f32::MAX);
    let part = Part {
        joint_name: name.to_string(),
        parent,
        position: v.vec3("mPosition")?,
        rotation: v.quat("mRotation")?,
        shapes,
        mass,
        motion_type,
        friction: f("mFriction")?,
        restitution: f("mRestitution")?,
        linear_damping: f("mLinearDamping")?,
        angular_damping: f("mAngularDamping")?,
        max_linear_velocity: f("mMaxLinearVelocity")?,
        max_angular_velocity: f("mMaxAngularVelocity")?,
        gravity_factor: v.float("mGravityFactor")?,
        collision_sub_group: group.uint("mSubGroupID")?,
    };
    Ok((part, group.reference("mGroupFilter")?))
}

/// Appends the leaf shapes under `v`, placed by `at` in the part's frame.
fn collect_shapes(v: &View, at: Iso, depth: usize, out: &mut Vec<SubShape>) -> Result<(), String> {
    let density = || positive(v, "mDensity");
    let shape = match v.obj.type_name.as_str() {
        "StaticCompoundShapeSettings" | "MutableCompoundShapeSettings" if depth < 4 => {
            for sub in v.inlines("mSubShapes")? {
                let local = Iso::new(sub.vec3("mPosition")?, sub.quat("mRotation")?);
                collect_shapes(&required(&sub, "mShape")?, at * local, depth + 1, out)?;
            }
            return Ok(());
        }
        "CapsuleShapeSettings" => PartShape::Capsule {
            half_height: positive(v, "mHalfHeightOfCylinder")?,
            radius: positive(v, "mRadius")?,
        },
        "TaperedCapsuleShapeSettings" => {
            let half_height = positive(v, "mHalfHeightOfTaperedCylinder")?;
            let (top_radius, bottom_radius) =
                (positive(v, "mTopRadius")?, positive(v, "mBottomRadius")?);
            if top_radius.max(bottom_radius) >= 2.0 * half_height + top_radius.min(bottom_radius) {
                return Err(object_error(v, "one sphere holds the other"));
            }
            PartShape::TaperedCapsule {
                half_height,
                top_radius,
                bottom_radius,
            }
        }
        "BoxShapeSettings" => {
            let half_extent = v.vec3("mHalfExtent")?;
            if !(half_extent.min_element() > 0.0 && half_extent.is_finite()) {
                return Err(v.error("mHalfExtent", "expected positive half extents"));
            }
            let convex_radius = float_in(v, "mConvexRadius", 0.0..=half_extent.min_element())?;
            PartShape::Box {
                half_extent,
                convex_radius,
            }
        }
        t => return Err(object_error(v, &format!("unsupported or too deep: {t}"))),
    };
    out.push(SubShape {
        shape,
        position: at.translation,
        rotation: at.rotation,
        density: density()?,
    });
    Ok(())
}

/// The joint `v` from part `body1` (the parent) to part `body2`.
fn read_swing_twist(v: &View, body1: usize, body2: usize) -> Result<SwingTwist, String> {
    use std::f32::consts::PI;
    if v.obj.type_name != "SwingTwistConstraintSettings" {
        return Err(object_error(v, "unsupported constraint type"));
    }
    let space = match optional(v, "mSpace", 1, View::uint)? {
        0 => ConstraintSpace::LocalToBodyCom,
        1 => ConstraintSpace::World,
        x => return Err(v.error("mSpace", &format!("unknown constraint space {x}"))),
    };
    if optional(v, "mSwingType", 0, View::uint)? != 0 {
        return Err(v.error("mSwingType", "only the cone swing type is supported"));
    }
    let twist_min_angle = float_in(v, "mTwistMinAngle", -PI..=PI)?;
    Ok(SwingTwist {
        body1,
        body2,
        space,
        position1: v.vec3("mPosition1")?,
        position2: v.vec3("mPosition2")?,
        twist_axis1: unit(v, "mTwistAxis1")?,
        twist_axis2: unit(v, "mTwistAxis2")?,
        plane_axis1: unit(v, "mPlaneAxis1")?,
        plane_axis2: unit(v, "mPlaneAxis2")?,
        normal_half_cone_angle: float_in(v, "mNormalHalfConeAngle", 0.0..=PI)?,
        plane_half_cone_angle: float_in(v, "mPlaneHalfConeAngle", 0.0..=PI)?,
        twist_min_angle,
        twist_max_angle: float_in(v, "mTwistMaxAngle", twist_min_angle..=PI)?,
        max_friction_torque: float_in(v, "mMaxFrictionTorque", 0.0..=f32::MAX)?,
        swing_motor: read_motor(&v.inline("mSwingMotorSettings")?)?,
        twist_motor: read_motor(&v.inline("mTwistMotorSettings")?)?,
    })
}

fn read_motor(v: &View) -> Result<Motor, String> {
    if optional(v, "mSpringMode", 0, View::uint)? != 0 {
        return Err(v.error("mSpringMode", "only frequency and damping are supported"));
    }
    Ok(Motor {
        frequency: float_in(v, "mFrequency", 0.0..=f32::MAX)?,
        damping: float_in(v, "mDamping", 0.0..=f32::MAX)?,
        min_force_limit: v.float("mMinForceLimit")?,
        max_force_limit: v.float("mMaxForceLimit")?,
        min_torque_limit: v.float("mMinTorqueLimit")?,
        max_torque_limit: v.float("mMaxTorqueLimit")?,
    })
}

/// The pairs of parts that do not collide, as Jolt's `CollisionGroup::CanCollide` and
/// `GroupFilterTable::CanCollide` decide with all parts in one group: the first non-null filter
/// decides; different filters or the same sub-group do not collide, else the table's bit says.
fn no_collide(groups: &[(Option<View>, u32)]) -> Result<Vec<(usize, usize)>, String> {
    let mut pairs = Vec::new();
    for (a, (fa, sa)) in groups.iter().enumerate() {
        for (b, (fb, sb)) in groups.iter().enumerate().skip(a + 1) {
            let Some(filter) = fa.or(*fb) else { continue };
            let same = |f: &Option<View>| f.is_some_and(|f| std::ptr::eq(f.obj, filter.obj));
            if !(same(fa) && same(fb)) || sa == sb || !table_allows(&filter, *sa, *sb)? {
                pairs.push((a, b));
            }
        }
    }
    Ok(pairs)
}

/// Whether a `GroupFilterTable` lets sub-groups `s1 != s2` collide: the table stores the
/// lower triangle, bit `s2 (s2 - 1) / 2 + s1` for `s1 < s2`, least significant bit first.
fn table_allows(table: &View, s1: u32, s2: u32) -> Result<bool, String> {
    if table.obj.type_name != "GroupFilterTable" {
        return Err(object_error(table, "unsupported group filter type"));
    }
    let (lo, hi) = (u64::from(s1.min(s2)), u64::from(s1.max(s2)));
    if hi >= u64::from(table.uint("mNumSubGroups")?) {
        return Err(table.error("mNumSubGroups", &format!("sub-group {hi} is out of range")));
    }
    let bit = hi * (hi - 1) / 2 + lo;
    let bytes = table.uints("mTable")?;
    let byte = usize::try_from(bit / 8).ok().and_then(|i| bytes.get(i));
    let byte = byte.ok_or_else(|| table.error("mTable", "too short for its sub-groups"))?;
    Ok(byte & (1 << (bit % 8)) != 0)
}
